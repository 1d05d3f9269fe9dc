// Pass 1 of the two-pass (tabulated) surface evaluation: the basis functions of one parameter
// direction at every grid sample, computed once instead of once per fragment of the grid.
// Target: samples x (degree + 1), texel (i, r) = (N_r(t_i), N'_r(t_i), span, 0) with t_i = i / n
// over the normalised domain, N_r the r-th non-zero basis function of the span.
#include "lib_bspline_basis.glsl"

uniform sampler2D u_knots;
uniform int u_count;    // control points in this direction
uniform int u_degree;
uniform int u_samples;  // n + 1
out vec4 o_basis;

void main() {
  ivec2 g = ivec2(gl_FragCoord.xy);
  float t = u_samples > 1 ? float(g.x) / float(u_samples - 1) : 0.0;
  int span = find_span(u_knots, u_count, u_degree, t);
  float N[MAX_DEGREE + 1], dN[MAX_DEGREE + 1];
  basis_and_derivative(u_knots, span, t, u_degree, N, dN);
  float n = 0.0, dn = 0.0;
  for (int r = 0; r <= MAX_DEGREE; ++r) {  // constant indices: select row g.y
    if (r == g.y) { n = N[r]; dn = dN[r]; }
  }
  o_basis = vec4(n, dn, float(span), 0.0);
}
