#pragma once
/// \file triangle_mesh.h
/// A triangle mesh of a model: what the tessellation produces, what the mesh writers (io/
/// mesh_writer.h) and the deviation check read. Plain data.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

namespace nurbs {

struct TriangleMesh {
  std::vector<glm::dvec3> positions;
  std::vector<glm::dvec3> normals;    ///< per vertex, unit; empty = none
  std::vector<glm::dvec2> uv;         ///< per vertex, in its face's parameter plane; empty = none
  std::vector<int> vertex_face;       ///< per vertex, index of its face in the model; empty = none
  std::vector<glm::ivec3> triangles;  ///< counter-clockwise seen from outside (the normal side)
  std::vector<int> triangle_face;     ///< per triangle, index of its face; empty = none
  std::vector<glm::dvec3> colors;     ///< per vertex RGB in [0, 1]; empty = none
  /// Per vertex scalar named `values_name` (e.g. the thickness the colours show; < 0 = none); empty = none.
  std::vector<double> values;
  std::string values_name;
};

}  // namespace nurbs
