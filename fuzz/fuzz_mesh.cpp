// libFuzzer target: the mesh readers (nurbs/io/mesh_reader.h). The first byte picks the format (STL,
// OBJ, PLY by its value modulo 3), the rest is the file; the coordinate limit is that of a model of
// size 1 at the origin (1e15). ReadError is the expected answer to bad input; a mesh read must hold
// only finite positions within the limit and triangle corners inside its vertex list.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "nurbs/io/mesh_reader.h"
#include "nurbs/io/read_error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  constexpr nurbs::io::MeshFormat formats[] = {nurbs::io::MeshFormat::Stl, nurbs::io::MeshFormat::Obj,
                                               nurbs::io::MeshFormat::Ply};
  constexpr double limit = 1e15;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data) + 1, size - 1));
  try {
    const nurbs::TriangleMesh m = nurbs::io::read_mesh(in, formats[data[0] % 3], "fuzz", limit);
    for (const glm::dvec3& p : m.positions)
      if (!(std::abs(p.x) <= limit && std::abs(p.y) <= limit && std::abs(p.z) <= limit)) std::abort();
    for (const glm::ivec3& t : m.triangles)
      for (int c = 0; c < 3; ++c)
        if (t[c] < 0 || size_t(t[c]) >= m.positions.size()) std::abort();
  } catch (const nurbs::io::ReadError&) {
  }
  return 0;
}
