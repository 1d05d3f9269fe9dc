// Hostile and extreme IGES input: files of a few KB that used to make the reader run for
// minutes or hand on non-finite geometry. Each is built in memory from the small sample model and
// must be refused with a message naming the entity, or read with its work bounded by a count the
// message states.
#include <doctest/doctest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "iges_edit.h"
#include "nurbs/io/iges_reader.h"
#include "nurbs/io/iges_writer.h"
#include "nurbs/io/model_summary.h"
#include "nurbs/io/read_error.h"
#include "nurbs/model_ops.h"
#include "nurbs/trim_loops.h"
#include "sample_models.h"

using nurbs::io::test::IgesEdit;

namespace {

std::string ent(int de, int type) { return "entity D" + std::to_string(de) + " (type " + std::to_string(type) + ")"; }

// The message of the ReadError that reading `text` throws; empty when it reads.
std::string read_error(const std::string& text) {
  try {
    nurbs::io::read_iges_text(text, "hostile.igs");
  } catch (const nurbs::io::ReadError& e) {
    return e.what();
  }
  return "";
}

IgesEdit sample() { return IgesEdit::parse(nurbs::io::write_iges_text(nurbs::io::test::small_model(), "h.igs")); }

nurbs::Model one_face(const nurbs::Surface& s) {
  nurbs::Model m;
  m.bodies.push_back({"faces", {nurbs::TrimmedSurface{}}, glm::dmat4(1.0), ""});
  m.bodies[0].faces[0].surface = s;
  return m;
}

bool has(const std::string& message, const std::string& part) { return message.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("a 144 naming the same hole loop twice is refused before any loop is expanded") {
  IgesEdit e = sample();
  const int face = e.find(144), hole = std::stoi(e.fields(face)[5]);
  // 2000 references: quartic work in the crossing check before (n = 500: 40 s).
  e.fields(face)[3] = "2000";
  for (int k = 1; k < 2000; ++k) e.fields(face).push_back(std::to_string(hole));
  const std::string message = read_error(e.text());
  CAPTURE(message);
  CHECK(has(message, ent(face, 144) + ", parameter 6: loop D" + std::to_string(hole) +
                         " is the same as at parameter 5: a face cannot have the same loop twice"));
}

TEST_CASE("two 142s of one face on the same parameter-space curve are the same loop") {
  IgesEdit e = sample();
  const int face = e.find(144), hole = std::stoi(e.fields(face)[5]);
  std::vector<std::string> copy(e.fields(hole).begin() + 1, e.fields(hole).end());
  const int twin = e.append(142, copy);
  e.fields(face)[3] = "2";
  e.fields(face).push_back(std::to_string(twin));
  const std::string message = read_error(e.text());
  CAPTURE(message);
  CHECK(has(message, ent(face, 144) + ", parameter 6: the parameter-space curve of loop D" + e.fields(hole)[3] +
                         " is the same as at parameter 5"));
}

TEST_CASE("composite curves listing a sub-curve twice, chained: bounded by the point budget") {
  // A hole made of a chain of 102s, each naming the previous one twice: 2^depth line segments.
  auto chain = [](int depth, int* top) {
    IgesEdit e = sample();
    int prev = e.append(110, {"0.2", "0.2", "0.", "0.8", "0.2", "0."});
    for (int k = 0; k < depth; ++k) prev = e.append(102, {"2", std::to_string(prev), std::to_string(prev)});
    const int hole = std::stoi(e.fields(e.find(144))[5]);
    e.fields(hole)[3] = std::to_string(prev);
    *top = prev;
    return e.text();
  };
  int top = 0;
  nurbs::io::IgesReadLog log;
  const nurbs::Model m = nurbs::io::read_iges_text(chain(8, &top), "h.igs", {}, &log);
  CHECK(m.bodies[0].faces[0].loops.back().curves.size() == 256);  // expanded as the file says
  // Depth 20: 2^20 segments of 2 points each, over the budget of 1e6 + file bytes: refused at the
  // outermost composite once the budget is spent (1 GB and a minute before).
  const std::string text = chain(20, &top);
  const std::string message = read_error(text);
  CAPTURE(message);
  CHECK(has(message, ent(top, 102) + ": reading it, the curves and surfaces read so far exceed " +
                         std::to_string(nurbs::io::kMaxPointsBase + static_cast<long long>(text.size())) +
                         " control points"));
}

TEST_CASE("composite curve cycles are refused, not expanded") {
  IgesEdit e = sample();
  const int hole = std::stoi(e.fields(e.find(144))[5]);
  const int a = e.append(102, {"2", "0", "0"});
  const int b = e.append(102, {"2", std::to_string(a), std::to_string(a)});
  e.fields(a)[2] = e.fields(a)[3] = std::to_string(b);  // a -> b -> a, each twice: 2^64 if expanded
  e.fields(hole)[3] = std::to_string(a);
  const std::string message = read_error(e.text());
  CAPTURE(message);
  CHECK(has(message, ": curves nested more than 64 deep (pointer cycle?)"));
}

TEST_CASE("degrees above kMaxDegree are refused, kMaxDegree itself is read") {
  // A Bézier patch of degree d x 1 (flat), and the same degree as a trim curve.
  auto patch = [](int d) {
    nurbs::Surface s;
    s.degree_u = d;
    s.degree_v = 1;
    s.count_u = d + 1;
    s.count_v = 2;
    s.knots_u.assign(static_cast<size_t>(d + 1), 0.0);
    s.knots_u.resize(static_cast<size_t>(2 * d + 2), 1.0);
    s.knots_v = {0, 0, 1, 1};
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i <= d; ++i) s.points.push_back({double(i) / d, j, 0.0});
    return s;
  };
  const int max = nurbs::io::kMaxDegree;
  CHECK_NOTHROW(nurbs::io::read_iges_text(nurbs::io::write_iges_text(one_face(patch(max))), "h.igs"));
  std::string message = read_error(nurbs::io::write_iges_text(one_face(patch(max + 1))));
  CHECK(has(message, ent(1, 128) + ", parameter 3: degree M1 = 33 exceeds the largest degree nurbsgl reads, 32"));

  IgesEdit e = sample();
  const int curve = e.find(126);
  e.fields(curve)[2] = "1000";
  message = read_error(e.text());
  CHECK(has(message, ent(curve, 126) + ", parameter 2: degree M = 1000 exceeds the largest degree nurbsgl reads, 32"));
}

TEST_CASE("coordinates, knots and weights beyond kMaxCoordinate are refused naming the entity") {
  nurbs::Surface s = nurbs::io::test::bump();
  s.points[5].z = 1e300;  // finite, but its box diagonal overflows: "size": null before
  std::string message = read_error(nurbs::io::write_iges_text(one_face(s)));
  CHECK(has(message, ent(1, 128) + ": out of range: control point 5 has coordinate 1e+300, beyond the largest "
                                   "magnitude 1e+100"));
  s = nurbs::io::test::bump();
  s.weights.assign(16, 1.0);
  s.weights[3] = 1e-200;
  message = read_error(nurbs::io::write_iges_text(one_face(s)));
  CHECK(has(message, ent(1, 128) + ": out of range: weight 3 is 1e-200, outside [1e-100, 1e+100]"));
  // Weights within range whose ratio the rational bounds cannot carry (a minute's tessellation 2.5
  // off its surface); a ratio of 1e6 is read.
  s.weights[3] = 1e9;
  message = read_error(nurbs::io::write_iges_text(one_face(s)));
  CHECK(has(message, ent(1, 128) + ": out of range: weight 3 is 1e+09 and weight 0 is 1: a ratio of 1e+09, above the "
                                   "1e+06 that the rational bounds carry"));
  s.weights[3] = 1e-6;
  CHECK(read_error(nurbs::io::write_iges_text(one_face(s))).empty());
  s = nurbs::io::test::bump();
  for (double& k : s.knots_u) k *= 1e150;
  message = read_error(nurbs::io::write_iges_text(one_face(s)));
  CHECK(has(message, ent(1, 128) + ": out of range: u knot 4 is 1e+150"));
  // A parameter-space line far out, after its transform.
  IgesEdit e = sample();
  const int line = e.append(110, {"0.2", "0.2", "0.", "1e200", "0.2", "0."});
  e.fields(std::stoi(e.fields(e.find(144))[5]))[3] = std::to_string(line);
  message = read_error(e.text());
  CHECK(has(message, ent(line, 110) + ": out of range: control point 1 has coordinate 1e+200"));
}

TEST_CASE("model size: zero and non-finite sizes are refused by validate_model_size") {
  nurbs::Surface s = nurbs::io::test::bump();
  for (glm::dvec3& p : s.points) p *= 1e-300;  // the diagonal underflows to 0
  const double size = nurbs::model_size(one_face(s));
  CHECK(size == 0.0);
  const auto problems = nurbs::validate_model_size(size);
  REQUIRE(problems.size() == 1);
  CHECK(problems[0] == "model size is 0, less than 1e-100: the surfaces collapse to a point (coordinates too small?)");
  CHECK(nurbs::validate_model_size(HUGE_VAL).size() == 1);
  CHECK(nurbs::validate_model_size(std::nan("")).size() == 1);
  CHECK(nurbs::validate_model_size(1e101).size() == 1);
  CHECK(nurbs::validate_model_size(4.2).empty());
}

TEST_CASE("info: the sampled model size misses a spike, the control box bounds it") {
  nurbs::Surface s = nurbs::io::test::bump();
  s.points[5].z = -999999.0;  // one control point far out: the sampled size is 40x below it
  const nurbs::io::ModelSummary summary = nurbs::io::summarize(one_face(s));
  CHECK(summary.size < summary.control_size / 4);
  CHECK(summary.control_size == doctest::Approx(std::sqrt(9.0 + 9.0 + 1e6 * 1e6)).epsilon(1e-12));
  CHECK(has(nurbs::io::to_text(summary),
            "(sampled box diagonal, a lower estimate; relative tolerances refer to it; "
            "the control-point box diagonal 1e+06 bounds it above)"));
  const nlohmann::json j = nurbs::io::to_json(summary);
  CHECK(j["control_box_diagonal"] == summary.control_size);
  CHECK(j["size_method"] == "sampled box diagonal (a lower estimate)");
}

TEST_CASE("crossing check: copies of one loop give one message per pair, and the search stops at its budgets") {
  nurbs::TrimmedSurface face;
  face.surface = nurbs::io::test::bump();
  face.face_id = 7;
  for (int k = 0; k < 40; ++k) face.loops.push_back(nurbs::io::test::square_loop(0.2, 0.8));
  std::vector<std::string> problems = nurbs::check_trim_loops(face, 1e-6, 1e-3);
  CHECK(problems.size() == 40 * 39 / 2);  // every pair of loops crosses, each said once
  CHECK(problems.back().rfind("face 7: loops ", 0) == 0);
  // 2000 copies cross in 2e6 pairs (2000 messages at n = 500 took 40 s before): 1000 are listed.
  face.loops.resize(2000, face.loops.front());
  problems = nurbs::check_trim_loops(face, 1e-6, 1e-3);
  CHECK(problems.size() == 1001);
  CHECK(problems.back() == "face 7: more than 1000 crossing loop pairs; the rest are not listed");
  // One loop going 4000 times around the square: one crossing, then > 6e7 candidate pairs of edges.
  face.loops.resize(1);
  const nurbs::TrimLoop square = face.loops[0];
  for (int k = 1; k < 4000; ++k)
    face.loops[0].curves.insert(face.loops[0].curves.end(), square.curves.begin(), square.curves.end());
  problems = nurbs::check_trim_loops(face, 1e-6, 1e-3);
  REQUIRE(problems.size() == 2);
  CHECK(problems[0].rfind("face 7: loop 0 crosses itself", 0) == 0);
  CHECK(problems[1] ==
        "face 7: crossing check stopped after 30000000 candidate edge pairs (loops overlapping over long "
        "stretches?); further crossings are not reported");
}
