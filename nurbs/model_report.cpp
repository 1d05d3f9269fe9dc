#include "nurbs/model_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "nurbs/curve_eval.h"
#include "nurbs/request_error.h"
#include "nurbs/segment_distance.h"
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
                    "depend on them are widened by what the gap can change there",
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

namespace {

/// Samples of a lifted loop curve: dense enough that a chord is about a quarter of the gap (the
/// runs' slack then takes little of what the rule can save), within [64, 1024].
constexpr int kMinBoundarySamples = 64, kMaxBoundarySamples = 1024;
constexpr size_t kRunSamples = 16;

}  // namespace

FaceDoubts::FaceDoubts(const std::vector<TrimmedSurface>& faces) {
  for (size_t k = 0; k < faces.size(); ++k) {
    const TrimmedSurface& f = faces[k];
    if (f.trim_problem.empty() && !(f.edge_gap > 0.0)) continue;
    Doubt d{control_box(f.surface), int(k), f.face_id, f.edge_gap, f.trim_problem, {}};
    if (f.edge_gap > 0.0) {
      // The loops lifted to space, in runs of 16 chords with their boxes. A face without loops has
      // the domain's sides as its boundary.
      // Each sample of a line carries how far the curve strays from the chord to the next one:
      // twice its point at the parameter midpoint's distance from that chord.
      struct Line {
        std::vector<glm::dvec3> points;
        std::vector<double> stray;
      };
      std::vector<Line> lines;
      const auto lift = [&](const Curve2& c) {
        const Interval cd = curve_domain(c);
        const auto at = [&](double t) {
          const glm::dvec2 uv = curve_point(c, cd.min + cd.width() * t);
          return surface_point(f.surface, uv.x, uv.y);
        };
        double length = 0.0;
        for (int i = 1; i <= kMinBoundarySamples; ++i)
          length += glm::length(at(double(i) / kMinBoundarySamples) - at(double(i - 1) / kMinBoundarySamples));
        const int n = int(std::clamp(std::ceil(4.0 * length / f.edge_gap), double(kMinBoundarySamples),
                                     double(kMaxBoundarySamples)));
        Line line;
        for (int i = 0; i <= n; ++i) line.points.push_back(at(double(i) / n));
        for (int i = 0; i < n; ++i)
          line.stray.push_back(2.0 * segment_distance(at((i + 0.5) / n), line.points[size_t(i)], line.points[size_t(i) + 1]));
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
      for (const Line& line : lines)
        for (size_t i = 0; i + 1 < line.points.size(); i += kRunSamples) {
          BoundaryRun run;
          const size_t end = std::min(line.points.size(), i + kRunSamples + 1);
          run.points.assign(line.points.begin() + std::ptrdiff_t(i), line.points.begin() + std::ptrdiff_t(end));
          run.box = {run.points.front(), run.points.front()};
          for (const glm::dvec3& q : run.points) run.box.min = glm::min(run.box.min, q), run.box.max = glm::max(run.box.max, q);
          for (size_t j = i; j + 1 < end; ++j) run.slack = std::max(run.slack, line.stray[j]);
          d.boundary.push_back(std::move(run));
        }
    }
    doubts_.push_back(std::move(d));
  }
  for (size_t i = 0; i < doubts_.size(); ++i) {
    largest_gap_ = std::max(largest_gap_, doubts_[i].gap);
    if (!doubts_[i].problem.empty()) invalid_.push_back(int(i));
  }
  for (size_t i = 0; i < doubts_.size(); ++i)
    for (size_t r = 0; r < doubts_[i].boundary.size(); ++r) {
      runs_.emplace_back(int(i), int(r));
      largest_slack_ = std::max(largest_slack_, doubts_[i].boundary[r].slack);
    }
  const auto run = [this](int k) -> const BoundaryRun& {
    return doubts_[size_t(runs_[size_t(k)].first)].boundary[size_t(runs_[size_t(k)].second)];
  };
  run_tree_ = std::make_shared<const MedianTree>(
      int(runs_.size()),
      [&](int k, auto add) {
        add(run(k).box.min);
        add(run(k).box.max);
      },
      [&](int k, int axis) { return run(k).box.min[axis] + run(k).box.max[axis]; });
}

void FaceDoubts::boundaries_near(const glm::dvec3& q, double radius,
                                 std::vector<std::pair<int, double>>& out) const {
  out.clear();
  if (run_tree_->nodes.empty()) return;
  int stack[128], top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const MedianTree::Node& n = run_tree_->nodes[size_t(stack[--top])];
    if (box_distance(Box{n.lo, n.hi}, q) - largest_slack_ > radius) continue;
    if (n.left >= 0) {
      stack[top++] = n.left;
      stack[top++] = n.right;
      continue;
    }
    for (int k = n.first; k < n.first + n.count; ++k) {
      const auto [doubt, r] = runs_[size_t(run_tree_->order[size_t(k)])];
      const BoundaryRun& run = doubts_[size_t(doubt)].boundary[size_t(r)];
      if (box_distance(run.box, q) - run.slack > radius) continue;
      double near = std::numeric_limits<double>::infinity();
      for (size_t j = 0; j + 1 < run.points.size(); ++j)
        near = std::min(near, segment_distance(q, run.points[j], run.points[j + 1]));
      const double lower = std::max(0.0, near - run.slack);
      if (lower > radius) continue;
      const auto at = std::find_if(out.begin(), out.end(), [&](const auto& e) { return e.first == doubt; });
      if (at == out.end())
        out.emplace_back(doubt, lower);
      else
        at->second = std::min(at->second, lower);
    }
  }
  std::sort(out.begin(), out.end());
}

