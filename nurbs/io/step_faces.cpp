// STEP faces and trims: the charts that bring a face's edges into its NURBS parameters, loops
// through poles and apexes, the faces built from their jobs (on worker threads), shells and solids.
#include "nurbs/io/step_reader_detail.h"
#include "nurbs/curve_ends.h"

namespace nurbs::io::step_detail {

// A B-spline surface is periodic along a direction whose two boundary curves coincide.
Chart bspline_chart(const Surface& s, double accept) {
  const Interval u = surface_domain_u(s), v = surface_domain_v(s);
  const double size = control_box(s).diagonal();
  auto closed = [&](bool along_u) {
    for (int i = 0; i <= 8; ++i) {
      const double t = along_u ? v.min + v.width() * i / 8 : u.min + u.width() * i / 8;
      const glm::dvec3 a = along_u ? surface_point(s, u.min, t) : surface_point(s, t, v.min);
      const glm::dvec3 b = along_u ? surface_point(s, u.max, t) : surface_point(s, t, v.max);
      if (glm::length(a - b) > 1e-9 * size) return false;
    }
    return true;
  };
  Chart c;
  c.period = {closed(true) ? u.width() : 0.0, closed(false) ? v.width() : 0.0};
  // Unwrapped parameters brought back into the domain along periodic directions, clamped to it
  // along the others.
  const glm::dvec2 period = c.period;
  auto wrap = [u, v, period](glm::dvec2 uv) {
    auto w = [](double x, Interval d, double p) {
      if (!(p > 0)) return std::clamp(x, d.min, d.max);
      return x < d.min || x > d.max ? d.min + std::fmod(std::fmod(x - d.min, p) + p, p) : x;
    };
    return glm::dvec2(w(uv.x, u, period.x), w(uv.y, v, period.y));
  };
  c.point = [&s, wrap](glm::dvec2 uv) {
    const glm::dvec2 q = wrap(uv);
    return surface_point(s, q.x, q.y);
  };
  c.derivatives = [&s, wrap](glm::dvec2 uv) {
    const glm::dvec2 q = wrap(uv);
    return surface_derivatives(s, q.x, q.y);
  };
  c.natural = [&s, u, v, period, accept](glm::dvec3 p, const std::optional<glm::dvec2>& prev) {
    // Newton clamps to the domain: on a periodic direction a start on one side of the seam cannot
    // reach a point just across it, so a start near the seam is also tried on its other side.
    glm::dvec2 best{0.0};
    double best_d = std::numeric_limits<double>::infinity();
    auto attempt = [&](glm::dvec2 start) {
      const std::array<glm::dvec2, 2> sides = {start, glm::dvec2(start.x <= u.min + 0.5 * u.width() ? u.max : u.min,
                                                                 start.y <= v.min + 0.5 * v.width() ? v.max : v.min)};
      for (int k = 0; k < 4; ++k) {
        const bool flip_u = k & 1, flip_v = k & 2;
        if ((flip_u && !(period.x > 0 && std::min(start.x - u.min, u.max - start.x) < 0.05 * u.width())) ||
            (flip_v && !(period.y > 0 && std::min(start.y - v.min, v.max - start.y) < 0.05 * v.width())))
          continue;
        const glm::dvec2 st(flip_u ? sides[1].x : start.x, flip_v ? sides[1].y : start.y);
        const glm::dvec2 uv = closest_parameter(s, p, st);
        const double d = glm::length(surface_point(s, uv.x, uv.y) - p);
        if (d < best_d) best_d = d, best = uv;
        if (best_d <= accept) return;  // the other side of the seam only when this one fails
      }
    };
    if (prev) {
      glm::dvec2 start = *prev;  // brought into the domain
      if (period.x > 0) start.x = u.min + std::fmod(std::fmod(start.x - u.min, period.x) + period.x, period.x);
      if (period.y > 0) start.y = v.min + std::fmod(std::fmod(start.y - v.min, period.y) + period.y, period.y);
      attempt(start);
    }
    if (!(best_d <= accept)) attempt(closest_parameter(s, p));
    if (!(best_d <= accept)) {
      // A start on a collapsed boundary (a pole, where Newton's Jacobian is singular): from inside.
      const glm::dvec2 in(std::clamp(best.x, u.min + 0.01 * u.width(), u.max - 0.01 * u.width()),
                          std::clamp(best.y, v.min + 0.01 * v.width(), v.max - 0.01 * v.width()));
      attempt(in);
    }
    glm::dvec2 uv = best;
    if (prev) {
      if (period.x > 0) uv.x += period.x * std::round((prev->x - uv.x) / period.x);
      if (period.y > 0) uv.y += period.y * std::round((prev->y - uv.y) / period.y);
    }
    return uv;
  };
  return c;
}

// The outer loop's natural (u, v) samples (NaN u at points on the axis) where it passes the axis
// twice or more: between two such points a run of the loop may lie on either side of a seam (a
// hemisphere bounded by the meridian circle through its poles: the second meridian at +pi or -pi).
// Each run after the first is turned by -1, 0 or +1 turn so that the loop runs counter-clockwise in
// (u, v) (the material on its left: the natural parameters of ISO 10303-42's surfaces are
// right-handed about the outer normal, and the reader has turned the bounds of a same_sense .F.
// face round) within one turn, the narrowest such choice. Other loops are left as they are.
void choose_branches_across_axis(const std::vector<glm::dvec2*>& loop, double turn) {
  std::vector<size_t> axis;
  for (size_t i = 0; i < loop.size(); ++i)
    if (!std::isfinite(loop[i]->x)) axis.push_back(i);
  if (axis.size() < 2) return;
  // Runs between consecutive axis points (cyclically), as [begin, end) index ranges into loop.
  std::vector<std::pair<size_t, size_t>> runs;
  for (size_t k = 0; k < axis.size(); ++k) {
    const size_t b = axis[k] + 1, e = k + 1 < axis.size() ? axis[k + 1] : axis.front() + loop.size();
    if (e > b) runs.emplace_back(b, e);
  }
  if (runs.size() < 2 || runs.size() > 4) return;
  const auto at = [&](size_t i) -> glm::dvec2& { return *loop[i % loop.size()]; };
  std::vector<int> best, pick(runs.size(), 0);
  double best_extent = std::numeric_limits<double>::infinity();
  const auto combos = static_cast<int>(std::pow(3, runs.size() - 1));
  for (int c = 0; c < combos; ++c) {
    for (size_t r = 1, x = size_t(c); r < runs.size(); ++r, x /= 3) pick[r] = int(x % 3) - 1;
    double area = 0.0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
    glm::dvec2 last(std::numeric_limits<double>::quiet_NaN());
    std::optional<glm::dvec2> head;
    for (size_t r = 0; r < runs.size(); ++r)
      for (size_t i = runs[r].first; i < runs[r].second; ++i) {
        const glm::dvec2 q = at(i) + glm::dvec2(turn * pick[r], 0.0);
        if (!std::isfinite(q.x)) continue;
        if (head) area += last.x * q.y - q.x * last.y;
        else head = q;
        last = q, lo = std::min(lo, q.x), hi = std::max(hi, q.x);
      }
    if (!head) return;
    area += last.x * head->y - head->x * last.y;
    // Twice the area, beyond the rounding of runs on one line (a seam down and up again, unshifted).
    if (area > 1e-9 * turn * turn && hi - lo <= turn + 1e-9 && hi - lo < best_extent) {
      best_extent = hi - lo;
      best = pick;
    }
  }
  if (best.empty()) return;
  for (size_t r = 1; r < runs.size(); ++r)
    for (size_t i = runs[r].first; i < runs[r].second; ++i) at(i).x += turn * best[r];
}

// A loop's (u, v) points on a surface periodic in u with period `period`, split by its points on
// the axis (a pole, an apex; NaN u, no angle): each run between them made continuous (every point
// within half a period of the one before: the samples next to a pole, which have no neighbour's
// angle to follow, land on either side of a seam edge), and the run that ends the loop shifted by
// whole periods to end where the loop starts (a ball's seam used down to the pole and up again:
// the way up is on the other side of the seam). An outer loop that passes the axis twice or more
// has runs that no continuity ties together (a whole ball bounded by its seam alone, from pole to
// pole and back): their branches are chosen by choose_branches_across_axis.
void unwrap_across_axis(std::vector<std::vector<glm::dvec2>>& loop, double period, bool outer) {
  std::vector<glm::dvec2*> pts;
  for (auto& l : loop)
    for (glm::dvec2& q : l) pts.push_back(&q);
  const glm::dvec2* last = nullptr;
  size_t run = 0;  // first point of the current run
  bool axis = false;
  for (size_t i = 0; i < pts.size(); ++i) {
    glm::dvec2& q = *pts[i];
    if (!std::isfinite(q.x)) {
      last = nullptr, axis = true;
      continue;
    }
    if (last)
      q.x += period * std::round((last->x - q.x) / period);
    else
      run = i;
    last = &q;
  }
  if (axis && run != 0 && last && std::isfinite(pts.front()->x)) {
    const double shift = period * std::round((pts.front()->x - last->x) / period);
    for (size_t i = run; i < pts.size(); ++i) pts[i]->x += shift;
  }
  if (outer) choose_branches_across_axis(pts, period);
}

Chart analytic_chart(const Analytic& a, const AnalyticSurface& as) {
  Chart c = bspline_chart(as.surface, 0.0);
  const Interval u = surface_domain_u(as.surface), v = surface_domain_v(as.surface);
  const glm::dvec2 period = c.period;
  c.natural = [&a, &as, u, v, period](glm::dvec3 p, const std::optional<glm::dvec2>& prev) {
    std::optional<glm::dvec2> near, anchor = prev;
    if (anchor) {
      // After a point on the axis (no angle), the angle is taken nearest the patch's middle: the
      // branch the patch was built on, not atan2's.
      if (!std::isfinite(anchor->x)) anchor->x = 0.5 * (u.min + u.max);
      if (!std::isfinite(anchor->y)) anchor->y = 0.5 * (v.min + v.max);
    }
    if (anchor) {
      glm::dvec2 q = *anchor;  // into the domain, then the file's parameters
      if (period.x > 0) q.x = u.min + std::fmod(std::fmod(q.x - u.min, period.x) + period.x, period.x);
      if (period.y > 0) q.y = v.min + std::fmod(std::fmod(q.y - v.min, period.y) + period.y, period.y);
      near = glm::dvec2(as.u.inverse(q.x), as.v.inverse(q.y));
    }
    glm::dvec2 st = as.map(a.natural(p, near));
    if (anchor) {
      if (period.x > 0 && std::isfinite(st.x)) st.x += period.x * std::round((anchor->x - st.x) / period.x);
      if (period.y > 0 && std::isfinite(st.y)) st.y += period.y * std::round((anchor->y - st.y) / period.y);
    }
    return st;
  };
  return c;
}

// Marks the loop with the largest parameter box as the outer one.
void mark_outer(TrimmedSurface& f) {
  // The loop enclosing the largest area (its curves sampled, shoelace): the box of a loop's control
  // points overstates a rotated circle's reach, so a circle of radius 0.255 out-boxed one of 0.278.
  double best = -1.0;
  TrimLoop* outer = nullptr;
  for (TrimLoop& l : f.loops) {
    std::vector<glm::dvec2> polygon;
    for (const Curve2& c : l.curves) {
      const Interval d = curve_domain(c);
      for (int i = 0; i < 32; ++i) polygon.push_back(curve_point(c, d.min + d.width() * i / 32.0));
    }
    const double area = std::abs(signed_area(polygon));
    if (area > best) best = area, outer = &l;
  }
  if (outer) outer->outer = true;
}

// Largest distance from the surface points of the parameter-space curve `pc` (in s's (u, v), z = 0)
// to its 3D edge `c`, at kGapSamples + 1 points evenly spaced in parameter: at the ends to the
// edge's ends, inside to the nearest edge point (Newton from the same fraction of the edge, so
// differently parametrised curves are not taken for a gap). Infinite when a point is not finite.
double trim_gap(const Curve3& pc, const Curve3& c, const Surface& s) {
  const Interval dp = curve_domain(pc), dc = curve_domain(c);
  double worst = 0.0;
  for (int i = 0; i <= kGapSamples; ++i) {
    const double x = static_cast<double>(i) / kGapSamples, tc = dc.min + x * dc.width();
    const glm::dvec3 q = curve_point(pc, dp.min + x * dp.width());
    const glm::dvec3 p = surface_point(s, q.x, q.y);
    double d = glm::length(p - curve_point(c, tc));
    if (i > 0 && i < kGapSamples) d = std::min(d, glm::length(curve_point(c, Analytic::newton_t(c, p, dc, tc)) - p));
    if (!std::isfinite(d)) return std::numeric_limits<double>::infinity();
    worst = std::max(worst, d);
  }
  return worst;
}

std::vector<StepReader::Loop> StepReader::face_loops(const StepEntity& face, long surface) {
  const StepRecord& fr = face.record("ADVANCED_FACE") ? *face.record("ADVANCED_FACE") : record(face, "FACE_SURFACE");
  std::vector<Loop> loops;
  for (const StepValue& bv : list(face, param(face, fr, 1, "bounds"), "bounds")) {
    const StepEntity& bound = entity(ref(face, bv, "bound"), face);
    const bool outer = is(bound, "FACE_OUTER_BOUND");
    const StepRecord& br = outer ? record(bound, "FACE_OUTER_BOUND") : record(bound, "FACE_BOUND");
    const bool orientation = logical(bound, param(bound, br, 2, "orientation"), "orientation");
    const StepEntity& le = entity(ref(bound, br, 1, "loop"), bound);
    if (is(le, "VERTEX_LOOP")) continue;  // a pole or apex: no curve
    Loop loop;
    loop.outer = outer;
    for (const StepValue& ov : list(le, param(le, record(le, "EDGE_LOOP"), 1, "edge list"), "edge list")) {
      const StepEntity& oe = entity(ref(le, ov, "oriented edge"), le);
      // ISO 10303-42 ORIENTED_EDGE (and AP242's SEAM_EDGE, one of them): (name, edge_start,
      // edge_end (both derived: *), edge_element, orientation[, pcurve_reference]).
      const StepRecord& orr = oe.record("SEAM_EDGE") ? *oe.record("SEAM_EDGE") : record(oe, "ORIENTED_EDGE");
      const long ec = ref(oe, orr, 3, "edge element");
      const bool forward = logical(oe, param(oe, orr, 4, "orientation"), "orientation");
      const std::vector<EdgePiece>& pieces = edge(ec, oe);
      const int index = edge_index_.at(ec);
      loop.uses.push_back(index);
      auto add = [&](const EdgePiece& p, bool flip) {
        loop.curves.push_back(flip ? reversed(p.c) : p.c);
        loop.edges.push_back(index);
        loop.pcurves.emplace_back();
        for (const auto& [on, pc] : p.pcurves)
          if (on == surface) loop.pcurves.back().push_back(flip ? reversed(pc) : pc);
      };
      if (forward) {
        for (const EdgePiece& p : pieces) add(p, false);
      } else {
        for (auto it = pieces.rbegin(); it != pieces.rend(); ++it) add(*it, true);
      }
    }
    if (!orientation) reverse(loop);
    if (!loop.curves.empty()) loops.push_back(std::move(loop));
  }
  return loops;
}

void StepReader::reverse(Loop& loop) {
  std::reverse(loop.curves.begin(), loop.curves.end());
  std::reverse(loop.edges.begin(), loop.edges.end());
  std::reverse(loop.pcurves.begin(), loop.pcurves.end());
  for (Curve3& c : loop.curves) c = reversed(c);
  for (auto& options : loop.pcurves)
    for (Curve3& c : options) c = reversed(c);
}

StepReader::FaceJob StepReader::face_job(long id, const StepEntity& from) {
  const StepEntity& e = entity(id, from);
  const StepRecord& fr = e.record("ADVANCED_FACE") ? *e.record("ADVANCED_FACE") : record(e, "FACE_SURFACE");
  FaceJob job;
  job.f.face_id = static_cast<int>(e.id);
  if (const StepValue& n = param(e, fr, 0, "name"); n.kind == Kind::String) job.f.name = n.text;
  job.f.reversed = !logical(e, param(e, fr, 3, "same_sense"), "same_sense");
  try {
    const long surface_id = ref(e, fr, 2, "face geometry");
    job.loops = face_loops(e, surface_id);
    // The bounds run counter-clockwise round the material seen against the face's normal, which is
    // the surface's turned round where same_sense is false: on the surface, they run the other way.
    // (Only a loop going round a closed surface alone, a cap, needs the direction: its material side
    // picks the side of the domain it is closed along.)
    if (job.f.reversed)
      for (Loop& l : job.loops) reverse(l);
    job.fs = surface(surface_id, e);
  } catch (const SkipFace& s) {
    job.skipped = s.reason;
  }
  return job;
}

std::optional<StepReader::GivenLoop> StepReader::given_loop(const Loop& loop, const Surface& s) {
  const size_t n = loop.curves.size();
  for (size_t k = 0; k < n; ++k)
    if (loop.pcurves[k].empty()) return std::nullopt;
  auto start = [](const Curve3& c) { return glm::dvec2(c.points.front()); };
  auto end = [](const Curve3& c) { return glm::dvec2(c.points.back()); };
  // Each first choice, then the nearest continuation; the choice whose gaps sum least.
  double best_gap = std::numeric_limits<double>::infinity();
  std::vector<const Curve3*> best;
  for (const Curve3& first : loop.pcurves[0]) {
    std::vector<const Curve3*> chosen{&first};
    double gap = 0.0;
    for (size_t k = 1; k < n; ++k) {
      const Curve3* pick = nullptr;
      double d = std::numeric_limits<double>::infinity();
      for (const Curve3& o : loop.pcurves[k])
        if (glm::length(start(o) - end(*chosen.back())) < d) d = glm::length(start(o) - end(*chosen.back())), pick = &o;
      chosen.push_back(pick);
      gap += d;
    }
    gap += glm::length(start(*chosen.front()) - end(*chosen.back()));
    if (gap < best_gap) best_gap = gap, best = chosen;
  }
  GivenLoop out;
  out.loop.outer = loop.outer;
  for (size_t k = 0; k < n; ++k) {
    out.gap = std::max(out.gap, trim_gap(*best[k], loop.curves[k], s));
    out.loop.curves.push_back(to_2d(*best[k]));
    out.loop.curves.back().edge = loop.edges[k];
  }
  return out;
}

std::vector<TrimmedSurface> StepReader::build_faces(std::vector<FaceJob>& jobs) {
  std::vector<std::optional<TrimmedSurface>> built(jobs.size());
  parallel_for(jobs.size(), 0, [&](size_t k, int) {
    if (!jobs[k].skipped.empty()) return;
    try {
      built[k] = build_face(jobs[k]);
    } catch (const SkipFace& s) {
      jobs[k].skipped = s.reason;
    }
  });
  std::vector<TrimmedSurface> out;
  for (size_t k = 0; k < jobs.size(); ++k) {
    if (built[k]) {
      out.push_back(std::move(*built[k]));
    } else {
      log_.warnings.push_back(fmt::format("face #{} dropped: {}", jobs[k].f.face_id, jobs[k].skipped));
      dropped_.push_back({fmt::format("#{}", jobs[k].f.face_id), jobs[k].skipped});
    }
  }
  return out;
}

TrimmedSurface StepReader::build_face(FaceJob& job) const {
  const std::vector<Loop>& loops = job.loops;
  const FaceSurface& fs = job.fs;
  TrimmedSurface f = job.f;
  const Analytic& a = fs.analytic;
  if (loops.empty()) {
    if (fs.bspline) {
      f.surface = *fs.bspline;  // the whole surface
      return f;
    }
    // A closed analytic surface without edges (a sphere bounded by a VERTEX_LOOP at a pole, a
    // torus) is the whole surface; the others have no extent.
    if (a.type == Analytic::Sphere) {
      f.surface = a.build({-kPi, -kPi / 2}, {kPi, kPi / 2}).surface;
      return f;
    }
    if (a.type == Analytic::Torus) {
      f.surface = a.build({-kPi, -kPi}, {kPi, kPi}).surface;
      return f;
    }
    throw SkipFace{"an analytic surface without edges has no extent"};
  }
  // Size of the face from its edges: the flattening tolerance scales with it.
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  for (const Loop& l : loops)
    for (const Curve3& c : l.curves)
      for (const glm::dvec3& q : c.points) lo = glm::min(lo, q), hi = glm::max(hi, q);
  const double size = glm::length(hi - lo);
  // Edges within this distance of the surface (trims' surface points within it of the edges) lie on
  // it up to rounding: TrimmedSurface::edge_gap stays 0. The same floor as the IGES reader's, and
  // not the file's stated uncertainty: a writer's 0.01 mm is far above the bounds of answers near
  // the edge, which must carry the gap.
  const double lie_off = kProjectionTolerance * size;
  // The face's edge_gap from the largest gap `off` measured; beyond kStepMaxEdgeGap of the face's size
  // (or not finite) the face is dropped.
  auto set_gap = [&](double off) {
    if (!(off <= kStepMaxEdgeGap * size))
      throw SkipFace{
          fmt::format("its edges lie up to {:.3g} from its surface, more than {:g} % of the face's size {:.3g}", off,
                      100 * kStepMaxEdgeGap, size)};
    f.edge_gap = off > lie_off ? off : 0.0;
  };
  if (!fs.bspline && a.type == Analytic::Plane) {
    // Affine: the control points' plane coordinates (exact, weights kept). The patch spans the
    // curves' box (16 samples per knot span, 1 % wider: an arc of a 90-degree span bulges 0.12 %
    // of its radius between them), not their control points' (a circle's reach 1.41 times out).
    Box2 box;
    for (const Loop& l : loops) {
      TrimLoop t;
      t.outer = l.outer;
      for (size_t k = 0; k < l.curves.size(); ++k) {
        const Curve3& c = l.curves[k];
        Curve2 c2{c.degree, c.knots, {}, c.weights, l.edges[k]};
        for (const glm::dvec3& q : c.points) c2.points.push_back(a.natural(q, std::nullopt));
        const Interval d = curve_domain(c2);
        const int n = 16 * std::max<int>(1, static_cast<int>(c2.points.size()) - c2.degree);
        for (int i = 0; i <= n; ++i) box.add(curve_point(c2, d.min + d.width() * i / n));
        t.curves.push_back(std::move(c2));
      }
      f.loops.push_back(std::move(t));
    }
    const glm::dvec2 margin = 0.01 * (box.hi - box.lo);
    if (!(margin.x > 0 && margin.y > 0)) throw SkipFace{"its edges span no area of its plane"};
    // The edges are projected onto the plane along its normal: the gap is their height above it.
    double off = 0.0;
    for (const Loop& l : loops)
      for (const Curve3& c : l.curves) {
        const Interval d = curve_domain(c);
        for (int i = 0; i <= kGapSamples; ++i)
          off = std::max(off, std::abs(glm::dot(curve_point(c, d.min + d.width() * i / kGapSamples) - a.f.o, a.f.z)));
      }
    set_gap(off);
    f.surface = a.build(box.lo - margin, box.hi + margin).surface;
    if (std::none_of(f.loops.begin(), f.loops.end(), [](const TrimLoop& l) { return l.outer; })) mark_outer(f);
    return f;
  }
  // An analytic surface becomes NURBS first, over the box of its edges' parameters from a coarse
  // pass (angles unwrapped along each loop, loops shifted by whole turns onto the first outer loop's
  // branch), widened by a margin for what the edges reach between samples; its edges are then
  // brought into the NURBS parameters as on a B-spline surface, with the closed-form inverse.
  AnalyticSurface as;
  std::vector<glm::dvec2> loop_start(loops.size(), glm::dvec2(std::numeric_limits<double>::quiet_NaN()));
  if (fs.bspline) {
    as.surface = *fs.bspline;
  } else {
    std::vector<Box2> boxes(loops.size());
    std::vector<std::vector<glm::dvec2>> coarse(loops.size());  // per loop: its samples, NaN u on the axis
    for (size_t li = 0; li < loops.size(); ++li) {
      std::optional<glm::dvec2> prev;
      for (const Curve3& c : loops[li].curves) {
        const Interval d = curve_domain(c);
        const int n = 8 * std::max<int>(1, static_cast<int>(c.points.size()) - c.degree);
        for (int i = 0; i <= n; ++i) {
          const glm::dvec2 uv = a.natural(curve_point(c, d.min + d.width() * i / n), prev);
          if (!std::isfinite(uv.y)) continue;
          coarse[li].push_back(uv);
          if (std::isfinite(uv.x)) prev = uv;
        }
      }
    }
    size_t first = 0;
    for (size_t li = 0; li < loops.size(); ++li)
      if (loops[li].outer) {
        first = li;
        break;
      }
    if (a.u_angular() && !coarse.empty()) {
      std::vector<glm::dvec2*> pts;
      for (glm::dvec2& q : coarse[first]) pts.push_back(&q);
      choose_branches_across_axis(pts, 2 * kPi);
    }
    for (size_t li = 0; li < loops.size(); ++li) {
      // A point on the axis (a pole, an apex) has no angle of its own but its latitude or height
      // belongs to the box: a meridian ending at a pole takes the patch up to it.
      for (const glm::dvec2& uv : coarse[li])
        if (std::isfinite(uv.x)) {
          if (!std::isfinite(loop_start[li].x)) loop_start[li] = uv;
          boxes[li].add(uv);
        }
      if (!std::isfinite(loop_start[li].x)) throw SkipFace{"an edge loop has no parameters on its surface"};
      for (const glm::dvec2& uv : coarse[li])
        if (!std::isfinite(uv.x)) boxes[li].add({boxes[li].lo.x, uv.y});
    }
    const glm::dvec2 centre = boxes[first].centre();
    Box2 all;
    for (size_t li = 0; li < loops.size(); ++li) {
      const glm::dvec2 m = boxes[li].centre();
      glm::dvec2 shift(0.0);
      if (a.u_angular()) shift.x = wrap_near(m.x, centre.x) - m.x;
      if (a.v_periodic()) shift.y = wrap_near(m.y, centre.y) - m.y;
      loop_start[li] += shift;
      all.add(boxes[li].lo + shift);
      all.add(boxes[li].hi + shift);
    }
    // A loop going once round the axis alone bounds a cap: the material reaches the apex of a cone
    // or a pole of a sphere, which no edge touches (a spherical cap bounded by one circle spans
    // no latitude of its own). The patch reaches them, and stops there; the trim keeps the
    // material side.
    int round_loops = 0;
    for (const Box2& b : boxes) round_loops += a.u_angular() && b.hi.x - b.lo.x >= 2 * kPi - 1e-6;
    std::optional<double> apex;
    if (round_loops % 2 == 1 && a.type == Analytic::Sphere) {
      all.lo.y = -kPi / 2, all.hi.y = kPi / 2;
    } else if (round_loops % 2 == 1 && a.type == Analytic::Cone && a.tan_angle != 0.0) {
      apex = -a.r / a.tan_angle;
      all.lo.y = std::min(all.lo.y, *apex), all.hi.y = std::max(all.hi.y, *apex);
    }
    const glm::dvec2 extent = all.hi - all.lo, turn(a.u_angular() ? 2 * kPi : 0.0, a.v_periodic() ? 2 * kPi : 0.0);
    for (int k = 0; k < 2; ++k) {
      const double margin = 0.01 * extent[k] + 1e-9 * size;
      if (turn[k] > 0 && extent[k] + 2 * margin >= turn[k] - 1e-6) {  // a whole turn
        all.lo[k] = 0.5 * (all.lo[k] + all.hi[k]) - kPi;
        all.hi[k] = all.lo[k] + 2 * kPi;
      } else if (a.type != Analytic::Sphere || k == 0) {
        all.lo[k] -= margin, all.hi[k] += margin;
      } else {  // latitude within the poles
        all.lo[k] = std::max(all.lo[k] - margin, -kPi / 2), all.hi[k] = std::min(all.hi[k] + margin, kPi / 2);
      }
    }
    if (apex) (*apex <= all.lo.y + extent.y / 2 ? all.lo.y : all.hi.y) = *apex;  // not past it, onto the other nappe
    if (!(all.hi.x > all.lo.x && all.hi.y > all.lo.y)) throw SkipFace{"its edges span no area of its surface"};
    as = a.build(all.lo, all.hi);
    for (glm::dvec2& q : loop_start) q = as.map(q);
  }
  const double accept = std::max(1e-6 * size, resolution_);
  const Chart chart = fs.bspline ? bspline_chart(as.surface, accept) : analytic_chart(a, as);
  // Each loop sampled along its edges in the surface's parameters, periodic ones unwrapped from
  // sample to sample; chords halved while the surface point of a chord's middle is farther than
  // the tolerance from the surface point of the edge's middle.
  const double tol = std::max(kStepTrimTolerance * size, 1e-300);
  std::vector<std::vector<std::vector<glm::dvec2>>> lines(loops.size());
  std::vector<double> off_loop(loops.size(), 0.0);  // per loop: farthest edge sample from the surface
  // Cubic Hermite pieces in (u, v) through the samples with the edge's (u, v) tangents
  // [Su Sv] (du, dv)' = C'(t) in least squares: few samples for a tight tolerance (error O(h^4));
  // Newton starts from the tangent's prediction.
  // Loops whose every edge has a parameter-space curve on this B-spline surface (files that carry
  // PCURVEs) take those when their surface points lie on the edges within the acceptance distance:
  // exact, no inversion. Otherwise the edges are projected; where the projection lies off too (the
  // edges are not on the surface), the given curves are the face's boundary, as in the writer.
  std::vector<std::optional<GivenLoop>> given(loops.size());
  if (fs.bspline)
    for (size_t li = 0; li < loops.size(); ++li) given[li] = given_loop(loops[li], as.surface);
  auto exact = [&](size_t li) { return given[li] && given[li]->gap <= accept; };
  for (size_t li = 0; li < loops.size(); ++li) {
    if (exact(li)) continue;
    double& off = off_loop[li];
    std::optional<glm::dvec2> prev;
    if (std::isfinite(loop_start[li].x)) prev = loop_start[li];
    for (const Curve3& c : loops[li].curves) {
      const Interval d = curve_domain(c);
      std::vector<glm::dvec2> line;
      struct Sample {
        double t;
        glm::dvec2 uv, duv;
        double gap;  // |S(uv) - C(t)|: how far the edge lies from the surface there
      };
      auto at = [&](double t, const std::optional<glm::dvec2>& near) {
        const std::vector<glm::dvec3> cd = curve_derivatives(c, t, 1);
        Sample out{t, chart.natural(cd[0], near), glm::dvec2(std::numeric_limits<double>::quiet_NaN()), 0.0};
        if (!std::isfinite(out.uv.x) || !std::isfinite(out.uv.y)) return out;
        out.gap = glm::length(chart.point(out.uv) - cd[0]);
        off = std::max(off, out.gap);
        const SurfaceDerivatives sd = chart.derivatives(out.uv);
        const double a11 = glm::dot(sd.su, sd.su), a12 = glm::dot(sd.su, sd.sv), a22 = glm::dot(sd.sv, sd.sv);
        const double b1 = glm::dot(sd.su, cd[1]), b2 = glm::dot(sd.sv, cd[1]), det = a11 * a22 - a12 * a12;
        if (det > 1e-12 * a11 * a22) out.duv = glm::dvec2(a22 * b1 - a12 * b2, a11 * b2 - a12 * b1) / det;
        return out;
      };
      auto predict = [&](const Sample& s, double t) {
        return std::isfinite(s.duv.x) ? s.uv + s.duv * (t - s.t) : s.uv;
      };
      // A piece is kept when the surface point of its Hermite middle lies within the tolerance of
      // the edge's middle, beyond the edge's own distance from the surface at the piece's ends; else
      // the middle is inverted and both halves are tried.
      std::function<void(const Sample&, const Sample&, int)> refine = [&](const Sample& s0, const Sample& s1,
                                                                          int depth) {
        const double h = s1.t - s0.t, tm = 0.5 * (s0.t + s1.t);
        const glm::dvec2 chord = (s1.uv - s0.uv) / h;
        const glm::dvec2 d0 = std::isfinite(s0.duv.x) ? s0.duv : chord, d1 = std::isfinite(s1.duv.x) ? s1.duv : chord;
        const glm::dvec2 mid = 0.5 * (s0.uv + s1.uv) + h / 8 * (d0 - d1);
        const bool finite = std::isfinite(mid.x) && std::isfinite(mid.y);
        if (depth < 12 &&
            (!finite || glm::length(chart.point(mid) - curve_point(c, tm)) > tol + std::max(s0.gap, s1.gap))) {
          const Sample sm = at(tm, predict(s0, tm));
          refine(s0, sm, depth + 1);
          refine(sm, s1, depth + 1);
          return;
        }
        line.insert(line.end(), {s0.uv + h / 3 * d0, s1.uv - h / 3 * d1, s1.uv});
      };
      const int n = 2 * std::max<int>(1, static_cast<int>(c.points.size()) - c.degree);
      Sample s0 = at(d.min, prev);
      line.push_back(s0.uv);
      std::vector<Sample> steps{s0};
      for (int i = 1; i <= n; ++i) {
        const double t1 = d.min + d.width() * i / n;
        const Sample s1 = at(t1, predict(s0, t1));
        refine(s0, s1, 0);
        s0 = s1;
        steps.push_back(s1);
      }
      // The gap between samples as well: the samples above are only as dense as the trim's shape
      // needs. Each starts from the tangent's prediction of the preceding step sample, as above.
      for (int i = 1; i < kGapSamples; ++i) {
        const double t = d.min + d.width() * i / kGapSamples;
        const size_t k = std::min(steps.size() - 1, static_cast<size_t>((t - d.min) / d.width() * n));
        (void)at(t, predict(steps[k], t));
      }
      prev = line.back();
      lines[li].push_back(std::move(line));
    }
  }
  // Per loop: the given curves when exact or when the projection lies off as far as they do or farther
  // (then their gap counts), else the projection (its gap counts).
  double off = 0.0;
  for (size_t li = 0; li < loops.size(); ++li) {
    if (exact(li)) {
      off = std::max(off, given[li]->gap);
      continue;
    }
    if (given[li] && off_loop[li] > lie_off && given[li]->gap <= off_loop[li]) {
      off = std::max(off, given[li]->gap);
      lines[li].clear();
    } else {
      off = std::max(off, off_loop[li]);
      given[li].reset();
    }
  }
  set_gap(off);
  if (!fs.bspline && chart.period.x > 0)
    for (size_t li = 0; li < loops.size(); ++li) unwrap_across_axis(lines[li], chart.period.x, loops[li].outer);
  // Points on an axis (apex, pole) take the angle of their nearest neighbour on their own edge (an
  // edge leaving a pole starts at its own angle, not at the one the edge before arrived with), else
  // of their neighbour along the loop.
  // Per loop, per edge: whether it starts and ends on the axis.
  std::vector<std::vector<std::pair<bool, bool>>> axis_ends(lines.size());
  for (size_t li = 0; li < lines.size(); ++li) {
    auto& loop = lines[li];
    for (auto& l : loop) {
      axis_ends[li].emplace_back(!l.empty() && !std::isfinite(l.front().x), !l.empty() && !std::isfinite(l.back().x));
      const std::vector<glm::dvec2> given_uv = l;
      for (size_t i = 0; i < l.size(); ++i) {
        if (std::isfinite(l[i].x)) continue;
        for (size_t k = 1; k < l.size(); ++k) {
          if (i + k < l.size() && std::isfinite(given_uv[i + k].x)) {
            l[i].x = given_uv[i + k].x;
            break;
          }
          if (k <= i && std::isfinite(given_uv[i - k].x)) {
            l[i].x = given_uv[i - k].x;
            break;
          }
        }
      }
    }
    std::vector<glm::dvec2*> pts;
    for (auto& l : loop)
      for (glm::dvec2& q : l) pts.push_back(&q);
    for (int pass = 0; pass < 2; ++pass)
      for (size_t i = 0; i < pts.size(); ++i)
        if (!std::isfinite(pts[i]->x)) {
          const glm::dvec2* n = i + 1 < pts.size() ? pts[i + 1] : nullptr;
          const glm::dvec2* p = i > 0 ? pts[i - 1] : nullptr;
          if (n && std::isfinite(n->x))
            pts[i]->x = n->x;
          else if (p && std::isfinite(p->x))
            pts[i]->x = p->x;
        }
    for (const glm::dvec2* q : pts)
      if (!std::isfinite(q->x) || !std::isfinite(q->y))
        throw SkipFace{"an edge point has no parameters on its surface"};
  }
  // Loops shifted by whole periods: onto the first (outer) loop's branch for an analytic surface,
  // whose NURBS is then built over them; into the domain of a B-spline surface.
  auto box = [](const std::vector<std::vector<glm::dvec2>>& loop) {
    Box2 b;
    for (const auto& l : loop)
      for (const glm::dvec2& q : l) b.add(q);
    return b;
  };
  {
    const Interval su = surface_domain_u(as.surface), sv = surface_domain_v(as.surface);
    for (auto& loop : lines) {
      const Box2 b = box(loop);
      glm::dvec2 shift(0.0);
      if (chart.period.x > 0)
        shift.x = chart.period.x * std::round((su.min + su.max - b.lo.x - b.hi.x) / (2 * chart.period.x));
      if (chart.period.y > 0)
        shift.y = chart.period.y * std::round((sv.min + sv.max - b.lo.y - b.hi.y) / (2 * chart.period.y));
      for (auto& l : loop)
        for (glm::dvec2& q : l) q += shift;
    }
  }
  f.surface = as.surface;
  const Interval su = surface_domain_u(f.surface), sv = surface_domain_v(f.surface);
  for (size_t li = 0; li < loops.size(); ++li) {
    if (given[li]) {
      f.loops.push_back(std::move(given[li]->loop));
      continue;
    }
    TrimLoop t;
    t.outer = loops[li].outer;
    for (size_t k = 0; k < lines[li].size(); ++k) {
      const auto& line = lines[li][k];
      Curve2 c;
      c.edge = loops[li].edges[k];
      c.degree = 3;
      for (const glm::dvec2& q : line) {
        // Along a periodic direction a loop may run past the domain's side (a circle round a band
        // whose vertex is not on the seam): kept, for wrap_loops_into_domain to cut at the seam.
        c.points.emplace_back(chart.period.x > 0 ? q.x : std::clamp(q.x, su.min, su.max),
                              chart.period.y > 0 ? q.y : std::clamp(q.y, sv.min, sv.max));
      }
      // Knots: 0, 1, ... at the samples, inner ones of multiplicity `degree` (Hermite pieces join C1
      // in shape, their Bezier form is kept).
      const int pieces = static_cast<int>(line.size() - 1) / c.degree;
      c.knots.assign(static_cast<size_t>(c.degree) + 1, 0.0);
      for (int i = 1; i < pieces; ++i)
        c.knots.insert(c.knots.end(), static_cast<size_t>(c.degree), static_cast<double>(i));
      c.knots.insert(c.knots.end(), static_cast<size_t>(c.degree) + 1, static_cast<double>(pieces));
      t.curves.push_back(std::move(c));
      // Two edges meeting at a pole or apex at different angles: the loop runs along the axis's
      // line of the parameter plane between them (the degenerate edge a file leaves out).
      const size_t next = (k + 1) % lines[li].size();
      if (axis_ends[li][k].second && axis_ends[li][next].first && !lines[li][next].empty()) {
        const glm::dvec2 a = end_point(t.curves.back()), b = lines[li][next].front();
        if (std::abs(a.x - b.x) > 1e-9 * chart.period.x) t.curves.push_back(segment_curve(a, {b.x, a.y}));
      }
    }
    f.loops.push_back(std::move(t));
  }
  // Without FACE_OUTER_BOUND, the loop of the largest parameter box is the outer one.
  if (std::none_of(f.loops.begin(), f.loops.end(), [](const TrimLoop& l) { return l.outer; })) mark_outer(f);
  return f;
}

void StepReader::shell_faces(long id, const StepEntity& from, bool reversed, std::vector<FaceJob>& out) {
  const StepEntity& e = entity(id, from);
  const StepRecord* oriented = e.record("ORIENTED_CLOSED_SHELL");
  if (!oriented) oriented = e.record("ORIENTED_OPEN_SHELL");
  if (oriented) {
    // ISO 10303-42: (name, cfs_faces (derived: *), closed / open_shell_element, orientation).
    const bool o = logical(e, param(e, *oriented, 3, "orientation"), "orientation");
    const StepEntity& inner = entity(ref(e, *oriented, 2, "shell element"), e);
    if (is(inner, "ORIENTED_CLOSED_SHELL") || is(inner, "ORIENTED_OPEN_SHELL"))
      fail(e, "is an oriented shell of an oriented shell");
    shell_faces(inner.id, e, reversed != !o, out);
    return;
  }
  const StepRecord* r = e.record("CLOSED_SHELL");
  if (!r) r = e.record("OPEN_SHELL");
  if (!r) fail(e, "is not a CLOSED_SHELL or OPEN_SHELL");
  for (const StepValue& fv : list(e, param(e, *r, 1, "faces"), "faces")) {
    const StepEntity& fe = entity(ref(e, fv, "face"), e);
    bool flip = reversed;
    long face = fe.id;
    if (const StepRecord* o = fe.record("ORIENTED_FACE")) {
      // ISO 10303-42: (name, bounds (derived: *), face_element, orientation).
      flip = flip != !logical(fe, param(fe, *o, 3, "orientation"), "orientation");
      face = ref(fe, *o, 2, "face element");
    }
    FaceJob job = face_job(face, fe);
    job.f.reversed = job.f.reversed != flip;
    out.push_back(std::move(job));
  }
}

std::vector<StepReader::FaceJob> StepReader::solid(const StepEntity& e) {
  std::vector<FaceJob> faces;
  if (const StepRecord* r = e.record("MANIFOLD_SOLID_BREP")) {
    shell_faces(ref(e, *r, 1, "outer shell"), e, false, faces);
    if (const StepRecord* v = e.record("BREP_WITH_VOIDS"))
      for (const StepValue& s : list(e, param(e, *v, e.records.size() == 1 ? 2 : 0, "voids"), "voids"))
        shell_faces(ref(e, s, "void shell"), e, false, faces);
  } else if (const StepRecord* b = e.record("BREP_WITH_VOIDS")) {
    shell_faces(ref(e, *b, 1, "outer shell"), e, false, faces);
    for (const StepValue& s : list(e, param(e, *b, 2, "voids"), "voids"))
      shell_faces(ref(e, s, "void shell"), e, false, faces);
  } else if (const StepRecord* m = e.record("SHELL_BASED_SURFACE_MODEL")) {
    for (const StepValue& s : list(e, param(e, *m, 1, "shells"), "shells"))
      shell_faces(ref(e, s, "shell"), e, false, faces);
  }
  return faces;
}

}  // namespace nurbs::io::step_detail
