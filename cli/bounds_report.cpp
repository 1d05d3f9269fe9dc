#include "cli/bounds_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "nurbs/distance/grid_report.h"
#include "nurbs/model_ops.h"

namespace cli {
// Named, not anonymous: the nurbsgl target is a unity build (cli/CMakeLists.txt), where the
// files' anonymous namespaces would meet.
namespace bounds_report_impl {

nlohmann::json finite_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

}  // namespace bounds_report_impl

nlohmann::json bounds_report(const nurbs::Model& model, double rel_tolerance, bool progress) {
  using namespace bounds_report_impl;
  const double size = nurbs::model_size(model);
  const double tolerance = rel_tolerance * size;
  const auto faces = nurbs::world_faces(model);
  nlohmann::json rows = nlohmann::json::array();
  std::vector<double> ratios;
  long long samples = 0, uniform_samples = 0;
  int meeting = 0, uniform_meeting = 0;
  for (size_t i = 0; i < faces.size(); ++i) {
    const nurbs::FaceGridReport r = nurbs::grid_report(faces[i].surface, tolerance);
    ratios.push_back(r.bound_ratio);
    samples += r.grid.grid.samples();
    uniform_samples += r.uniform_samples();
    meeting += r.grid.meets_tolerance ? 1 : 0;
    uniform_meeting += r.uniform_k_e <= tolerance ? 1 : 0;
    rows.push_back({{"face", i},
                    {"face_id", faces[i].face_id},
                    {"degree", {faces[i].surface.degree_u, faces[i].surface.degree_v}},
                    {"bound_ratio", finite_or_null(r.bound_ratio)},
                    {"K_e", finite_or_null(r.grid.k_e)},
                    {"grid", {r.grid.grid.u.size(), r.grid.grid.v.size()}},
                    {"segments", {r.grid.cells_u.size(), r.grid.cells_v.size()}},
                    {"meets_tolerance", r.grid.meets_tolerance},
                    {"uniform_grid", {r.uniform_n + 1, r.uniform_m + 1}},
                    {"uniform_K_e", finite_or_null(r.uniform_k_e)}});
    if (progress) fmt::print(stderr, "\r[{}/{}] faces bounded", i + 1, faces.size());
  }
  if (progress) fmt::print(stderr, "\n");
  std::vector<double> sorted = ratios;
  std::sort(sorted.begin(), sorted.end());
  auto q = [&](double f) { return sorted.empty() ? 0.0 : sorted[size_t(f * double(sorted.size() - 1))]; };
  return {{"tolerance", tolerance},
          {"relative_tolerance", rel_tolerance},
          {"faces", rows},
          {"faces_meeting_tolerance", meeting},
          {"uniform_faces_meeting_tolerance", uniform_meeting},
          {"samples", samples},
          {"uniform_samples", uniform_samples},
          {"bound_ratio",
           {{"median", q(0.5)},
            {"p90", q(0.9)},
            {"max", q(1.0)},
            {"faces_over_4", std::count_if(ratios.begin(), ratios.end(), [](double r) { return r > 4; })}}}};
}

std::string bounds_text(const nlohmann::json& r) {
  using namespace bounds_report_impl;
  auto num = [](const nlohmann::json& x) {
    return x.is_null() ? std::string("inf") : fmt::format("{:.3g}", x.get<double>());
  };
  std::string out = fmt::format(
      "bounds at tolerance {:.3g} ({:g} x model size): K_e from the Filip bound (knot-aligned grid) against the\n"
      "same K_e from sampled second derivatives (ratio), and the former uniform grid of the same tolerance\n"
      "{:>5} {:>7} {:>7} {:>11} {:>11} {:>10} {:>11} {:>11}\n",
      r["tolerance"].get<double>(), r["relative_tolerance"].get<double>(), "face", "degree", "ratio", "grid",
      "segments", "K_e", "uniform", "uniform K_e");
  for (const auto& f : r["faces"])
    out += fmt::format("{:>5} {:>3}x{:<3} {:>7} {:>5}x{:<5} {:>5}x{:<5} {:>10} {:>5}x{:<5} {:>11}{}\n",
                       f["face"].get<int>(), f["degree"][0].get<int>(), f["degree"][1].get<int>(),
                       num(f["bound_ratio"]), f["grid"][0].get<int>(), f["grid"][1].get<int>(),
                       f["segments"][0].get<int>(), f["segments"][1].get<int>(), num(f["K_e"]),
                       f["uniform_grid"][0].get<int>(), f["uniform_grid"][1].get<int>(), num(f["uniform_K_e"]),
                       f["meets_tolerance"].get<bool>() ? "" : "  NOT MET");
  const auto& b = r["bound_ratio"];
  out += fmt::format(
      "bound / sampled: median {:.3g}, 90 % {:.3g}, max {:.3g}, {} faces over 4\n"
      "faces meeting the tolerance: {} knot-aligned, {} uniform; samples {} knot-aligned, {} uniform\n",
      b["median"].get<double>(), b["p90"].get<double>(), b["max"].get<double>(), b["faces_over_4"].get<int>(),
      r["faces_meeting_tolerance"].get<int>(), r["uniform_faces_meeting_tolerance"].get<int>(),
      r["samples"].get<long long>(), r["uniform_samples"].get<long long>());
  return out;
}

}  // namespace cli
