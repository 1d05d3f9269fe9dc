#pragma once
/// \file model_ops.h
/// Whole-model operations: rigid transforms applied to faces, and the model size (bounding-box
/// diagonal, as ACIS defines its tolerance) that every relative tolerance in nurbsgl refers to.
#include <cmath>
#include <glm/mat4x4.hpp>
#include <string>
#include <vector>

#include "nurbs/model.h"

namespace nurbs {

/// What is wrong with `m` as a rigid transform (rotation + translation, no scale/shear/projection);
/// empty when it is one (tolerance 1e-9 on R^T R = I and det R = 1).
[[nodiscard]] std::vector<std::string> validate_rigid(const glm::dmat4& m);

/// The face moved by the affine map `m`: control points mapped, weights kept, which is exact for
/// NURBS (affine invariance). Trim curves live in (u, v) and do not change.
[[nodiscard]] TrimmedSurface transformed(const TrimmedSurface& face, const glm::dmat4& m);

/// The faces of every body with their body's transform applied, in body order.
[[nodiscard]] std::vector<TrimmedSurface> world_faces(const Model& model);

/// The largest TrimmedSurface::edge_gap of `faces`; 0 when none has one.
[[nodiscard]] double largest_edge_gap(const std::vector<TrimmedSurface>& faces);

/// Axis-aligned box of the model in world coordinates from its surfaces' sample points (a 17 x 17
/// grid per face) united with nothing else: a tight box, slightly inside the true one on curved
/// faces. Returns {min, max}; both zero for an empty model.
struct Box {
  glm::dvec3 min{0.0}, max{0.0};
  [[nodiscard]] double diagonal() const;
};
[[nodiscard]] Box model_box(const Model& model);

/// One face's part of model_box: the box of the 17 x 17 sample points of `s` mapped by `m`.
[[nodiscard]] Box sampled_box(const Surface& s, const glm::dmat4& m = glm::dmat4(1.0));

/// Box of a surface's control points: it holds the surface (convex hull, positive weights).
[[nodiscard]] Box control_box(const Surface& s);

/// Distance between two boxes, and from a box to a point (0 where they meet).
[[nodiscard]] double box_distance(const Box& a, const Box& b);
[[nodiscard]] double box_distance(const Box& b, const glm::dvec3& p);

/// The outward unit normal of face `f` at (u, v): Su x Sv, negated when the face is reversed
/// (TrimmedSurface::reversed); zero where the surface has none (a pole).
[[nodiscard]] glm::dvec3 outward_normal(const TrimmedSurface& f, const glm::dvec2& uv);

/// Model size = model_box(model).diagonal().
[[nodiscard]] double model_size(const Model& model);

/// Smallest and largest model size that relative tolerances can refer to: squares and products of
/// a few tolerances stay far from double underflow and overflow (about 1e-308 and 1.8e308). A model
/// scaled by 1e-300 has size 0 (its diagonal underflows); one at 1e300 an infinite size.
inline constexpr double kMinModelSize = 1e-100;
inline constexpr double kMaxModelSize = 1e100;

/// How far from a model, in model sizes, a query's input (a point, a ray origin, a mesh vertex, a
/// motion's translation) may lie: double arithmetic carries about 16 digits, so a coordinate 1e15
/// sizes away keeps about a tenth of the model size; beyond it distances to the model are noise.
inline constexpr double kCoordinateReach = 1e15;

/// The largest coordinate magnitude a query against a model with box `box` can carry: the box's
/// largest coordinate magnitude plus kCoordinateReach x its diagonal. Input beyond it is bad input.
[[nodiscard]] double coordinate_limit(const Box& box);

/// Whether every coordinate of `p` is finite and of magnitude at most `limit` (coordinate_limit).
[[nodiscard]] inline bool within_coordinate_limit(const glm::dvec3& p, double limit) {
  return std::abs(p.x) <= limit && std::abs(p.y) <= limit && std::abs(p.z) <= limit;
}

/// What is wrong with `size` (a model_size) as the scale of a query's tolerances, empty when it is
/// finite and in [kMinModelSize, kMaxModelSize]. Callers that derive tolerances from the model size
/// refuse the model with this message.
[[nodiscard]] std::vector<std::string> validate_model_size(double size);

/// The model's length unit as text ("mm", "in", "m", ...; "x 2.5 mm" for another scale), from the
/// file's unit (Model::unit_scale_to_mm): what the distances of an answer are in.
[[nodiscard]] std::string unit_name(const Model& model);

}  // namespace nurbs
