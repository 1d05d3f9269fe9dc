#include "nurbs/io/iges_faces.h"

#include <fmt/format.h>

#include <algorithm>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <iterator>
#include <limits>
#include <span>
#include <unordered_map>

#include "nurbs/curve_ends.h"
#include "nurbs/curve_eval.h"
#include "nurbs/homogeneous.h"
#include "nurbs/io/curve_utils.h"
#include "nurbs/io/iges_analytic.h"
#include "nurbs/io/pcurve_gap.h"
#include "nurbs/io/read_error.h"
#include "nurbs/io/step_reader.h"
#include "nurbs/model_ops.h"
#include "nurbs/project_curve.h"
#include "nurbs/surface_eval.h"
#include "nurbs/validate.h"
#include "nurbs/trim_loops.h"
#include "nurbs/trim_seams.h"
#include "nurbs/trim_surface_gaps.h"

namespace nurbs::io {
namespace {

constexpr std::initializer_list<int> kCurveTypes = {100, 102, 104, 110, 126};

void append_reversed(std::vector<Curve2>& loop, std::vector<Curve2> piece, bool reverse) {
  if (reverse) {
    std::reverse(piece.begin(), piece.end());
    for (Curve2& c : piece) c = reversed(c);
  }
  for (Curve2& c : piece) loop.push_back(std::move(c));
}

// Extent of all trim control points (which bounds the curves): the scale of the repair, check and
// flattening tolerances, whatever the file's units. Flattening at 1e-3 of it suffices to orient
// the loops (only the sign of each area matters; flatten_curve cuts every Bézier segment into >= 4
// chords, so small holes keep their sign too). Relative to the curves rather than to the domain, so
// that a damaged file with huge trim coordinates is flattened in a few levels, not to the depth limit.
double trim_extent(const TrimmedSurface& f) {
  glm::dvec2 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  for (const TrimLoop& loop : f.loops)
    for (const Curve2& c : loop.curves)
      for (const glm::dvec2& q : c.points) lo = glm::min(lo, q), hi = glm::max(hi, q);
  const double extent = std::max(hi.x - lo.x, hi.y - lo.y);
  return extent > 0.0 ? extent : 1e3;  // a loop collapsed to a point (or NaN data): any positive value
}

// The boundary of the surface's parameter domain as an outer loop of four lines, counter-clockwise
// from (u0, v0): the outer loop of faces that have holes but no outer boundary in the file.
TrimLoop domain_loop(const Surface& s) {
  const Interval u = surface_domain_u(s), v = surface_domain_v(s);
  const glm::dvec2 corners[4] = {{u.min, v.min}, {u.max, v.min}, {u.max, v.max}, {u.min, v.max}};
  TrimLoop loop;
  loop.outer = true;
  for (int i = 0; i < 4; ++i)
    loop.curves.push_back(to_2d(line_segment({corners[i], 0.0}, {corners[(i + 1) % 4], 0.0})));
  return loop;
}

// A pointer parameter of a face: its index in the record and the entity it names.
struct ParameterRef {
  int index = 0;
  int de = 0;
};

// Throws at the second parameter naming the same entity: a face cannot have the same loop twice,
// and n copies of one loop would make the crossing check's work grow with n^2 or worse.
void reject_repeats(const EntityParams& p, const std::vector<ParameterRef>& refs, const char* what) {
  std::unordered_map<int, int> first;  // entity -> parameter that names it first
  for (const ParameterRef& r : refs)
    if (auto [it, fresh] = first.emplace(r.de, r.index); !fresh)
      p.fail(r.index, fmt::format("{} D{} is the same as at parameter {}: a face cannot have the same loop twice", what,
                                  r.de, it->second));
}

// Distance within which a file's model-space edge lies on the surface along the face's parameter
// curves: kProjectionTolerance of the surface's control-point box diagonal, the tolerance within
// which the reader projects edges given only in model space.
double on_surface_tolerance(const Surface& s) {
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  for (const glm::dvec3& q : s.points) lo = glm::min(lo, q), hi = glm::max(hi, q);
  return kProjectionTolerance * glm::length(hi - lo);
}

}  // namespace

int IgesFaces::surface_pointer(int de) {
  const IgesDirectoryEntry& e = g_.file().entry(de);
  if (e.type == 128) return 0;
  EntityParams p(g_.file(), e);
  return p.pointer(e.type == 143 ? 2 : 1);
}

TrimmedSurface IgesFaces::face(int de, const glm::dmat4& parent) {
  const IgesDirectoryEntry& e = g_.file().entry(de);
  edge_gap_ = 0.0;
  edge_uses_.clear();
  TrimmedSurface f;
  if (e.type == 128) {
    f.surface = g_.surface(de, parent);
  } else if (e.type == 108) {
    f = bounded_plane_face(g_, de, parent);
  } else {
    const glm::dmat4 m = parent * g_.transform(de);
    EntityParams p(g_.file(), e);
    switch (e.type) {
      case 144:
        f = face_144(p, m);
        break;
      case 143:
        f = face_143(p, m);
        break;
      case 510:
        f = face_510(p, m);
        break;
      default:
        g_.fail(de, "is not a face entity (108, 128, 143, 144 or 510)");
    }
  }
  f.face_id = de;
  f.name = e.label;
  f.edge_gap = edge_gap_;
  return f;
}

void IgesFaces::finish(TrimmedSurface& f, double model_size) { finish_trim_loops(f, model_size, log_); }

bool trims_evaluable(const TrimmedSurface& f) {
  return std::all_of(f.loops.begin(), f.loops.end(), [](const TrimLoop& l) {
    return std::all_of(l.curves.begin(), l.curves.end(), [](const Curve2& c) { return validate(c).empty(); });
  });
}

void finish_trim_loops(TrimmedSurface& f, double model_size, IgesReadLog& log) {
  // A curve that is not a valid B-spline (its knots do not fit its points) cannot be evaluated: the
  // repairs, the flattening and the orientation below would read past its arrays. Checked before
  // them and after those that cut curves; the problem is said, and the readers then drop the face
  // (trims_evaluable).
  const auto unusable = [&] {
    if (trims_evaluable(f)) return false;
    for (std::string& problem : check_trim_loops(f, 0.0, 0.0)) {
      if (f.trim_problem.empty()) f.trim_problem = problem;
      log.trim_problems.push_back(std::move(problem));
    }
    return true;
  };
  if (unusable()) return;
  if (!f.loops.empty()) {
    const double extent = trim_extent(f);
    // What a repair moves the face's boundary by, beyond the reader's floor, is the face's edge gap.
    const double face_size = control_box(f.surface).diagonal();
    const auto boundary_moved = [&](double by) {
      if (by > kProjectionTolerance * face_size) f.edge_gap = std::max(f.edge_gap, by);
    };
    log.loops_wrapped += wrap_loops_into_domain(f, kTrimGap3d * model_size, kTrimGapRepair * extent);
    if (unusable()) return;
    log.reordered_loops += reorder_trim_curves(f, kTrimGapRepair * extent);
    // The repairs below close gaps between consecutive curves: the boundary moves by up to the gap
    // in space, which the face's edge gap then carries into every bound near it.
    double joint_gap = 0.0;
    for (const TrimLoop& l : f.loops)
      for (size_t k = 0; k < l.curves.size(); ++k) {
        const glm::dvec2 a = end_point(l.curves[k]), b = start_point(l.curves[(k + 1) % l.curves.size()]);
        if (glm::length(a - b) > kTrimGapRounding * extent)
          joint_gap =
              std::max(joint_gap, glm::length(surface_point(f.surface, a.x, a.y) - surface_point(f.surface, b.x, b.y)));
      }
    boundary_moved(joint_gap);
    log.gaps_closed += repair_trim_gaps(f, kTrimGapRepair * extent, kTrimGapRounding * extent);
    // Loops going round a closed surface jump by its period at the seam: trim_seams.h.
    log.gaps_closed += close_loops_round_seam(f, kTrimGap3d * model_size, kTrimGapRepair * extent);
    // What is left may still be one point on the surface (pole, pcurves fitted short): trim_surface_gaps.h.
    log.gaps_closed += close_gaps_on_surface(f, kTrimGap3d * model_size, kTrimGapRepair * extent);
    // Larger gaps bridged as OpenCASCADE's healing does, up to the edge gap a STEP face may keep (a
    // missing edge): the bridge's length is then the face's edge gap, carried into the bounds near it.
    int bridged = 0;
    boundary_moved(bridge_open_joints(f, kStepMaxEdgeGap * face_size, kTrimGapRepair * extent, bridged));
    log.gaps_closed += bridged;
    if (unusable()) return;
    TrimPolygons polygons = flatten_trim(f, 1e-3 * extent);  // one flattening: check and orient
    log.outer_loops_fixed += fix_outer_loop(f, polygons);
    // A loop that touches itself in space (through a pole, out and back along a degenerate side)
    // within the gaps the repairs above close is valid; its boundary is known that closely.
    double touch = 0.0;
    for (std::string& problem : check_trim_loops(f, kTrimGapRepair * extent, polygons, kTrimGap3d * model_size, &touch)) {
      if (f.trim_problem.empty()) f.trim_problem = problem;
      log.trim_problems.push_back(std::move(problem));
    }
    boundary_moved(touch);
    log.reoriented_loops += orient_trim_loops(f, polygons);
  }
  const bool has_outer = std::any_of(f.loops.begin(), f.loops.end(), [](const TrimLoop& l) { return l.outer; });
  if (!has_outer && !f.loops.empty()) {
    f.loops.insert(f.loops.begin(), domain_loop(f.surface));
    ++log.domain_loops_added;
  }
}

void IgesFaces::no_parameter_curve(int de, const std::string& what) {
  if (options_.skip_faces_without_parameter_curves) throw SkipFace{fmt::format("trim curve D{} {}", de, what)};
  g_.fail(de, what);
}

// 144: PTS, N1 (0 = outer boundary is the domain boundary), N2, PTO, PTI(1..N2). PTS may be a 128
// or an analytic surface (OpenCASCADE 6.5 writes 144s over 120 surfaces of revolution): the 142s'
// parameter curves are then in the analytic surface's IGES (u, v), mapped with it
// (set_analytic_surface).
TrimmedSurface IgesFaces::face_144(const EntityParams& p, const glm::dmat4& m) {
  const int pts = g_.expect(p, 1, {128, 108, 120, 122, 190, 192, 194, 196, 198}, "a surface");
  const bool analytic = is_analytic_surface_type(g_.file().entry(pts).type);
  const int n1 = p.integer(2, 0, 1, "outer boundary flag N1");
  const int n2 = p.integer(3, 0, std::max(0, p.size() - 4), "number of inner boundaries N2");
  const int pto = n1 == 1 ? g_.expect(p, 4, {142}, "a curve on a parametric surface") : p.integer(4);
  std::vector<ParameterRef> loops;  // the 142s, outer first
  if (n1 == 1) loops.push_back({4, pto});
  for (int k = 0; k < n2; ++k) loops.push_back({5 + k, g_.expect(p, 5 + k, {142}, "a curve on a parametric surface")});
  p.check_trailing(4 + n2);
  reject_repeats(p, loops, "loop");
  std::vector<ParameterRef> curves, model_curves;  // per loop BPTR / CPTR, checked before any is expanded
  for (const ParameterRef& l : loops) {
    const auto [bptr, cptr] = curve_142(l.de);
    curves.push_back({l.index, bptr});
    model_curves.push_back({l.index, cptr});
  }
  std::vector<ParameterRef> given;  // BPTR = 0 is no curve: no repeat
  std::copy_if(curves.begin(), curves.end(), std::back_inserter(given),
               [](const ParameterRef& r) { return r.de != 0; });
  reject_repeats(p, given, "the parameter-space curve of loop");
  TrimmedSurface f;
  if (g_.file().entry(pts).type == 108) {
    std::vector<int> des;
    for (const ParameterRef& l : loops) des.push_back(l.de);
    return face_144_on_plane(p, m, pts, des, n1);
  }
  if (analytic) {
    // The range bounds a face without outer boundary; 190-198 have none (unbounded parameters).
    const auto range = n1 == 0 ? analytic_range(g_, pts) : std::nullopt;
    if (n1 == 0 && !range)
      g_.fail(p.entry().de, fmt::format("has no outer boundary (N1 = 0) and its surface D{} "
                                        "is unbounded",
                                        pts));
    for (size_t k = 0; k < curves.size(); ++k) {
      if (curves[k].de == 0)
        no_parameter_curve(loops[k].de, fmt::format("has no parameter-space curve (BPTR = 0) and its face's surface "
                                                    "D{} is analytic (model-space curves are projected onto 128s only)",
                                                    pts));
      f.loops.push_back({g_.parameter_curves(curves[k].de), n1 == 1 && k == 0});
      add_model_curve(f, loops[k].de);
    }
    set_analytic_surface(g_, pts, m, f, range);
    measure_edge_gaps(f, m);
    return f;
  }
  f.surface = g_.surface(pts, m, /*restrict_to_range=*/n1 == 0);  // N1 = 0: the range is the outer boundary
  for (size_t k = 0; k < curves.size(); ++k) {
    TrimLoop loop;
    loop.outer = n1 == 1 && k == 0;
    if (curves[k].de != 0) {
      loop.curves = g_.parameter_curves(curves[k].de);
    } else {
      for (const Curve3& c : g_.curves(model_curves[k].de, m))
        loop.curves.push_back(projected(f.surface, c, loops[k].de));
    }
    f.loops.push_back(std::move(loop));
    if (curves[k].de != 0) add_model_curve(f, loops[k].de);
  }
  measure_edge_gaps(f, m);
  return f;
}

// A 144 on a 108 plane (A x + B y + C z = D; OpenCASCADE writes its planes so): IGES gives a plane
// no parametrization, so its 142s are read by their model-space curves CPTR, projected onto a
// patch of the plane (u, v along default_x of its normal and the normal cross that) over the
// curves' extent on it, widened by a hundredth each way. Unbounded (N1 = 0) or without model-space
// curves, the face is refused.
TrimmedSurface IgesFaces::face_144_on_plane(const EntityParams& p, const glm::dmat4& m, int pts,
                                            const std::vector<int>& loops, int n1) {
  if (n1 == 0) g_.fail(p.entry().de, fmt::format("has no outer boundary (N1 = 0) and its surface D{} is an "
                                                 "unbounded plane",
                                                 pts));
  EntityParams plane(g_.file(), g_.file().entry(pts));
  const glm::dvec3 normal(plane.real(1), plane.real(2), plane.real(3));
  const double length = glm::length(normal);
  if (!(length > 0.0) || !std::isfinite(plane.real(4))) plane.fail(1, "plane normal (A, B, C) has zero length");
  const glm::dmat4 mp = m * g_.transform(pts);
  const glm::dvec3 n = glm::normalize(glm::dvec3(mp * glm::dvec4(normal / length, 0.0)));
  const glm::dvec3 o(mp * glm::dvec4(plane.real(4) / (length * length) * normal, 1.0));
  const glm::dvec3 x = default_x(n), y = glm::cross(n, x);
  std::vector<std::vector<Curve3>> model(loops.size());
  glm::dvec2 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  for (size_t k = 0; k < loops.size(); ++k) {
    EntityParams c(g_.file(), g_.file().entry(loops[k]));
    const int cptr = g_.expect(c, 4, kCurveTypes, "a curve", true);
    if (cptr == 0)
      no_parameter_curve(loops[k], fmt::format("has no model-space curve (CPTR = 0) and its face's surface D{} "
                                                  "is a 108 plane, which IGES gives no parameters",
                                                  pts));
    model[k] = g_.curves(cptr, m);
    for (const Curve3& curve : model[k]) {
      const Interval d = curve_domain(curve);
      for (int i = 0; i <= 64; ++i) {
        const glm::dvec3 q = curve_point(curve, d.min + d.width() * i / 64) - o;
        const glm::dvec2 uv(glm::dot(q, x), glm::dot(q, y));
        lo = glm::min(lo, uv), hi = glm::max(hi, uv);
      }
    }
  }
  if (!(hi.x >= lo.x && hi.y >= lo.y)) g_.fail(p.entry().de, "has no trim curves on its plane");
  const glm::dvec2 margin = 0.01 * (hi - lo) + glm::dvec2(1e-9 * glm::length(hi - lo));
  TrimmedSurface f;
  f.surface = plane_patch(o, x, y, lo - margin, hi + margin);
  for (size_t k = 0; k < loops.size(); ++k) {
    TrimLoop loop;
    loop.outer = n1 == 1 && k == 0;
    for (const Curve3& c : model[k]) loop.curves.push_back(projected(f.surface, c, loops[k]));
    f.loops.push_back(std::move(loop));
  }
  measure_edge_gaps(f, m);
  return f;
}

// The last loop of `f`, the parameter curve BPTR of the 142 `de`, is measured against its
// model-space curve CPTR (IGES 5.3 §4.32: both may be given, PREF saying which the sender
// prefers) once the surface is built (measure_edge_gaps).
void IgesFaces::add_model_curve(const TrimmedSurface& f, int de) {
  const EntityParams& p = parsed(de);
  if (p.pointer(4, true) != 0) edge_uses_.push_back({f.loops.size() - 1, 0, f.loops.back().curves.size(), de, 4});
}

// 142: CRTN, SPTR, BPTR (parameter-space curve), CPTR (model-space curve), PREF; returns BPTR and
// CPTR. BPTR = 0 needs CPTR, which is then projected (projected()).
std::pair<int, int> IgesFaces::curve_142(int de) {
  EntityParams p(g_.file(), g_.file().entry(de));
  p.integer(1);
  p.pointer(2);
  const int bptr = g_.expect(p, 3, kCurveTypes, "a curve", true);
  p.pointer(4, true);  // checked as a curve only when it is needed: a file's BPTR curves stand alone
  const int cptr = bptr == 0 ? g_.expect(p, 4, kCurveTypes, "a curve", true) : 0;
  p.integer(5);
  p.check_trailing(5);
  if (bptr == 0 && cptr == 0)
    no_parameter_curve(de, "has no parameter-space curve (BPTR = 0) and no model-space curve (CPTR = 0)");
  return {bptr, cptr};
}

// Largest distance between the model-space curve `c` and the surface points of its projection `p`
// (degree 1, knots = parameters of `c`), at the vertices and the chord midpoints.
static double projection_gap(const Surface& s, const Curve3& c, const Curve2& p) {
  double gap = 0.0;
  for (size_t i = 0; i < p.points.size(); ++i) {
    const double t = p.knots[i + 1];
    gap = std::max(gap, glm::length(surface_point(s, p.points[i].x, p.points[i].y) - curve_point(c, t)));
    if (i + 1 == p.points.size()) break;
    const glm::dvec2 mid = 0.5 * (p.points[i] + p.points[i + 1]);
    gap = std::max(gap, glm::length(surface_point(s, mid.x, mid.y) - curve_point(c, 0.5 * (t + p.knots[i + 2]))));
  }
  return gap;
}

// A trim curve given only in model space, in the surface's (u, v): project_curve.h within
// kProjectionTolerance of the surface's control-point box diagonal (the model size is not known
// yet; the surface's own size bounds the face's). A curve off the surface by up to kEdgeGapLimit of
// it is projected within twice its distance and kept, its gap measured (TrimmedSurface::edge_gap).
Curve2 IgesFaces::projected(const Surface& s, const Curve3& c, int de) {
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  for (const glm::dvec3& q : s.points) lo = glm::min(lo, q), hi = glm::max(hi, q);
  const double size = glm::length(hi - lo);
  ProjectedCurve pc = project_curve(s, c, kProjectionTolerance * size);
  if (!pc.curve && pc.distance <= kEdgeGapLimit * size) {
    ProjectedCurve loose = project_curve(s, c, std::min(2.0 * pc.distance, kEdgeGapLimit * size));
    if (!loose.curve) loose = project_curve(s, c, kEdgeGapLimit * size);  // samples between the first ones farther
    if (loose.curve) {
      edge_gap_ = std::max(edge_gap_, projection_gap(s, c, *loose.curve));
      pc = std::move(loose);
    }
  }
  if (!pc.curve)
    no_parameter_curve(
        de, fmt::format("has a model-space curve that {} (kept up to {:.3g})", pc.problem, kEdgeGapLimit * size));
  ++log_.curves_projected;
  return std::move(*pc.curve);
}

// 143: TYPE, SPTR, N, BDPT(1..N) pointing to 141s; the first boundary is taken as the outer one.
TrimmedSurface IgesFaces::face_143(const EntityParams& p, const glm::dmat4& m) {
  p.integer(1, 0, 1, "boundary type");
  const int sptr = g_.expect(p, 2, {128}, "a surface");
  const int n = p.integer(3, 1, std::max(1, p.size() - 3), "number of boundaries N");
  std::vector<ParameterRef> bounds;
  for (int k = 0; k < n; ++k) bounds.push_back({4 + k, g_.expect(p, 4 + k, {141}, "a boundary")});
  p.check_trailing(3 + n);
  reject_repeats(p, bounds, "boundary");
  TrimmedSurface f;
  f.surface = g_.surface(sptr, m, /*restrict_to_range=*/false);  // its boundaries bound it
  for (int k = 0; k < n; ++k) f.loops.push_back(loop_141(bounds[static_cast<size_t>(k)].de, k == 0, f.surface, m));
  return f;
}

// 141: TYPE, PREF, SPTR, N, then per curve CRVPT, SENSE (1 same, 2 reversed), K, PSCPT(1..K). A curve
// with K = 0 is its model-space curve CRVPT projected onto the surface (project_curve.h).
TrimLoop IgesFaces::loop_141(int de, bool outer, const Surface& surface, const glm::dmat4& m) {
  EntityParams p(g_.file(), g_.file().entry(de));
  p.integer(1, 0, 1, "boundary type");  // 0: model-space curves only, projected below
  p.integer(2);
  p.pointer(3);
  const int n = p.integer(4, 1, std::max(1, p.size()), "number of curves N");
  TrimLoop loop;
  loop.outer = outer;
  int i = 5;
  for (int c = 0; c < n; ++c) {
    const int crvpt = p.pointer(i, true);
    const int sense = p.integer(i + 1, 1, 2, "orientation SENSE");
    const int k = p.integer(i + 2, 0, std::max(0, p.size() - i - 2), "number of parameter curves K");
    std::vector<Curve2> piece;
    if (k == 0) {  // the model-space curve alone (TYPE 0, or no PSCPT given): projected
      if (crvpt == 0)
        no_parameter_curve(de, fmt::format("curve {} has neither a model-space nor a parameter curve", c + 1));
      for (const Curve3& c3 : g_.curves(g_.expect(p, i, kCurveTypes, "a curve"), m))
        piece.push_back(projected(surface, c3, de));
    }
    for (int j = 0; j < k; ++j)
      for (Curve2& pc : g_.parameter_curves(g_.expect(p, i + 3 + j, kCurveTypes, "a curve")))
        piece.push_back(std::move(pc));
    append_reversed(loop.curves, std::move(piece), sense == 2);
    i += 3 + k;
  }
  p.check_trailing(i - 1);
  return loop;
}

// 510: SURF, N, OF (1 = loop 1 is the outer loop), LOOP(1..N) pointing to 508s.
TrimmedSurface IgesFaces::face_510(const EntityParams& p, const glm::dmat4& m) {
  const int surf = g_.expect(p, 1, {128, 120, 122, 190, 192, 194, 196, 198}, "a surface");
  const int n = p.integer(2, 1, std::max(1, p.size() - 3), "number of loops N");
  const int of = p.integer(3, 0, 1, "outer loop flag OF");
  std::vector<ParameterRef> loops;
  for (int k = 0; k < n; ++k) loops.push_back({4 + k, g_.expect(p, 4 + k, {508}, "a loop")});
  p.check_trailing(3 + n);
  reject_repeats(p, loops, "loop");
  TrimmedSurface f;
  const bool analytic = is_analytic_surface_type(g_.file().entry(surf).type);
  if (!analytic) f.surface = g_.surface(surf, m, /*restrict_to_range=*/of == 0);  // no outer loop: the range bounds it
  const bool plane = g_.file().entry(surf).type == 190;  // OpenCASCADE writes no parameter curves on planes
  double off_plane = 0.0;
  for (int k = 0; k < n; ++k) {
    const int loop = loops[static_cast<size_t>(k)].de;
    f.loops.push_back(plane ? plane_loop(g_, surf, m, loop, of == 1 && k == 0, &off_plane)
                            : loop_508(loop, of == 1 && k == 0, analytic ? nullptr : &f.surface, m, f.loops.size()));
  }
  if (analytic) set_analytic_surface(g_, surf, m, f);  // surface over the loops' IGES (u, v), loops mapped
  if (off_plane > on_surface_tolerance(f.surface)) edge_gap_ = std::max(edge_gap_, off_plane);
  measure_edge_gaps(f, m);
  return f;
}

const EntityParams& IgesFaces::parsed(int de) {
  if (auto it = parsed_.find(de); it != parsed_.end()) return it->second;
  // In place: a file's single 504 may hold every edge of the model, and each use looks it up.
  return parsed_.try_emplace(de, g_.file(), g_.file().entry(de)).first->second;
}

int IgesFaces::edge_list_size(int de) {
  const EntityParams& p = parsed(de);
  return p.integer(1, 1, std::max(1, p.size()), "number of list entries N");
}

// The largest distance between each EdgeUse's model-space curve and the surface along its
// parameter curves (pcurve_gap), into edge_gap_ where beyond on_surface_tolerance. After
// set_analytic_surface: the trims measured are those the face keeps. An edge curve the reader
// cannot convert is not measured (the face stands by its parameter curves, as it would without it).
void IgesFaces::measure_edge_gaps(const TrimmedSurface& f, const glm::dmat4& m) {
  const double floor = on_surface_tolerance(f.surface);
  for (const EdgeUse& u : edge_uses_) {
    std::vector<Curve3> edge;
    try {
      edge = g_.curves(g_.expect(parsed(u.entity), u.parameter, kCurveTypes, "a curve"), m);
    } catch (const UnsupportedEntity&) {
      continue;
    } catch (const ReadError&) {
      continue;
    }
    const std::span<const Curve2> pcurves(f.loops[u.loop].curves.data() + u.first, u.count);
    const double gap = pcurve_gap(f.surface, pcurves, edge, floor);
    if (gap > floor) edge_gap_ = std::max(edge_gap_, gap);
  }
}

// 508 (IGES 5.3 "Loop Entity (Type 508)"): N, then per edge use TYPE (0 edge, 1 vertex), EDGE
// (504/502 list), NDX, OF (1 = the use runs along the edge's model curve, 0 = against it), K, then
// K pairs (ISOP, CURV) of parameter-space curves. OF concerns the model-space curve only: the K
// parameter-space curves already run in the direction of the edge use, one after the other, so the
// loop is their concatenation in file order. That is how OpenCASCADE writes 508s (the teapot's
// unit-square loops: OF = 0, 1, 1, 0 with the pcurves (0,1)->(0,0)->(1,0)->(1,1)->(0,1)) and how
// it reads them (IGESToBRep_BRepEntity::TransferLoop reverses the edge for OF = 0 and its pcurve
// too, which cancels out in the wire). Reversing the pcurves by OF broke 48 of the 96 edge uses of
// gmsh_component8_brep.igs. An edge use with K = 0 has only the edge's model curve: reversed for
// OF = 0, projected onto the surface (project_curve.h).
TrimLoop IgesFaces::loop_508(int de, bool outer, const Surface* surface, const glm::dmat4& m, size_t index) {
  TrimLoop loop;
  loop.outer = outer;
  int c = 0;
  for (const LoopEdgeUse& use : loop_edge_uses(g_, de, [this](int list) { return edge_list_size(list); })) {
    ++c;
    if (use.pcurves.empty() && use.type == 0) {
      // Only the edge's model-space curve (504: CURV, SVP, SV, TVP, TV per edge), used along OF.
      if (surface == nullptr)
        no_parameter_curve(de, fmt::format("edge {} has no parameter-space curve and its face's surface is analytic "
                                           "(only planes take model-space edges)",
                                           c));
      std::vector<Curve3> curves =
          g_.curves(g_.expect(parsed(use.list), 2 + 5 * (use.ndx - 1), kCurveTypes, "a curve"), m);
      if (use.of == 0) {
        std::reverse(curves.begin(), curves.end());
        for (Curve3& c3 : curves) c3 = reversed(c3);
      }
      for (const Curve3& c3 : curves) loop.curves.push_back(projected(*surface, c3, de));
      for (size_t j = loop.curves.size() - curves.size(); j < loop.curves.size(); ++j)
        loop.curves[j].edge = g_.edge_id(use.list, use.ndx);
    }
    std::vector<Curve2> piece;
    for (int pc_de : use.pcurves)
      for (Curve2& pc : g_.parameter_curves(pc_de)) piece.push_back(std::move(pc));
    // The edge's model-space curve (504 CURV) is measured against these once the surface is built.
    if (use.type == 0 && !piece.empty())
      edge_uses_.push_back({index, loop.curves.size(), piece.size(), use.list, 2 + 5 * (use.ndx - 1)});
    for (Curve2& pc : piece) {
      if (use.type == 0) pc.edge = g_.edge_id(use.list, use.ndx);
      loop.curves.push_back(std::move(pc));
    }
  }
  return loop;
}

}  // namespace nurbs::io
