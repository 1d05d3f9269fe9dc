#pragma once
/// \file bpt_reader.h
/// Reader of the Bézier patch text format of the Utah teapot (`.bpt`): first line the patch
/// count; per patch a line "n m" (degrees in u and v) and then (n+1)(m+1) lines "x y z", row-major
/// with row i = u index (point (i, j) is row i * (m + 1) + j).
#include <filesystem>
#include <string>

#include "nurbs/model.h"

namespace nurbs::io {

/// Reads a .bpt file into one body ("patches") of untrimmed faces, one polynomial Bézier
/// surface each (clamped knots 0^(n+1) 1^(n+1)); face_id = patch index from 0. Throws ReadError
/// "FILE: line L: patch P: problem" on missing or extra numbers, non-finite values, degrees
/// outside 1..32, a wrong patch count or trailing data.
Model read_bpt(const std::filesystem::path& path);

/// Same as read_bpt on text already in memory; `name` is used in messages and Model::source.
Model read_bpt_text(const std::string& text, const std::string& name);

}  // namespace nurbs::io
