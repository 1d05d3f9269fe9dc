#include "nurbs/distance/grid_report.h"

namespace nurbs {

FaceGridReport grid_report(const Surface& s, double tolerance, const GridLimits& limits, bool with_uniform) {
  FaceGridReport r;
  r.bound = filip_bound(s);
  const FilipBound& b = r.bound;
  r.grid = certified_grid(b, tolerance, limits);
  const double sampled = grid_k(sampled_bound(s, b), r.grid.grid, KNorm::Euclidean);
  r.bound_ratio = sampled > 0 ? r.grid.k_e / sampled : 1.0;
  if (with_uniform && tolerance > 0) {
    const GridChoice u = choose_grid(b, tolerance, 4095, KNorm::Euclidean);
    r.uniform_n = u.n;
    r.uniform_m = u.m;
    r.uniform_k_e = grid_k(b, uniform_param_grid(b.domain_u, b.domain_v, u.n, u.m), KNorm::Euclidean);
  }
  return r;
}

}  // namespace nurbs
