// The library in a few lines: load a model, its size, and the distance of a point from its first
// face by the CPU twin of the paper's search (double precision, with the certified bound K).
#include <cstdio>

#include "nurbs/distance/certified_grid.h"
#include "nurbs/distance/filip_bound.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "nurbs/surface_eval.h"
#include "queries/distance/point_distance.h"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const nurbs::Model model = nurbs::io::read_model(argv[1]);  // throws nurbs::io::ReadError
  size_t faces = 0;
  for (const nurbs::Body& b : model.bodies) faces += b.faces.size();
  const nurbs::Surface& s = model.bodies.front().faces.front().surface;
  const nurbs::ParamGrid grid = nurbs::uniform_param_grid(nurbs::surface_domain_u(s), nurbs::surface_domain_v(s), 64, 64);
  const queries::PointDistance d = queries::point_distance_cpu(s, nurbs::filip_bound(s), grid, {3.0, 0.0, 1.5});
  std::printf("faces %zu size %.2f distance %.3f +- %.2g\n", faces, nurbs::model_size(model), d.distance, d.bound);
  return 0;
}
