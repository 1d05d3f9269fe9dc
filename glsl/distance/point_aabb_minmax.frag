// Point-AABB distances of Krishnamurthy et al. §3.2, Eqs. (5)-(12), for every grid cell of an atlas
// of evaluated faces (queries/distance/face_atlas.h). The cell with lower-left sample (x, y) has the AABB of
// its four samples grown by its face's K (+ the float budget of the samples): R = the minimum
// distance from u_point to the box (0 inside), G = the maximum. Cells that are not cells (the last
// row or column of a slot, texels outside the slots) get +inf in both. Trim culling (§5.3): a cell
// whose four samples are all trimmed away is culled (+inf, +inf); a cell with some trimmed samples
// keeps its lower bound but gives no upper bound (G = +inf), since part of its box may hold no surface.
uniform sampler2D u_points;   // RGBA32F atlas of samples (x, y, z, w)
uniform sampler2D u_slot_of;  // R32F: slot index or -1
uniform sampler2D u_mask;     // R8 trim mask, 1 = material
#ifdef TRIM_CROSSED
uniform sampler2D u_crossed;  // R8: 1 where a trim edge crosses the cell with lower-left sample (x, y)
#endif
uniform sampler2D u_grow;     // per slot: R = K_e + float budget, model units (G: the budget)
uniform vec3 u_point;         // query point relative to u_origin
uniform vec3 u_origin;        // subtracted from the samples (keeps the differences small in float)
out vec4 o_minmax;

const float kInf = 1.0 / 0.0;

void main() {
  ivec2 g = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(u_points, 0);
  int slot = int(texelFetch(u_slot_of, g, 0).r);
  if (slot < 0 || g.x + 1 >= size.x || g.y + 1 >= size.y ||
      int(texelFetch(u_slot_of, g + ivec2(1, 1), 0).r) != slot ||
      int(texelFetch(u_slot_of, g + ivec2(1, 0), 0).r) != slot ||
      int(texelFetch(u_slot_of, g + ivec2(0, 1), 0).r) != slot) {
    o_minmax = vec4(kInf, kInf, 0.0, 0.0);
    return;
  }
  vec3 lo = vec3(kInf), hi = vec3(-kInf);
  float material = 0.0;
  for (int k = 0; k < 4; ++k) {
    ivec2 t = g + ivec2(k & 1, k >> 1);
    vec3 p = texelFetch(u_points, t, 0).xyz - u_origin;
    lo = min(lo, p);
    hi = max(hi, p);
    material += texelFetch(u_mask, t, 0).r > 0.5 ? 1.0 : 0.0;
  }
#ifdef TRIM_CROSSED
  // Material may lie between the samples where a trim edge crosses the cell: not culled then.
  if (texelFetch(u_crossed, g, 0).r > 0.5) material = max(material, 0.5);
#endif
  if (material == 0.0) {
    o_minmax = vec4(kInf, kInf, 0.0, 0.0);
    return;
  }
  float grow = texelFetch(u_grow, ivec2(slot, 0), 0).r;
  vec3 c = 0.5 * (lo + hi), B = 0.5 * (hi - lo) + vec3(grow);
  vec3 Dc = abs(u_point - c);
  float dmax = length(Dc + B);               // Eqs. (5)-(8)
  float dmin = length(max(Dc - B, vec3(0)));  // Eqs. (9)-(12)
  o_minmax = vec4(dmin, material == 4.0 ? dmax : kInf, 0.0, 0.0);
}
