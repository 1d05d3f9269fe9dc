#include "nurbs/model_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "nurbs/curve_eval.h"
#include "nurbs/request_error.h"
#include "nurbs/surface_eval.h"

namespace nurbs {

namespace {

std::string face_name(const FaceNote& n) { return fmt::format("face {} (id {})", n.face, n.face_id); }

std::string invalid_trim_text(int face, int face_id, const std::string& problem) {
  return fmt::format("face {} (id {}) may hold the answer and its trim could not be made valid: {}", face, face_id,
                     problem);
}

}  // namespace

double ModelReport::largest_gap() const {
  double g = 0.0;
  for (const FaceNote& n : edge_gaps) g = std::max(g, n.gap);
  return g;
}

std::string ModelReport::invalid_trim_reason() const {
  if (invalid_trims.empty()) return "";
  const FaceNote& n = invalid_trims.front();
  return invalid_trim_text(n.face, n.face_id, n.problem);
}

std::string ModelReport::uncertified_reason(bool accept_partial) const {
  if (!partial() || accept_partial) return "";
  return fmt::format(
      "the reader dropped {} of {} faces of {}: answers on the rest are not answers on the file's model (accept the "
      "partial model explicitly to certify them on it)",
      dropped.size(), faces_in_file >= 0 ? faces_in_file : faces_read + int(dropped.size()), source);
}

std::vector<std::string> ModelReport::lines(size_t max_items) const {
  std::vector<std::string> out;
  if (partial()) {
    std::map<std::string, int> by_reason;
    for (const DroppedFace& d : dropped) ++by_reason[d.reason];
    out.push_back(fmt::format("{} of {} faces of the file dropped by the reader", dropped.size(),
                              faces_in_file >= 0 ? faces_in_file : faces_read + int(dropped.size())));
    for (size_t k = 0; k < dropped.size() && k < max_items; ++k)
      out.push_back(fmt::format("  face {} dropped: {}", dropped[k].entity, dropped[k].reason));
    if (dropped.size() > max_items) out.push_back(fmt::format("  ... and {} more", dropped.size() - max_items));
  }
  if (!invalid_trims.empty()) {
    out.push_back(
        fmt::format("{} faces kept with trim loops that could not be made valid: answers that may depend "
                    "on them are not certified",
                    invalid_trims.size()));
    for (size_t k = 0; k < invalid_trims.size() && k < max_items; ++k)
      out.push_back(fmt::format("  {}: {}", face_name(invalid_trims[k]), invalid_trims[k].problem));
    if (invalid_trims.size() > max_items)
      out.push_back(fmt::format("  ... and {} more", invalid_trims.size() - max_items));
  }
  if (!edge_gaps.empty()) {
    out.push_back(
        fmt::format("{} faces kept whose file edges lie off their surface, up to {:.3g}: bounds that may "
                    "depend on them are widened by the gap",
                    edge_gaps.size(), largest_gap()));
    std::vector<FaceNote> worst = edge_gaps;
    std::sort(worst.begin(), worst.end(), [](const FaceNote& a, const FaceNote& b) { return a.gap > b.gap; });
    for (size_t k = 0; k < worst.size() && k < max_items; ++k)
      out.push_back(fmt::format("  {}: edges up to {:.3g} off the surface", face_name(worst[k]), worst[k].gap));
    if (worst.size() > max_items) out.push_back(fmt::format("  ... and {} more", worst.size() - max_items));
  }
  for (size_t k = 0; k < warnings.size() && k < max_items; ++k) out.push_back(warnings[k]);
  if (warnings.size() > max_items) out.push_back(fmt::format("... and {} more warnings", warnings.size() - max_items));
  return out;
}

ModelReport model_report(const Model& model) {
  ModelReport r;
  r.source = model.source;
  r.faces_in_file = model.faces_in_file;
  r.dropped = model.dropped_faces;
  r.warnings = model.read_warnings;
  int index = 0;
  for (const Body& b : model.bodies)
    for (const TrimmedSurface& f : b.faces) {
      if (!f.trim_problem.empty()) r.invalid_trims.push_back({index, f.face_id, f.trim_problem, f.edge_gap});
      if (f.edge_gap > 0.0) r.edge_gaps.push_back({index, f.face_id, "", f.edge_gap});
      ++index;
    }
  r.faces_read = index;
  return r;
}

FaceDoubts::FaceDoubts(const std::vector<TrimmedSurface>& faces) {
  for (size_t k = 0; k < faces.size(); ++k) {
    const TrimmedSurface& f = faces[k];
    if (f.trim_problem.empty() && !(f.edge_gap > 0.0)) continue;
    Doubt d{control_box(f.surface), int(k), f.face_id, f.edge_gap, f.trim_problem, {}, 0.0};
    if (f.edge_gap > 0.0) {
      // The loops lifted to space, 64 samples a curve, in runs of 16 with their boxes. A face
      // without loops has the domain's sides as its boundary.
      std::vector<std::vector<glm::dvec3>> lines;
      const auto lift = [&](const Curve2& c) {
        std::vector<glm::dvec3> line;
        const Interval cd = curve_domain(c);
        for (int i = 0; i <= 64; ++i) {
          const glm::dvec2 uv = curve_point(c, cd.min + cd.width() * i / 64.0);
          line.push_back(surface_point(f.surface, uv.x, uv.y));
        }
        return line;
      };
      for (const TrimLoop& l : f.loops)
        for (const Curve2& c : l.curves) lines.push_back(lift(c));
      if (f.loops.empty()) {
        const Interval du = surface_domain_u(f.surface), dv = surface_domain_v(f.surface);
        const glm::dvec2 corners[4] = {{du.min, dv.min}, {du.max, dv.min}, {du.max, dv.max}, {du.min, dv.max}};
        for (int s = 0; s < 4; ++s) {
          Curve2 side;
          side.degree = 1, side.knots = {0, 0, 1, 1}, side.points = {corners[s], corners[(s + 1) % 4]};
          lines.push_back(lift(side));
        }
      }
      for (const auto& line : lines)
        for (size_t i = 0; i + 1 < line.size(); i += 16) {
          BoundaryRun run;
          run.points.assign(line.begin() + std::ptrdiff_t(i),
                            line.begin() + std::ptrdiff_t(std::min(line.size(), i + 17)));
          run.box = {run.points.front(), run.points.front()};
          for (size_t j = 0; j < run.points.size(); ++j) {
            run.box.min = glm::min(run.box.min, run.points[j]), run.box.max = glm::max(run.box.max, run.points[j]);
            // Between two samples the lifted curve stays within their chord's length of them.
            if (j > 0) d.slack = std::max(d.slack, glm::length(run.points[j] - run.points[j - 1]));
          }
          d.boundary.push_back(std::move(run));
        }
    }
    doubts_.push_back(std::move(d));
  }
}

double FaceDoubts::boundary_distance(const Doubt& d, const glm::dvec3& p, double within) {
  double best = std::numeric_limits<double>::infinity();
  for (const BoundaryRun& run : d.boundary) {
    if (box_distance(run.box, p) > std::min(best, within)) continue;
    for (size_t j = 0; j + 1 < run.points.size(); ++j) {
      const glm::dvec3 a = run.points[j], ab = run.points[j + 1] - a;
      const double len2 = glm::dot(ab, ab);
      const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
      best = std::min(best, glm::length(a + t * ab - p));
    }
  }
  return best;
}

template <class Within>
void FaceDoubts::mark_invalid(Verdict& v, Within within) const {
  for (const Doubt& d : doubts_)
    if (!d.problem.empty() && within(d.box, v.widen)) {
      v.invalid_face = d.face;
      v.reason = invalid_trim_text(d.face, d.face_id, d.problem);
      return;
    }
}

FaceDoubts::Verdict FaceDoubts::at(const glm::dvec3& p, double d, double b) const {
  if (doubts_.empty()) return {};
  // A non-finite answer reaches every face.
  const double reach = std::isfinite(d + b) ? d + b : std::numeric_limits<double>::infinity();
  Verdict v;
  for (const Doubt& x : doubts_) {
    if (!(x.gap > 0.0) || v.widen >= x.gap) continue;
    const double within = reach + 2.0 * x.gap + x.slack;
    if (box_distance(x.box, p) <= within && boundary_distance(x, p, within) <= within) v.widen = x.gap;
  }
  // After the gaps: a widened bound reaches farther, to faces an invalid trim may hold.
  mark_invalid(v, [&](const Box& box, double extra) { return box_distance(box, p) <= reach + extra; });
  return v;
}

FaceDoubts::Verdict FaceDoubts::near(const Box& other, double reach) const {
  if (doubts_.empty()) return {};
  const double r = std::isfinite(reach) ? reach : std::numeric_limits<double>::infinity();
  const auto within = [&](const Box& box, double extra) { return box_distance(box, other) <= r + extra; };
  Verdict v;
  for (const Doubt& d : doubts_)
    if (d.gap > 0.0 && within(d.box, d.gap)) v.widen = std::max(v.widen, d.gap);
  mark_invalid(v, within);
  return v;
}

double checked_model_size(const Model& model, const std::filesystem::path& path) {
  const double size = model_size(model);
  if (const auto problems = validate_model_size(size); !problems.empty())
    throw RequestError(fmt::format("{}: {}", path.string(), problems.front()));
  return size;
}

}  // namespace nurbs
