// B-spline basis functions of The NURBS Book in float, knots read from an R32F texture laid out
// row-major with a power-of-two width (lib_layout.glsl, pow2_texel).
// MAX_DEGREE (a define) sizes the arrays; the degree p is a run-time value <= MAX_DEGREE.
#include "lib_layout.glsl"

float knot_at(sampler2D knots, int i) {
  return texelFetch(knots, pow2_texel(i, textureSize(knots, 0).x), 0).r;
}

// A2.1 FindSpan for n_ctrl control points: the span s in [p, n_ctrl - 1] with U[s] <= u < U[s+1];
// u is clamped to the domain [U[p], U[n_ctrl]], and at its end the last non-empty span is used.
int find_span(sampler2D knots, int n_ctrl, int p, float u) {
  float lo = knot_at(knots, p), hi = knot_at(knots, n_ctrl);
  u = clamp(u, lo, hi);
  if (u >= hi) {
    int s = n_ctrl - 1;
    while (s > p && knot_at(knots, s) >= knot_at(knots, s + 1)) --s;
    return s;
  }
  int low = p, high = n_ctrl, mid = (low + high) / 2;
  for (int guard = 0; guard < 40 && (u < knot_at(knots, mid) || u >= knot_at(knots, mid + 1)); ++guard) {
    if (u < knot_at(knots, mid)) high = mid; else low = mid;
    mid = (low + high) / 2;
  }
  return mid;
}

// A2.2 BasisFuns up to degree p, and the first derivatives (A2.3 for k = 1, from degree p - 1):
// N'_{i,p} = p N_{i,p-1} / (U[i+p] - U[i]) - p N_{i+1,p-1} / (U[i+p+1] - U[i+1]).
// 0/0 terms (repeated knots) are 0, as in the definition.
void basis_and_derivative(sampler2D knots, int span, float u, int p, out float N[MAX_DEGREE + 1],
                          out float dN[MAX_DEGREE + 1]) {
  float left[MAX_DEGREE + 1], right[MAX_DEGREE + 1], lower[MAX_DEGREE + 1];
  for (int i = 0; i <= MAX_DEGREE; ++i) { N[i] = 0.0; dN[i] = 0.0; lower[i] = 0.0; }
  N[0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    if (j == p) for (int r = 0; r < p; ++r) lower[r] = N[r];  // degree p - 1, for the derivative
    left[j] = u - knot_at(knots, span + 1 - j);
    right[j] = knot_at(knots, span + j) - u;
    float saved = 0.0;
    for (int r = 0; r < j; ++r) {
      float den = right[r + 1] + left[j - r];
      float temp = den != 0.0 ? N[r] / den : 0.0;
      N[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    N[j] = saved;
  }
  for (int r = 0; r <= p && p > 0; ++r) {
    float a = 0.0, b = 0.0;
    if (r >= 1) {
      float d = knot_at(knots, span + r) - knot_at(knots, span - p + r);
      a = d != 0.0 ? lower[r - 1] / d : 0.0;
    }
    if (r <= p - 1) {
      float d = knot_at(knots, span + r + 1) - knot_at(knots, span - p + r + 1);
      b = d != 0.0 ? lower[r] / d : 0.0;
    }
    dN[r] = float(p) * (a - b);
  }
}
