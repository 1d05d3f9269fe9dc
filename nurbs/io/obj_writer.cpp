#include "nurbs/io/obj_writer.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <fstream>
#include <stdexcept>

#include "nurbs/io/output_file.h"

namespace nurbs::io {

void write_obj(std::ostream& out, const std::vector<SampledGrid>& grids, bool triangles) {
  for (const SampledGrid& g : grids)
    if (g.nu < 2 || g.nv < 2 || g.points.size() != static_cast<size_t>(g.nu) * static_cast<size_t>(g.nv))
      throw std::invalid_argument(fmt::format("write_obj: grid '{}' has {} points for {} x {} (need >= 2 x 2)", g.name,
                                              g.points.size(), g.nu, g.nv));
  out << "# nurbsgl sampled grids\n";
  size_t base = 1;  // OBJ indices are 1-based and global
  for (const SampledGrid& g : grids) {
    if (!g.name.empty()) fmt::print(out, "g {}\n", g.name);
    for (const glm::dvec3& p : g.points) fmt::print(out, "v {} {} {}\n", p.x, p.y, p.z);
    for (int j = 0; j + 1 < g.nv; ++j) {
      for (int i = 0; i + 1 < g.nu; ++i) {
        const size_t a = base + static_cast<size_t>(j) * g.nu + i, b = a + 1, c = b + g.nu, d = a + g.nu;
        if (triangles)
          fmt::print(out, "f {} {} {}\nf {} {} {}\n", a, b, c, a, c, d);
        else
          fmt::print(out, "f {} {} {} {}\n", a, b, c, d);
      }
    }
    base += g.points.size();
  }
}

void write_obj_file(const std::filesystem::path& path, const std::vector<SampledGrid>& grids, bool triangles) {
  write_file(path, [&](std::ostream& out) { write_obj(out, grids, triangles); });
}

}  // namespace nurbs::io
