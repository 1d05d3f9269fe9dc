#pragma once
/// \file clearance_json.h
/// The JSON of one clearance answer: `clearance --json` prints it for its pair, `clash --json` for
/// each pair of bodies, so the field names are one contract.
#include <nlohmann/json.hpp>

#include "queries/distance/clearance_pair.h"

namespace cli {

/// found, distance, bound, point_bound, point_a, point_b, face_a, face_b, uv_a, uv_b, seconds,
/// pairs_per_level, leaf_pairs, on_trim_edge, intersecting (with intersection {point, residual}),
/// meets_tolerance, refine; uncertified (why) when it is not certified; first_stage with the voxel
/// stage (`voxels` per axis).
[[nodiscard]] nlohmann::json clearance_answer_json(const queries::ClearanceAnswer& answer, int voxels);

}  // namespace cli
