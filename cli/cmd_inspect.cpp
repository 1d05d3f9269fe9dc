// `nurbsgl inspect MODEL SCAN`: a scan against its model through the library's front door
// queries::inspect (queries/inspection/inspect.h): placed by --transform, best-fitted with --align,
// every point's deviation certified, and per --within band the verdicts that hold whatever the
// bounds. Exit 0 when every inlier's verdicts are certain, 1 when some are undecided (or the fit
// failed), with the counts and reasons; the outputs are written either way.
#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/deviation_outputs.h"
#include "cli/validators.h"
#include "nurbs/io/input_file.h"
#include "nurbs/io/mesh_writer.h"
#include "nurbs/io/output_file.h"
#include "nurbs/io/read_error.h"
#include "nurbs/io/transform_file.h"
#include "nurbs/model_ops.h"
#include "queries/distance/deviation_report.h"
#include "nurbs/tessellation/model_mesh.h"
#include "queries/inspection/inspect.h"
#include "queries/inspection/inspection_report.h"

namespace cli {
namespace cmd_inspect_impl {

struct Options {
  std::string model, scan, transform, csv, ply, report, histogram;
  queries::InspectOptions inspect;
  double range = 0.0;  ///< the PLY's colour scale end; 0: the widest band
  std::string engine = "auto";
  bool json = false;
};

const char* verdict_name(queries::Verdict v) {
  switch (v) {
    case queries::Verdict::Within:
      return "within";
    case queries::Verdict::Outside:
      return "outside";
    case queries::Verdict::Undecided:
      return "undecided";
    case queries::Verdict::Outlier:
      return "outlier";
    case queries::Verdict::NotFound:
      return "not_found";
  }
  return "";
}

nlohmann::json matrix_json(const glm::dmat4& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 4; ++r) rows.push_back({m[0][r], m[1][r], m[2][r], m[3][r]});
  return rows;
}

/// One row per point: its place in the model's frame, deviation, bound, closest point and outward
/// normal there, and a verdict per band.
void write_csv(const std::string& path, const queries::InspectResult& r) {
  std::string header = "point,x,y,z,deviation,bound,closest_x,closest_y,closest_z,normal_x,normal_y,normal_z,face";
  for (const queries::BandVerdicts& b : r.bands) header += fmt::format(",within_{:g}", b.within);
  header += ",reason\n";
  const size_t nb = r.bands.size();
  write_rows(path, header, r.points.size(), [&](fmt::memory_buffer& buf, size_t k) {
    const auto out = std::back_inserter(buf);
    const queries::PointDistance& d = r.answers.answers[k];
    const glm::dvec3& p = r.points[k];
    fmt::format_to(out, "{},{},{},{}", k, p.x, p.y, p.z);
    if (d.found)
      fmt::format_to(out, ",{},{},{},{},{},{},{},{},{}", r.deviation[k], d.bound, d.point.x, d.point.y, d.point.z,
                     r.answers.normals[k].x, r.answers.normals[k].y, r.answers.normals[k].z, d.face);
    else
      fmt::format_to(out, ",,,,,,,,,-1");
    for (size_t b = 0; b < nb; ++b) fmt::format_to(out, ",{}", verdict_name(r.verdicts[k * nb + b]));
    buf.push_back(',');
    append_csv_quoted(buf, r.answers.reason(k));
    buf.push_back('\n');
  });
}

nlohmann::json result_json(const queries::InspectResult& r, const Options& o, const nurbs::io::PointCloud& scan) {
  const queries::InspectStatistics& s = r.stats;
  nlohmann::json percentiles = nlohmann::json::object();
  for (size_t i = 0; i < s.percentiles.size(); ++i)
    percentiles[fmt::format("{:g}", queries::InspectStatistics::kPercentiles[i])] = s.percentiles[i];
  nlohmann::json bands = nlohmann::json::array();
  for (const queries::BandVerdicts& b : r.bands)
    bands.push_back({{"within", b.within},
                     {"certainly_within", b.certainly_within},
                     {"certainly_outside", b.certainly_outside},
                     {"undecided", b.undecided},
                     {"share_within", b.share_within},
                     {"share_above", b.share_above},
                     {"share_below", b.share_below}});
  const queries::Alignment& a = r.alignment;
  nlohmann::json alignment = {{"matrix", matrix_json(a.matrix)}, {"aligned", r.aligned}};
  if (r.aligned) {
    alignment["rms"] = a.rms, alignment["points_used"] = a.points_used, alignment["iterations"] = a.iterations;
    alignment["converged"] = a.converged, alignment["coarse_start"] = a.coarse_start;
    if (!a.problem.empty()) alignment["problem"] = a.problem;
  }
  nlohmann::json j = {{"model", o.model},
                      {"scan", {{"file", o.scan}, {"points", scan.points.size()}, {"format", scan.format}}},
                      {"tolerance", r.tolerance},
                      {"signed", r.signed_values},
                      {"alignment", alignment},
                      {"statistics",
                       {{"points", s.points},
                        {"inliers", s.inliers},
                        {"outliers", s.outliers},
                        {"not_found", s.not_found},
                        {"min", s.min},
                        {"max", s.max},
                        {"mean", s.mean},
                        {"sigma", s.sigma},
                        {"rms", s.rms},
                        {"percentiles", percentiles}}},
                      {"bands", bands},
                      {"undecided_points", r.undecided_points},
                      {"certain", r.failure().empty()},
                      {"seconds",
                       {{"prepare", r.prepare_seconds}, {"fit", r.fit_seconds}, {"deviations", r.query_seconds}}}};
  if (!r.unsigned_reason.empty()) j["unsigned_reason"] = r.unsigned_reason;
  if (const std::string f = r.failure(); !f.empty()) j["failure"] = f;
  if (!o.csv.empty()) j["results_file"] = o.csv;
  return j;
}

void print_text(const queries::InspectResult& r, const std::string& unit) {
  const queries::InspectStatistics& s = r.stats;
  if (r.aligned)
    fmt::print("best fit: {} in {} rounds on {} points, rms {:.4g} {} over the inliers{}\n",
               r.alignment.converged ? "converged" : "FAILED", r.alignment.iterations, r.alignment.points_used,
               r.alignment.rms, unit, r.alignment.coarse_start ? " (started from the box centres)" : "");
  fmt::print("{} points: {} inliers, {} outliers, {} without an answer; deviations {} ({}), certified within {:.3g}\n",
             s.points, s.inliers, s.outliers, s.not_found, r.signed_values ? "signed" : "unsigned", unit, r.tolerance);
  fmt::print("min {:.4g}, max {:.4g}, mean {:.4g}, sigma {:.4g}, rms {:.4g}; median {:.4g}, 5 % {:.4g}, 95 % {:.4g}\n",
             s.min, s.max, s.mean, s.sigma, s.rms, s.percentiles[3], s.percentiles[1], s.percentiles[5]);
  for (const queries::BandVerdicts& b : r.bands)
    fmt::print("within {:g}: {:.2f} % (above {:.2f} %, below {:.2f} %); certainly within {}, certainly outside {}, "
               "undecided {}\n",
               b.within, 100.0 * b.share_within, 100.0 * b.share_above, 100.0 * b.share_below, b.certainly_within,
               b.certainly_outside, b.undecided);
}

void run(const GlobalOptions& global, Options o) {
  const LoadedModel loaded = load_model(o.model, "inspect");
  const double limit = nurbs::coordinate_limit(nurbs::model_box(loaded.model));
  if (!o.transform.empty()) {
    try {
      o.inspect.transform = nurbs::io::read_transform_file(o.transform);
    } catch (const nurbs::io::ReadError& e) {
      throw BadInput(std::string("--transform ") + e.what());
    }
  }
  o.inspect.check();  // the options and outputs before the scan is read
  if (!o.csv.empty()) check_output(o.csv, "--csv");
  if (!o.ply.empty()) check_output(o.ply, "--ply");
  if (!o.histogram.empty()) check_histogram_python();
  std::string three_js;
  if (!o.report.empty()) {
    check_output(o.report, "--report");
    try {
      three_js = nurbs::io::read_input_file(NURBSGL_THREE_JS);
    } catch (const nurbs::io::ReadError& e) {
      throw BadInput(fmt::format("--report draws the part with three.js: {} (apt install libjs-three)", e.what()));
    }
  }
  const nurbs::io::PointCloud scan = read_points_file(o.scan, "SCAN", limit);
  auto gpu = start_gpu(global);
  o.inspect.query.engine = queries::engine_choice(o.engine);
  o.inspect.query.accept_partial = global.accept_partial;
  const CommandProgress watch = command_progress("inspect", "points");
  o.inspect.query.progress = watch.progress, o.inspect.query.log = watch.log;
  const queries::InspectResult r = queries::inspect(*gpu, loaded, scan.points, o.inspect, watch.log);
  const std::string unit = unit_name(loaded.model);
  if (!o.csv.empty()) write_csv(o.csv, r);
  if (!o.ply.empty()) {
    const double green = r.bands.empty() ? r.tolerance : r.bands.front().within;
    const double full = o.range > 0.0 ? o.range : r.bands.empty() ? std::max(std::abs(r.stats.min), r.stats.max)
                                                                  : 2.0 * r.bands.back().within;
    nurbs::io::write_mesh_file(o.ply, queries::deviation_cloud(r.points, r.deviation, green, full));
  }
  if (!o.histogram.empty()) {  // of the inliers
    queries::DeviationReport inliers;
    inliers.signed_values = r.signed_values;
    inliers.deviation = r.deviation;
    for (size_t k = 0; k < r.points.size(); ++k)
      if (r.outlier[k]) inliers.deviation[k] = std::nan("");
    write_histogram(o.histogram, inliers, o.inspect.within, unit);
  }
  if (!o.report.empty()) {
    // The part for display: its approximate tessellation at 1e-3 of the model size.
    nurbs::tess::ModelMeshOptions mo;
    mo.eps = 1e-3, mo.tess.mode = nurbs::tess::TessMode::Approximate, mo.accept_partial = true;
    const nurbs::tess::ModelMesh part = nurbs::tess::mesh_model(loaded, mo);
    queries::InspectionReportInputs in;
    in.model = o.model, in.scan = o.scan, in.unit = unit, in.result = &r, in.part = &part.result.mesh;
    in.three_js = std::move(three_js), in.range = o.range;
    const std::string text = queries::inspection_report_html(in);
    nurbs::io::write_file(o.report, [&](std::ostream& out) { out.write(text.data(), std::streamsize(text.size())); });
  }
  if (o.json) {
    nlohmann::json j = result_json(r, o, scan);
    if (!o.report.empty()) j["report"] = o.report;
    j["unit"] = unit;
    add_model_json(j, loaded.report, global);
    print_json(j);
  } else {
    print_text(r, unit);
  }
  report_profile(*gpu, global);
  if (const std::string why = r.failure(); !why.empty()) throw CommandFailed(why);
}

}  // namespace cmd_inspect_impl

