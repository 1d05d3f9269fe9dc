#pragma once
/// \file query_text.h
/// The text formats of query inputs: a point (`--point`; files of points: point_cloud.h) and rays
/// ("ox oy oz dx dy dz" per line, `raycast --rays`). Numbers are separated by spaces, tabs or commas;
/// blank lines and lines starting with '#' are skipped. Every coordinate must be
/// finite and of magnitude at most `limit` (nurbs::coordinate_limit of the model queried).
#include <glm/vec3.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nurbs::io {

/// `text` as a point. Throws ReadError "NAME: '...' is not a point X,Y,Z of three finite numbers" or
/// "NAME: '...' lies beyond LIMIT, ..." (NAME: "--point", or "FILE: line N").
[[nodiscard]] glm::dvec3 parse_point(const std::string& text, const std::string& name, double limit);

/// `word` as one whole number (std::from_chars; a leading '+' allowed, not before a '-'), or none.
[[nodiscard]] std::optional<double> parse_number(std::string_view word);

/// "lies beyond LIMIT, ...": the end of the message for a coordinate beyond the limit.
[[nodiscard]] std::string beyond_limit(double limit);

/// A ray of a ray file: its origin and unit direction.
struct TextRay {
  glm::dvec3 origin{0.0}, direction{0.0, 0.0, 1.0};
};

/// Every line of `text` that is not blank or a '#' comment as a ray, its direction normalised.
/// Throws ReadError "NAME: line N: PROBLEM" for a word that is not a finite number, a count other
/// than 6, a direction without length or an origin beyond `limit`; "NAME: no rays in the file".
[[nodiscard]] std::vector<TextRay> parse_rays(std::string_view text, const std::string& name, double limit);

}  // namespace nurbs::io