double FaceDoubts::boundary_distance(const Doubt& d, const glm::dvec3& p, double within) {
  double best = std::numeric_limits<double>::infinity();
  for (const BoundaryRun& run : d.boundary) {
    if (box_distance(run.box, p) - run.slack > std::min(best, within)) continue;
    double near = std::numeric_limits<double>::infinity();
    for (size_t j = 0; j + 1 < run.points.size(); ++j)
      near = std::min(near, segment_distance(p, run.points[j], run.points[j + 1]));
    best = std::min(best, std::max(0.0, near - run.slack));
  }
  return best <= within ? best : std::numeric_limits<double>::infinity();
}

template <class Within>
void FaceDoubts::mark_invalid(Verdict& v, Within within) const {
  for (const int i : invalid_)
    if (const Doubt& d = doubts_[size_t(i)]; within(d.box, v.widen)) {
      v.invalid_face = d.face;
      v.reason = invalid_trim_text(d.face, d.face_id, d.problem);
      return;
    }
}

FaceDoubts::Verdict FaceDoubts::at(const glm::dvec3& p, double d, double b,
                                   const std::optional<Witness>& closest) const {
  if (doubts_.empty()) return {};
  const double inf = std::numeric_limits<double>::infinity();
  // A non-finite answer reaches every face, and every gap widens it in full.
  const bool finite = std::isfinite(d + b);
  const double reach = finite ? d + b : inf;
  const double low = finite ? std::max(0.0, d - b) : 0.0;  // the answer's lower end (distances are >= 0)
  const bool witnessed = finite && closest && std::isfinite(closest->within) &&
                         glm::all(glm::lessThan(glm::abs(closest->point), glm::dvec3(inf)));
  Verdict v;
  const auto raise = [&](double w, const Doubt& x) {
    if (w > v.widen) v.widen = w, v.gap_face = x.face, v.gap_face_id = x.face_id, v.gap = x.gap;
  };
  if (!finite) {
    for (const Doubt& x : doubts_)
      if (x.gap > 0.0) raise(x.gap, x);
  } else {
    // The gapped boundaries within reach of p (below) and of the witness, or p (above), from the
    // tree of runs: the faces are taken in their order, as each face's own test would.
    const double largest = largest_gap_;
    thread_local std::vector<std::pair<int, double>> below, above;
    below.clear();
    if (low > 0.0) boundaries_near(p, low + largest, below);
    if (witnessed)
      boundaries_near(closest->point, largest + closest->within, above);
    else
      boundaries_near(p, reach + largest, above);
    size_t i = 0, j = 0;
    while (i < below.size() || j < above.size()) {
      constexpr int none = std::numeric_limits<int>::max();
      const int face = std::min(i < below.size() ? below[i].first : none, j < above.size() ? above[j].first : none);
      const double to_p = i < below.size() && below[i].first == face ? below[i++].second : inf;
      const double to_witness = j < above.size() && above[j].first == face ? above[j++].second : inf;
      const Doubt& x = doubts_[size_t(face)];
      const double g = x.gap;
      if (!(g > 0.0) || v.widen >= g) continue;
      // Below, by (i): the file's face may add material within g of B, nearer than `low` only where
      // dist(p, B) < low + g.
      if (low > 0.0 && to_p < low + g) raise(std::min({g, low, low + g - to_p}), x);
      // Above, by (ii) and (iii): the closest point may have been cut away only within g of B.
      if (v.widen < g && to_witness <= (witnessed ? g + closest->within : reach + g)) raise(g, x);
    }
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
    if (d.gap > v.widen && within(d.box, d.gap))
      v.widen = d.gap, v.gap_face = d.face, v.gap_face_id = d.face_id, v.gap = d.gap;
  mark_invalid(v, within);
  return v;
}

double FaceDoubts::boundary_distance(const Doubt& d, const std::vector<Box>& boxes, double within) {
  double best = std::numeric_limits<double>::infinity();
  for (const Box& box : boxes) {
    if (box_distance(d.box, box) > std::min(best, within)) continue;
    for (const BoundaryRun& run : d.boundary) best = std::min(best, std::max(0.0, box_distance(run.box, box) - run.slack));
  }
  return best <= within ? best : std::numeric_limits<double>::infinity();
}

double FaceDoubts::largest_gap() const { return largest_gap_; }

FaceDoubts::Side FaceDoubts::side(const std::vector<Box>& others, double low, double reach, double d, double b,
                                  const std::optional<Witness>& witness) const {
  Side s;
  if (doubts_.empty()) return s;
  const bool finite = std::isfinite(d + b) && std::isfinite(reach);
  // A face box within the answer's reach (plus `extra`) of the other side's faces.
  const double r = finite ? d + b : std::numeric_limits<double>::infinity();
  const auto near_others = [&](const Box& box, double extra) {
    for (const Box& o : others)
      if (box_distance(box, o) <= r + extra) return true;
    return false;
  };
  const auto set_face = [&](const Doubt& x) {
    s.verdict.gap_face = x.face, s.verdict.gap_face_id = x.face_id, s.verdict.gap = x.gap;
  };
  for (const Doubt& x : doubts_) {
    if (!(x.gap > 0.0)) continue;
    if (!finite) {
      if (x.gap > std::max(s.gap, s.cut)) set_face(x);
      s.gap = std::max(s.gap, x.gap), s.cut = std::max(s.cut, x.gap), s.boundary = 0.0;
      continue;
    }
    // Below: a boundary that may come within `reach` of the other faces.
    if (low > 0.0) {
      const double to = boundary_distance(x, others, reach);
      if (to < reach) {
        if (x.gap > std::max(s.gap, s.cut)) set_face(x);
        s.gap = std::max(s.gap, x.gap), s.boundary = std::min(s.boundary, to);
      }
    }
    // Above: the witness may have been cut away only within the gap of a boundary.
    if (x.gap > s.cut) {
      const bool cut = witness ? boundary_distance(x, witness->point, x.gap + witness->within) <= x.gap + witness->within
                               : near_others(x.box, x.gap);
      if (cut) {
        if (x.gap > std::max(s.gap, s.cut)) set_face(x);
        s.cut = x.gap;
      }
    }
  }
  mark_invalid(s.verdict, near_others);
  return s;
}

FaceDoubts::Verdict FaceDoubts::clearance(const Side& a, const Side& b, double d, double bound) {
  // Below: d' >= min(d*, min(D_a, D_b) - G_a - G_b), the boundaries D within reach and their
  // largest gaps G; above: d' <= d + b + the gaps at either witness (each may be cut away).
  const double low = std::isfinite(d - bound) ? std::max(0.0, d - bound) : 0.0;
  const double g = a.gap + b.gap, to = std::min(a.boundary, b.boundary);
  const double below = g > 0.0 ? std::clamp(low + g - to, 0.0, std::min(low, g)) : 0.0;
  const double above = a.cut + b.cut;
  Verdict v;
  v.widen = std::isfinite(d + bound) ? std::max(below, above) : a.cut + b.cut;
  // The face named: the side that contributes most.
  const Side& main = std::max(a.gap, a.cut) >= std::max(b.gap, b.cut) ? a : b;
  v.gap_face = main.verdict.gap_face, v.gap_face_id = main.verdict.gap_face_id, v.gap = main.verdict.gap;
  return v;
}

double checked_model_size(const Model& model, const std::filesystem::path& path) {
  const double size = model_size(model);
  if (const auto problems = validate_model_size(size); !problems.empty())
    throw RequestError(fmt::format("{}: {}", path.string(), problems.front()));
  return size;
}

}  // namespace nurbs