void add_inspect(CLI::App& app, const GlobalOptions& global) {
  using namespace cmd_inspect_impl;
  auto* cmd = app.add_subcommand(
      "inspect", "A scan against its model: best fit, certified deviations, verdicts per tolerance band");
  auto o = std::make_shared<Options>();
  cmd->add_option("MODEL", o->model, "Model file (IGES, STEP, .bpt)")->required();
  cmd->add_option("SCAN", o->scan,
                  "The scan: PLY (ascii or binary), NumPy .npy (N x 3) or text (x y z per line, a header may name the "
                  "columns), told apart by content; - reads stdin")
      ->required();
  cmd->add_option("--within", o->inspect.within,
                  "Inspection bands, model units, ascending and comma-separated: per band each point is certainly "
                  "within, certainly outside or undecided, its bound included")
      ->delimiter(',')
      ->check(positive_number("a positive distance"));
  cmd->add_option("--max-distance", o->inspect.max_distance,
                  "Points farther than this from the model (model units) are outliers: counted, not judged, not fitted")
      ->check(positive_number("a positive distance"));
  cmd->add_option("--tol", o->inspect.tolerance,
                  "The certification tolerance in model units; default the smallest band / 10 (1e-5 of the model "
                  "size without bands)")
      ->check(positive_number("a positive distance"));
  cmd->add_option("--transform", o->transform,
                  "A 4 x 4 matrix placing the scan in the model's frame, applied first: the JSON inspect --json "
                  "prints (its alignment), or 16 numbers row by row")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--align", o->inspect.align,
                "Best-fit the scan first: robust point-to-plane ICP on the exact faces (points beyond --max-distance "
                "left out)");
  cmd->add_option("--align-faces", o->inspect.fit.faces,
                  "With --align: fit on these faces only (datum faces; indices as the JSON's face fields, "
                  "comma-separated)")
      ->delimiter(',');
  cmd->add_option("--align-sample", o->inspect.fit.sample, "With --align: the points the fit iterates on")
      ->check(CLI::Range(size_t(6), size_t(1) << 30))
      ->capture_default_str();
  cmd->add_option("--range", o->range,
                  "The PLY's colour scale: full red (above) or blue (below) at this deviation; default twice the "
                  "widest band")
      ->check(positive_number("a positive distance"));
  cmd->add_option("--engine", o->engine, "Where the distances are searched (as distance --engine)")
      ->check(CLI::IsMember({"auto", "gpu", "cpu"}))
      ->capture_default_str();
  cmd->add_option("--csv", o->csv,
                  "Write one row per point: place, deviation, bound, closest point, normal there, verdict per band")
      ->check(extension_is(".csv"));
  cmd->add_option("--ply", o->ply, "Write the points coloured by deviation (green within the first band) as PLY")
      ->check(extension_is(".ply"));
  cmd->add_option("--histogram", o->histogram,
                  "Write the inliers' deviation histogram with the bands as PNG (as distance --histogram)")
      ->check(extension_is(".png"));
  cmd->add_option("--report", o->report,
                  "Write the inspection report: one HTML file that opens with no network (the part and the scan "
                  "coloured by deviation in a 3D view, the bands, histogram, statistics, alignment and certificate)")
      ->check(extension_is(".html"));
  cmd->add_flag("--json", o->json, "Print one JSON object instead of text");
  cmd->callback([&global, o] {
    if (!o->inspect.fit.faces.empty() && !o->inspect.align) throw BadInput("--align-faces applies with --align");
    run(global, *o);
  });
}

}  // namespace cli
