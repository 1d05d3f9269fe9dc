// `nurbsgl clash ASSEMBLY [--min-clearance D] [--json] [--csv F]`: the clearance of every pair of
// bodies of a model through the library's front door queries::clash_report
// (queries/distance/clash.h): each pair answered as `clearance ASSEMBLY ASSEMBLY --body-a I
// --body-b J` answers it, pairs whose boxes lie farther apart than D left out. Text: one line per
// pair, intersecting first, then by clearance. JSON: the summary (bodies, pairs, pairs_computed,
// pairs_beyond, pairs_intersecting, ...) and `results`, each with clearance --json's fields plus
// body_a, name_a, body_b, name_b, box_distance, computed, beyond_min_clearance (and of clearance's
// engine object, `used`). Exit 1 naming each pair whose answer is not certified.
#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "cli/clearance_json.h"
#include "cli/commands.h"
#include "cli/validators.h"
#include "nurbs/io/output_file.h"
#include "queries/distance/clash.h"

namespace cli {
// Named, not anonymous: the nurbsgl target is a unity build (cli/CMakeLists.txt).
namespace cmd_clash_impl {

struct Options {
  std::string model, csv;
  double min_clearance = std::numeric_limits<double>::infinity();
  queries::ClearanceOptions query;
  std::string engine = "auto";
  std::string face_cull = "boxes";
  int threads = 0;
  bool json = false;
};

/// A distance D >= 0 (a finite number).
CLI::Validator distance_at_least_zero() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0;
        if (std::string e = parse_double(text, v, "a distance"); !e.empty()) return e;
        if (!std::isfinite(v) || v < 0.0) return text + " is not a finite distance of 0 or more";
        return "";
      },
      "DISTANCE >= 0");
}

/// What a row says of its pair in one word: intersecting, clearance, or beyond (boxes, computed).
std::string status(const queries::ClashRow& r, double d) {
  if (!r.computed) return "beyond (boxes)";
  if (r.answer.clearance.intersecting) return "intersecting";
  return r.beyond(d) ? "beyond (computed)" : "clearance";
}

nlohmann::json row_json(const queries::ClashRow& r, const queries::ClashReport& report, int voxels) {
  nlohmann::json j = r.computed ? clearance_answer_json(r.answer, voxels) : nlohmann::json::object();
  j.update({{"body_a", r.body_a},
            {"name_a", r.name_a},
            {"body_b", r.body_b},
            {"name_b", r.name_b},
            {"box_distance", r.box_distance},
            {"computed", r.computed},
            {"beyond_min_clearance", r.beyond(report.min_clearance)}});
  if (r.computed)
    j.update({{"tolerance", r.answer.tolerance}, {"engine", {{"used", r.engine}}}, {"prepare_seconds", r.prepare_seconds}});
  return j;
}

nlohmann::json report_json(const queries::ClashReport& r, const Options& o, const LoadedModel& loaded,
                           const GlobalOptions& global) {
  nlohmann::json j = {{"model", o.model},
                      {"bodies", r.bodies},
                      {"pairs", r.rows.size()},
                      {"pairs_computed", r.computed},
                      {"pairs_beyond", r.beyond_boxes},
                      {"pairs_beyond_computed", r.beyond_computed},
                      {"pairs_intersecting", r.intersecting},
                      {"pairs_uncertified", r.uncertified},
                      {"pairs_limited_by_file", r.limited_by_file},
                      {"min_clearance", std::isfinite(r.min_clearance) ? nlohmann::json(r.min_clearance) : nullptr},
                      {"relative_tolerance", o.query.tolerance},
                      {"seconds", r.seconds},
                      {"engine", {{"requested", o.engine}, {"cpu_pairs", r.cpu_pairs}, {"gpu_pairs", r.gpu_pairs}}},
                      {"unit", unit_name(loaded.model)},
                      {"results", nlohmann::json::array()}};
  for (const queries::ClashRow& row : r.rows) j["results"].push_back(row_json(row, r, o.query.voxels));
  add_model_json(j, loaded.report, global);
  return j;
}

