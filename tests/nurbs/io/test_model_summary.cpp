// Model summary as struct, text and JSON, on the exact sample model.
#include <doctest/doctest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "nurbs/io/model_summary.h"
#include "nurbs/model_ops.h"
#include "sample_models.h"

TEST_CASE("summary of the sample model") {
  nurbs::Model m = nurbs::io::test::small_model();
  m.skipped_entities[120] = 2;
  const nurbs::io::ModelSummary s = nurbs::io::summarize(m);
  CHECK(s.faces == 2);
  CHECK(s.trimmed_faces == 1);
  CHECK(s.rational_faces == 1);
  CHECK(s.control_points == 9 + 16);
  CHECK(s.max_degree_u == 3);
  CHECK(s.outer_loops == 1);
  CHECK(s.inner_loops == 1);
  CHECK(s.trim_curves == 5);
  // Control points: cylinder in [0,2]x[0,3]x[0,2], bump in [0,3]x[0,3]x[0,1]; exact small integers.
  CHECK(s.bbox_min == glm::dvec3(0.0));
  CHECK(s.bbox_max == glm::dvec3(3.0, 3.0, 2.0));
  // Model size: the sampled box (nurbs::model_size), inside the control-point box (diagonal sqrt 22).
  CHECK(s.size == nurbs::model_size(m));
  CHECK(s.size > 0.9 * std::sqrt(22.0));
  CHECK(s.size <= std::sqrt(22.0));
  const std::string text = nurbs::io::to_text(s, true);
  CHECK(text.find("faces: 2 (1 with trim loops, 1 rational)") != std::string::npos);
  CHECK(text.find("skipped entities: 120x2") != std::string::npos);
  CHECK(text.find("loops 1 outer 1 inner, 5 curves") != std::string::npos);
  // Faces numbered as every command numbers them (0-based), the file's id beside.
  CHECK(text.find("face 0 (id " + std::to_string(s.face_list[0].face_id) + ", body 0") != std::string::npos);
  CHECK(text.find("face 1 (id " + std::to_string(s.face_list[1].face_id) + ", body 0") != std::string::npos);
  const nlohmann::json j = nurbs::io::to_json(s);
  CHECK(j["faces"] == 2);
  CHECK(j["skipped_entities"]["120"] == 2);
  CHECK(j["face_list"].size() == 2);
  CHECK(j["face_list"][0]["rational"] == true);
  CHECK(j["face_list"][1]["face"] == 1);
  CHECK(j["control_bbox"]["max"][2] == 2.0);
  CHECK(j["size"] == s.size);
}

TEST_CASE("summary: body transform moves the bbox") {
  nurbs::Model m = nurbs::io::test::small_model();
  m.bodies[0].transform[3] = glm::dvec4(10.0, 0.0, 0.0, 1.0);  // translate by +10 in x
  const auto s = nurbs::io::summarize(m);
  CHECK(s.bbox_min.x == 10.0);
  CHECK(s.bbox_max.x == 13.0);
}

TEST_CASE("summary: the file's faces, the dropped ones with their reasons, the read warnings") {
  nurbs::Model m = nurbs::io::test::small_model();
  m.faces_in_file = 3;
  m.dropped_faces.push_back({"D41", "it needs D37 of unsupported type 118"});
  m.read_warnings.push_back(
      "line 2: global parameter 3: Hollerith count 38 runs past its string; read up to the delimiter");
  const nurbs::io::ModelSummary s = nurbs::io::summarize(m);
  const std::string text = nurbs::io::to_text(s);
  CHECK(text.find("faces in file: 3 (1 dropped)\n") != std::string::npos);
  CHECK(text.find("dropped face D41: it needs D37 of unsupported type 118\n") != std::string::npos);
  CHECK(text.find("read warning: line 2: global parameter 3: Hollerith count 38") != std::string::npos);
  const nlohmann::json j = nurbs::io::to_json(s);
  CHECK(j["faces_in_file"] == 3);
  REQUIRE(j["faces_dropped"].size() == 1);
  CHECK(j["faces_dropped"][0]["entity"] == "D41");
  CHECK(j["faces_dropped"][0]["reason"] == "it needs D37 of unsupported type 118");
  REQUIRE(j["read_warnings"].size() == 1);
  CHECK(j["read_warnings"][0] == m.read_warnings[0]);
  // A reader that does not count faces says so with -1, and no line claims a count.
  const nurbs::Model plain = nurbs::io::test::small_model();
  CHECK(nurbs::io::to_text(nurbs::io::summarize(plain)).find("faces in file") == std::string::npos);
  CHECK(nurbs::io::to_json(nurbs::io::summarize(plain))["faces_in_file"] == -1);
}
