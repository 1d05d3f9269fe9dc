#include "cli/clearance_json.h"

#include <algorithm>

namespace cli {

nlohmann::json clearance_answer_json(const queries::ClearanceAnswer& answer, int voxels) {
  const queries::Clearance& c = answer.clearance;
  nlohmann::json j = {
      {"found", c.found},
      {"distance", c.distance},
      {"bound", c.bound},
      {"point_bound", c.point_bound()},
      {"point_a", {c.point_a.x, c.point_a.y, c.point_a.z}},
      {"point_b", {c.point_b.x, c.point_b.y, c.point_b.z}},
      {"face_a", c.face_a},
      {"face_b", c.face_b},
      {"uv_a", {c.uv_a.x, c.uv_a.y}},
      {"uv_b", {c.uv_b.x, c.uv_b.y}},
      {"seconds", answer.seconds},
      {"pairs_per_level", c.pairs_per_level},
      {"leaf_pairs", c.leaf_pairs},
      {"on_trim_edge", c.on_trim_edge},
      {"intersecting", c.intersecting},
      {"meets_tolerance", c.found && c.meets_tolerance && queries::within_tolerance(c.bound, answer.tolerance)},
      {"refine",
       {{"rounds", c.rounds},
        {"cells", c.refined_cells},
        {"most_pairs", c.most_pairs},
        {"start_pairs", c.start_pairs},
        {"seconds", c.refine_seconds}}}};
  if (c.intersecting)  // a point of both models: the surfaces meet (or touch) there
    j["intersection"] = {{"point", {c.intersection.x, c.intersection.y, c.intersection.z}},
                         {"residual", c.intersection_residual}};
  if (!answer.reason.empty()) j["uncertified"] = answer.reason;
  j["limited_by_file"] = answer.limited_by_file();
  if (answer.widen > 0.0)
    j["file_widen"] = answer.widen, j["file_gap"] = answer.gap, j["gap_model"] = answer.gap_model,
    j["gap_face"] = answer.gap_face, j["gap_face_id"] = answer.gap_face_id;
  if (c.found && !answer.meets()) j["reason"] = answer.shortfall();
  if (const auto& vs = answer.first_stage)
    j["first_stage"] = {{"method", "voxels"},
                        {"voxels", voxels},
                        {"occupied_a", vs->voxels_a},
                        {"occupied_b", vs->voxels_b},
                        {"voxel_pairs", vs->voxel_pairs},
                        {"surviving_pairs", vs->surviving_pairs},
                        {"face_pairs", vs->face_pairs.size()},
                        {"faces_a", std::count(vs->faces_a.begin(), vs->faces_a.end(), 1)},
                        {"faces_b", std::count(vs->faces_b.begin(), vs->faces_b.end(), 1)},
                        {"seconds", answer.first_stage_seconds}};
  return j;
}

}  // namespace cli