/// A CSV field: quoted, its quotes doubled (body names may hold commas).
std::string csv_text(const std::string& s) {
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

void write_csv(const std::string& path, const queries::ClashReport& r) {
  nurbs::io::write_file(path, [&](std::ostream& out) {
    out << "body_a,name_a,body_b,name_b,status,distance,bound,face_a,face_b,point_a_x,point_a_y,point_a_z,"
           "point_b_x,point_b_y,point_b_z,meets_tolerance,box_distance,uncertified\n";
    for (const queries::ClashRow& row : r.rows) {
      out << fmt::format("{},{},{},{},{},", row.body_a, csv_text(row.name_a), row.body_b, csv_text(row.name_b),
                         status(row, r.min_clearance));
      const queries::Clearance& c = row.answer.clearance;
      if (row.computed)
        out << fmt::format("{:.17g},{:.17g},{},{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{}", c.distance,
                           c.bound, c.face_a, c.face_b, c.point_a.x, c.point_a.y, c.point_a.z, c.point_b.x, c.point_b.y,
                           c.point_b.z, row.answer.meets() ? "true" : "false");
      else
        out << ",,,,,,,,,,";
      out << fmt::format(",{:.17g},{}\n", row.box_distance, csv_text(row.answer.reason));
    }
  });
}

void print_text(const queries::ClashReport& r, const Options& o, const std::string& unit) {
  const std::string beyond = fmt::format("{:g} {}", r.min_clearance, unit);
  const std::string left_out = std::isfinite(r.min_clearance)
                                   ? fmt::format(", {} left out (boxes farther apart than {}), {} computed beyond it",
                                                 r.beyond_boxes, beyond, r.beyond_computed)
                                   : "";
  fmt::print(
      "{}: {} bodies, {} pairs: {} computed, {} intersecting{}; {:.3f} s ({} pairs on the CPU alone, {} with "
      "the GPU)\n",
      o.model, r.bodies, r.rows.size(), r.computed, r.intersecting, left_out, r.seconds, r.cpu_pairs, r.gpu_pairs);
  fmt::print("{:>16} {:>9}  {:<24} {:<24} {:>7}  {}\n", fmt::format("clearance ({})", unit), "bound", "body A",
             "body B", "faces", "");
  for (const queries::ClashRow& row : r.rows) {
    const auto body = [](int k, const std::string& name) { return fmt::format("{:>3} {}", k, name); };
    const queries::Clearance& c = row.answer.clearance;
    std::string value = fmt::format("> {:g}", r.min_clearance), bound, faces, note;
    if (!row.computed) {
      note = fmt::format("boxes {:.6g} apart", row.box_distance);
    } else {
      value = c.intersecting ? "intersecting" : fmt::format("{:.9g}", c.distance);
      bound = fmt::format("{:.3g}", c.bound), faces = fmt::format("{}, {}", c.face_a, c.face_b);
      if (c.intersecting)
        note = fmt::format("at ({:.6g}, {:.6g}, {:.6g})", c.intersection.x, c.intersection.y, c.intersection.z);
      else if (row.beyond(r.min_clearance))
        note = fmt::format("beyond {}", beyond);
      if (!row.answer.meets()) note += note.empty() ? "NOT CERTIFIED" : ", NOT CERTIFIED";
    }
    fmt::print("{:>16} {:>9}  {:<24} {:<24} {:>7}  {}\n", value, bound, body(row.body_a, row.name_a),
               body(row.body_b, row.name_b), faces, note);
  }
}

void run(const GlobalOptions& global, const Options& o) {
  check_output(o.csv, "--csv");
  const LoadedModel loaded = load_model(o.model, "clash");
  queries::ClashOptions q;
  q.clearance = o.query;
  q.clearance.engine = queries::engine_choice(o.engine);
  q.clearance.face_cull = o.face_cull == "boxes";
  q.clearance.accept_partial = global.accept_partial;
  q.min_clearance = o.min_clearance;
  q.threads = o.threads;
  const CommandProgress watch = command_progress("clash", "pairs");
  q.progress = watch.progress;
  const queries::ClashReport r = queries::clash_report(loaded, q, nullptr, [&global] { return start_gpu(global); });
  if (!o.csv.empty()) write_csv(o.csv, r);
  if (o.json)
    print_json(report_json(r, o, loaded, global));
  else
    print_text(r, o, unit_name(loaded.model));
  if (r.gpu) report_profile(*r.gpu, global);
  require_certified(loaded.report, global);
  if (r.limited_by_file > 0)
    fmt::print(stderr, "clash: {} of {} computed pairs certified to the file's precision (limited_by_file)\n",
               r.limited_by_file, r.computed);
  if (const std::string why = r.failure(global.strict); !why.empty()) throw CommandFailed(why);
}

}  // namespace cmd_clash_impl

void add_clash(CLI::App& app, const GlobalOptions& global) {
  using namespace cmd_clash_impl;
  auto* cmd = app.add_subcommand("clash",
                                 "Clash report of an assembly: the clearance of every pair of its bodies (as "
                                 "`clearance --body-a I --body-b J`), intersecting pairs first");
  auto o = std::make_shared<Options>();
  cmd->add_option("ASSEMBLY", o->model, "Model file of several bodies (`nurbsgl info` lists them)")->required();
  cmd->add_option("--min-clearance", o->min_clearance,
                  "Leave out the pairs whose bodies' boxes lie farther apart than D (model units; the box distance "
                  "is a lower bound of the clearance); default: every pair computed")
      ->type_name("D")
      ->check(distance_at_least_zero());
  cmd->add_option("--tol", o->query.tolerance,
                  "The bound every answer must meet, relative to the larger body of its pair (as clearance)")
      ->check(relative_tolerance())
      ->capture_default_str();
  add_search_option(cmd, o->query.search);
  cmd->add_option("--max-samples", o->query.max_samples,
                  "The most grid samples of one face; a face that needs more for --tol is refused (exit 2)")
      ->check(CLI::Range(4LL, 1LL << 30))
      ->capture_default_str();
  cmd->add_option("--face-cull", o->face_cull, "As clearance --face-cull: boxes or off")
      ->check(CLI::IsMember({"boxes", "off"}))
      ->capture_default_str();
  cmd->add_option("--engine", o->engine,
                  "As clearance --engine: auto (small pairs on the CPU alone, on every core; the others on the GPU), "
                  "gpu or cpu")
      ->check(CLI::IsMember({"auto", "gpu", "cpu"}))
      ->capture_default_str();
  cmd->add_option("--threads", o->threads, "Threads for the pairs answered on the CPU; 0: one per hardware thread")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  cmd->add_flag("--json", o->json, "Print one JSON object instead of text");
  cmd->add_option("--csv", o->csv, "Write one line per pair (the rows of the table) as CSV");
  cmd->callback([&global, o] { run(global, *o); });
}

}  // namespace cli
