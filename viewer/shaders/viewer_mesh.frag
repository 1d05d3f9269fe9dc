// Shading of viewer_mesh.vert's triangles. u_style: 0 lit base colour, 1 lit colour ramp of the
// scalar over u_range (thickness mode; below u_threshold striped white), 2 flat u_color (edges).
// The picked face (u_picked_face, -1 = none) is tinted. Light from the eye, two-sided.
in vec3 v_normal;
in float v_face;
in float v_scalar;

uniform vec3 u_color;
uniform int u_style;
uniform float u_picked_face;
uniform vec2 u_range;
uniform float u_threshold;

out vec4 o_color;

uniform vec3 u_ramp[4];  // the stops of nurbs::ray::kThicknessRamp, thin to thick

// Thin (0) to thick (1), linear between the stops, as nurbs::ray::thickness_ramp (the legend's too).
vec3 ramp(float t) {
  t = clamp(t, 0.0, 1.0);
  if (t < 1.0 / 3.0) return mix(u_ramp[0], u_ramp[1], 3.0 * t);
  if (t < 2.0 / 3.0) return mix(u_ramp[1], u_ramp[2], 3.0 * t - 1.0);
  return mix(u_ramp[2], u_ramp[3], 3.0 * t - 2.0);
}

void main() {
  if (u_style == 2) {
    o_color = vec4(u_color, 1.0);
    return;
  }
  vec3 base = u_color;
  if (u_style == 1) {
    if (v_scalar < 0.0) {
      base = vec3(0.55);  // no sample here
    } else {
      base = ramp((v_scalar - u_range.x) / max(u_range.y - u_range.x, 1e-30));
      bool stripe = mod(floor((gl_FragCoord.x + gl_FragCoord.y) / 6.0), 2.0) == 0.0;
      if (v_scalar < u_threshold && stripe) base = vec3(1.0);
    }
  }
  if (u_picked_face >= 0.0 && abs(v_face - u_picked_face) < 0.5) base = mix(base, vec3(1.0, 0.75, 0.2), 0.55);
  vec3 n = normalize(v_normal);
  float diffuse = abs(n.z);
  float specular = pow(diffuse, 40.0) * 0.25;
  o_color = vec4(base * (0.22 + 0.78 * diffuse) + vec3(specular), 1.0);
}
