#pragma once
/// \file exact_shapes.h
/// Exact rational NURBS shapes (The NURBS Book §7.5 circle, §8.5 surfaces of revolution): the
/// closed-form references for evaluation tests. Circles use the standard 9-point construction:
/// degree 2, knots {0,0,0,1/4,1/4,1/2,1/2,3/4,3/4,1,1,1}, corner weights sqrt(2)/2.
#include <array>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "nurbs/curve.h"
#include "nurbs/model_report.h"
#include "nurbs/surface.h"
#include "nurbs/trimmed_surface.h"

namespace models {

/// A model of one closed body, a sphere of radius r at the origin (one face), as a reader hands a
/// model to the queries' front doors: its report made, no file. `unit_scale_to_mm`: millimetres per
/// model unit.
[[nodiscard]] nurbs::LoadedModel loaded_sphere(double radius, double unit_scale_to_mm = 1.0);

/// Full circle of radius r around c in the plane, counter-clockwise (ccw) or clockwise, starting at
/// c + (r, 0). Parameter domain [0, 1]. Used as trim loops (holes are clockwise).
[[nodiscard]] nurbs::Curve2 rational_circle_2d(glm::dvec2 centre, double radius, bool ccw);

/// Quarter circle of radius r in the xy plane from (r, 0, 0) to (0, r, 0): degree 2, 3 points,
/// weights {1, sqrt(2)/2, 1}, knots {0,0,0,1,1,1}.
[[nodiscard]] nurbs::Curve3 rational_quarter_circle(double radius);

/// Sphere of `radius` about `centre`: u in [0,1] = longitude (9-point circle), v in [0,1] from the
/// south pole to the north pole (5-point half circle). Degree (2, 2), 9 x 5 control points, normal
/// Su x Sv pointing outwards.
[[nodiscard]] nurbs::Surface rational_sphere(double radius, glm::dvec3 centre = glm::dvec3(0.0));

/// Torus about the z axis through `centre`: tube-centre circle of radius `major` in the xy plane,
/// tube radius `minor` < major. u = around the z axis, v = around the tube; degree (2, 2), 9 x 9.
[[nodiscard]] nurbs::Surface rational_torus(double major, double minor, glm::dvec3 centre = glm::dvec3(0.0));

/// Cylinder of `radius` about the z axis from the base centre up `height`: u around (degree 2,
/// 9 points), v along the axis (degree 1, 2 points).
[[nodiscard]] nurbs::Surface rational_cylinder(double radius, double height, glm::dvec3 base = glm::dvec3(0.0));

/// The square [0, side]^2 of the plane z = 0 as a bilinear surface, u = x, v = y on [0, side]^2.
[[nodiscard]] nurbs::Surface bilinear_square(double side);

/// The bilinear surface over [0, 1]^2 through four corners, P(i, j) = corners[i + 2 j].
[[nodiscard]] nurbs::Surface bilinear_patch(const std::array<glm::dvec3, 4>& corners);

/// The square [0, 2]^2 of the plane z = 0 parametrized by a cubic each way (x = f(u), y = f(v) on
/// [0, 2], f(1) = 1: flat, yet its certified grids have many cells, where a bilinear square has
/// one), with a clockwise circular hole of radius `hole` in (u, v) about (1, 1).
[[nodiscard]] nurbs::TrimmedSurface cubic_square_with_hole(double hole);

}  // namespace models
