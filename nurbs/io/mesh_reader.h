#pragma once
/// \file mesh_reader.h
/// Triangle mesh import, so that meshes made by other programs (OpenCASCADE's BRepMesh, a CAD
/// exporter) can be measured against a model (`nurbsgl deviation`, tessellation/mesh_check.h):
/// STL (binary and ASCII), PLY (ASCII and binary little endian; vertex x y z, face vertex_indices)
/// and Wavefront OBJ (v and f lines). Polygons become triangle fans. Only positions and triangles
/// are read; normals, texture coordinates, colours and other properties are skipped.
#include <filesystem>
#include <istream>
#include <limits>
#include <string>

#include "nurbs/io/mesh_writer.h"
#include "nurbs/triangle_mesh.h"

namespace nurbs::io {

/// Reads a mesh in `format` from `in`; `name` is the file named in errors. Throws ReadError
/// (read_error.h) for malformed or truncated input: "NAME: line N: PROBLEM" for text,
/// "NAME: byte B: PROBLEM" for binary data (PROBLEM names the element, e.g. "face 3 of 12").
/// STL vertices (binary and ASCII) are welded where their coordinates are bit-identical (STL
/// repeats them per facet); the other formats keep their own vertex list. Faces with fewer than three corners
/// and indices outside the vertex list are errors; an empty mesh is not. Triangles that name one
/// vertex twice are left out; a polygon of more than 65536 corners is an error. A vertex coordinate
/// of magnitude above `coordinate_limit` (nurbs::coordinate_limit of the model the mesh is measured
/// against) is an error naming the vertex and the value. No count in the file is trusted before the
/// bytes behind it exist.
[[nodiscard]] TriangleMesh read_mesh(std::istream& in, MeshFormat format, const std::string& name,
                                     double coordinate_limit = std::numeric_limits<double>::infinity());

/// read_mesh of a file in the format of its extension (.stl, .ply, .obj, any case). Throws
/// ReadError for a file that cannot be read ("no such file", "is a directory, not a file",
/// input_file.h), an unknown extension or bad content.
[[nodiscard]] TriangleMesh read_mesh_file(const std::filesystem::path& path,
                                          double coordinate_limit = std::numeric_limits<double>::infinity());

}  // namespace nurbs::io
