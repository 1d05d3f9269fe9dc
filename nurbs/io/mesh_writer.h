#pragma once
/// \file mesh_writer.h
/// Triangle mesh export (the tessellation's output, the thickness map): Wavefront OBJ (text, with
/// normals and (u, v) when present, one group per face), PLY (binary little endian, with normals,
/// per-vertex colours when present and a per-face "face_id") and STL (binary, facet normals).
#include <filesystem>
#include <ostream>

#include "nurbs/triangle_mesh.h"

namespace nurbs::io {

enum class MeshFormat { Obj, Ply, Stl };

/// The format named by a file's extension (.obj, .ply, .stl, any case); throws std::invalid_argument
/// naming the file otherwise.
[[nodiscard]] MeshFormat mesh_format_of(const std::filesystem::path& path);

void write_mesh(std::ostream& out, const TriangleMesh& mesh, MeshFormat format);

/// write_mesh into a file in the format of its extension; throws std::runtime_error when it cannot
/// be written.
void write_mesh_file(const std::filesystem::path& path, const TriangleMesh& mesh);

}  // namespace nurbs::io
