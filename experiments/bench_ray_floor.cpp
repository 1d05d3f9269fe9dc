// Benchmark, not a test: what one Embree traversal of the certified mesh costs, the least any ray
// of the mesh method (queries/raycast/ray_caster.h, RayMethod::Mesh) spends before its exact hit.
// The faces tessellated as `nurbsgl raycast` does (guaranteed mode at the default mesh tolerance
// relative to the model size, queries::MeshDistance), then every ray of a file cast once, on every
// hardware thread, in the file's order (as the mesh pipeline peer casts them):
//  - plain: one traversal of the mesh's triangles (rtcIntersect1), the same work per ray as the
//    peer's query on its BRepMesh triangles;
//  - slabs: one traversal of the scene the mesh method casts into (the two shells, robust mode,
//    the tubes and balls around the faces' mesh boundaries), the method's first step.
// Prints one JSON object: the triangles, the median seconds of --repeat casts of each, the hits.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "nurbs/io/query_text.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "nurbs/parallel.h"
#include "nurbs/raycast/raycast_cpu.h"
#include "queries/distance/mesh_distance.h"
#include "queries/raycast/ray_caster.h"

namespace {

using Clock = std::chrono::steady_clock;

struct Cast {
  double seconds = 0.0;
  long long hits = 0;
};

/// The median of `repeat` casts of every ray through mesh.first_hit (t from 0 on, unbounded).
Cast cast_once(const queries::MeshDistance& mesh, const std::vector<nurbs::io::TextRay>& rays, int repeat) {
  std::vector<double> seconds;
  long long hits = 0;
  for (int r = 0; r < repeat; ++r) {
    std::atomic<long long> found{0};
    const auto t0 = Clock::now();
    nurbs::parallel_for(
        rays.size(), 0,
        [&](size_t k, int) {
          const queries::MeshRayHit h = mesh.first_hit(rays[k].origin, rays[k].direction, 0.0, 3.4e38);
          if (h.triangle >= 0 || h.boundary) found.fetch_add(1, std::memory_order_relaxed);
        },
        256);
    seconds.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    hits = found.load();
  }
  std::sort(seconds.begin(), seconds.end());
  return {seconds[seconds.size() / 2], hits};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"One Embree traversal of the certified mesh per ray: the floor of the mesh ray method"};
  std::string model_path, rays_path;
  int repeat = 3;
  double mesh_tolerance = queries::RayCasterOptions{}.mesh_tolerance;
  app.add_option("model", model_path, "IGES or STEP model")->required();
  app.add_option("--rays", rays_path, "ox oy oz dx dy dz per line")->required();
  app.add_option("--repeat", repeat, "casts of each scene; the median is printed")->check(CLI::Range(1, 100));
  app.add_option("--mesh-tolerance", mesh_tolerance, "the mesh's tolerance relative to the model size")
      ->check(CLI::Range(queries::RayCasterOptions::kMinMeshTolerance, queries::RayCasterOptions::kMaxMeshTolerance));
  CLI11_PARSE(app, argc, argv);
  try {
    const nurbs::Model model = nurbs::io::read_model(model_path);
    std::ifstream in(rays_path);
    if (!in) throw std::runtime_error(rays_path + ": cannot be read");
    std::stringstream text;
    text << in.rdbuf();
    const std::vector<nurbs::io::TextRay> rays = nurbs::io::parse_rays(text.str(), rays_path, 1e300);
    const std::vector<nurbs::TrimmedSurface> faces = nurbs::world_faces(model);
    const double eps = mesh_tolerance * nurbs::ray::scene_size(faces);
    const long long max_cells = nurbs::tess::TessellateOptions{}.max_cells;
    const queries::MeshDistance plain(faces, eps, 0, max_cells, false);
    const Cast p = cast_once(plain, rays, repeat);
    const queries::MeshDistance slabs(faces, eps, 0, max_cells, true);
    const Cast s = cast_once(slabs, rays, repeat);
    const nlohmann::json out = {{"rays", rays.size()},
                                {"mesh_tolerance", mesh_tolerance},
                                {"triangles", plain.triangles()},
                                {"plain_seconds", p.seconds},
                                {"plain_hits", p.hits},
                                {"slab_seconds", s.seconds},
                                {"slab_hits", s.hits},
                                {"repeat", repeat}};
    fmt::print("{}\n", out.dump(2));
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "bench_ray_floor: {}\n", e.what());
    return 2;
  }
}
