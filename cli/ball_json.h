#pragma once
/// \file ball_json.h
/// `thickness --ball`: the JSON of the rolling-ball thickness (queries::BallMap, made by the
/// library's thickness map, queries/raycast/thickness_map.h).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/common.h"
#include "nurbs/model.h"
#include "nurbs/raycast/ball_thickness.h"
#include "nurbs/raycast/thickness.h"
#include "queries/raycast/thickness_map.h"

namespace cli {

/// The JSON of a thickness summary: {"min", "max", "mean", "median"} (-1 when there is none).
inline nlohmann::json summary_json(const nurbs::ray::ThicknessSummary& s) {
  return {{"min", s.min}, {"max", s.max}, {"mean", s.mean}, {"median", s.median}};
}

/// JSON: thickness min / median / mean / max, samples where the ball is thinner than the ray by
/// more than its bound, rounds, queries, unconverged samples, seconds; below_min_wall when given.
[[nodiscard]] nlohmann::json ball_json(const queries::BallMap& r, const std::vector<nurbs::ray::Hit>& hits, double min_wall);

}  // namespace cli
