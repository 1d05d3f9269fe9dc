// Leaf AABBs of an atlas of evaluated faces (Krishnamurthy et al. §3.1, §5.1): the box of the four
// samples of the cell with lower-left sample (x, y), mapped by u_motion (rigid motion of the object:
// boxes refitted from the untransformed samples), grown by the face's K_e + float budget. Cells
// that are not cells, or whose four samples are all trimmed away (§5.3), are empty: lo = +inf,
// hi = -inf; so are the cells of faces with a negative growth (left out by a first stage).
// Coordinates relative to u_origin.
// SAMPLE_UPPER (beyond the paper; needs TRIM_CROSSED): a third target holds a sample of the face for
// the pair pass's upper bound: the cell's first sample when all four are material and no trim edge
// crosses the cell (so the cell lies inside the trim), with the face's float budget in w; w = -1: none.
uniform sampler2D u_points;   // RGBA32F atlas of samples
uniform sampler2D u_slot_of;  // R32F: slot index or -1
uniform sampler2D u_mask;     // R8 trim mask
#ifdef TRIM_CROSSED
uniform sampler2D u_crossed;  // R8: 1 where a trim edge crosses the cell with lower-left sample (x, y)
#endif
uniform sampler2D u_grow;     // per slot: R = growth (K_e + float budget), G = float budget
uniform mat4 u_motion;        // model -> common frame, applied before u_origin is subtracted
uniform vec3 u_origin;
layout(location = 0) out vec4 o_lo;
layout(location = 1) out vec4 o_hi;
#ifdef SAMPLE_UPPER
layout(location = 2) out vec4 o_sample;
#endif

const float kInf = 1.0 / 0.0;

void main() {
  ivec2 g = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(u_points, 0);
  int slot = int(texelFetch(u_slot_of, g, 0).r);
  o_lo = vec4(kInf);
  o_hi = vec4(-kInf);
#ifdef SAMPLE_UPPER
  o_sample = vec4(0.0, 0.0, 0.0, -1.0);
#endif
  if (slot < 0 || g.x + 1 >= size.x || g.y + 1 >= size.y ||
      int(texelFetch(u_slot_of, g + ivec2(1, 1), 0).r) != slot ||
      int(texelFetch(u_slot_of, g + ivec2(1, 0), 0).r) != slot ||
      int(texelFetch(u_slot_of, g + ivec2(0, 1), 0).r) != slot)
    return;
  vec3 lo = vec3(kInf), hi = vec3(-kInf), first = vec3(0.0);
  float material = 0.0;
  for (int k = 0; k < 4; ++k) {
    ivec2 t = g + ivec2(k & 1, k >> 1);
    vec3 p = (u_motion * vec4(texelFetch(u_points, t, 0).xyz, 1.0)).xyz - u_origin;
    if (k == 0) first = p;
    lo = min(lo, p);
    hi = max(hi, p);
    material += texelFetch(u_mask, t, 0).r > 0.5 ? 1.0 : 0.0;
  }
  bool inside = material == 4.0;
#ifdef TRIM_CROSSED
  // Material may lie between the samples where a trim edge crosses the cell: not culled then.
  if (texelFetch(u_crossed, g, 0).r > 0.5) material = max(material, 0.5), inside = false;
#endif
  vec2 grow = texelFetch(u_grow, ivec2(slot, 0), 0).rg;
  if (material == 0.0 || grow.r < 0.0) return;  // all trimmed, or the face left out by a first stage
  o_lo = vec4(lo - vec3(grow.r), 0.0);
  o_hi = vec4(hi + vec3(grow.r), 0.0);
#ifdef SAMPLE_UPPER
  if (inside) o_sample = vec4(first, grow.g);
#endif
}
