#pragma once
/// \file obj_writer.h
/// Wavefront OBJ export of sampled surface grids, for looking at geometry in other tools. The
/// grids are sampled by the caller (e.g. with nurbs/surface_eval.h), so this file knows no NURBS.
#include <filesystem>
#include <glm/vec3.hpp>
#include <ostream>
#include <string>
#include <vector>

namespace nurbs::io {

/// A grid of nu × nv points, row-major with u fastest: point(i, j) = points[j * nu + i].
struct SampledGrid {
  std::vector<glm::dvec3> points;
  int nu = 0;
  int nv = 0;
  std::string name;  ///< OBJ group name ("g"), optional
};

/// Writes each grid's vertices and (nu-1)(nv-1) faces, quads or two triangles per cell, counter-
/// clockwise in (u, v) so normals follow ∂u × ∂v. Indices continue across grids. Throws
/// std::invalid_argument when points.size() != nu * nv or a grid is smaller than 2 × 2.
void write_obj(std::ostream& out, const std::vector<SampledGrid>& grids, bool triangles = false);

/// write_obj into a file; throws std::runtime_error when it cannot be written.
void write_obj_file(const std::filesystem::path& path, const std::vector<SampledGrid>& grids, bool triangles = false);

}  // namespace nurbs::io
