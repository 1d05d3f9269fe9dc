#pragma once
/// \file point_batch_trim.h
/// The trim boundary inside the grid cells of a face (Krishnamurthy et al. §5.3), for the batched
/// point projection (point_batch.h): when the closest point of a cell's two triangles lies in a
/// trimmed region, the closest material point of those triangles lies on the trim curve (or on the
/// cell's edges, which its neighbours hold). The face's flattened trim polygons are indexed by the
/// cells their edges cross; inside a cell each edge piece is mapped onto the cell's triangles (the
/// same piecewise-linear interpolant the triangle distances use), where it is a straight segment.
#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>
#include <glm/vec3.hpp>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <unordered_map>
#include <utility>
#include <vector>

#include "nurbs/distance/certified_grid.h"
#include "nurbs/trim_classify.h"

namespace queries {

/// A point of the interpolant with its parameters.
struct TrimEdgeHit {
  double distance = 0.0;
  glm::dvec3 point{0.0};
  glm::dvec2 uv{0.0};
};

using nurbs::BandedTrim;  ///< (the batched projection and the refinement use it)


/// A piece of a trim edge inside one triangle of a grid cell, where it is straight (TrimEdges::pieces).
struct TrimPiece {
  glm::dvec3 a{0.0}, b{0.0};        ///< its ends on the triangle
  glm::dvec2 uv_a{0.0}, uv_b{0.0};  ///< their parameters
  int triangle = 0;                 ///< 0: corners (0, 1, 3); 1: corners (0, 3, 2)
  [[nodiscard]] glm::dvec2 uv_at(double t) const { return uv_a + t * (uv_b - uv_a); }
};

class TrimEdges {
 public:
  TrimEdges() = default;
  /// Indexes the edges of `trim` by the cells of `grid` they cross (both must outlive this).
  TrimEdges(const nurbs::TrimPolygons& trim, const nurbs::ParamGrid& grid);

  /// The closest point to p of the trim edges inside cell (i, j), whose corner points are
  /// corners[k] at (u_{i + (k & 1)}, v_{j + (k >> 1)}); triangles (0, 1, 3) and (0, 3, 2) as
  /// point_distance.cpp cell_hit. Replaces `best` when closer; true if it did. An edge counts only
  /// where material lies beside it (pieces): a hole's edge outside the outer loop bounds no material.
  bool closest(const glm::dvec3& p, int i, int j, const glm::dvec3 corners[4], TrimEdgeHit& best) const;
  /// The pieces of the trim edges inside cell (i, j) (corners as `closest`), appended to `out`:
  /// each edge clipped to the cell and split at the diagonal, mapped onto its triangle. Only edges
  /// with material beside them (is_material 1e-9 of the domain to either side of their middle).
  void pieces(int i, int j, const glm::dvec3 corners[4], std::vector<TrimPiece>& out) const;
  /// The edges of the trim loops inside cell (i, j) in unit-cell coordinates ((u - u_i) / du,
  /// (v - v_j) / dv), clipped to the cell grown by `margin` on every side, appended to `out` as
  /// (s0, t0, s1, t1): every edge, with material beside it or not (a crossing count from a point of
  /// known side tells the side of any point of the cell; glsl/distance/point_batch_trim.frag).
  void segments(int i, int j, double margin, std::vector<glm::dvec4>& out) const;
  /// Whether some edge crosses cell (i, j); if none does, one side holds the whole cell.
  [[nodiscard]] bool crossed(int i, int j) const {
    return grid_ != nullptr && cells_.count(int64_t(j) * grid_->cells_u() + i) > 0;
  }
  /// The cells some edge crosses (pieces or segments may still be empty), as (i, j).
  [[nodiscard]] std::vector<glm::ivec2> cells() const;
  /// nurbs::is_material(trim, uv) (BandedTrim).
  [[nodiscard]] bool is_material(glm::dvec2 uv) const { return banded_.is_material(uv); }

 private:
  /// A piece in unit-cell coordinates (s, t) and in (u, v), on triangle (0, 1, 3) (lower) or (0, 3, 2).
  struct UnitPiece {
    glm::dvec2 st0, st1, uv0, uv1;
    bool lower;
  };
  /// The pieces of cell (i, j) in unit-cell coordinates, computed once per cell and kept (the
  /// batched finishing and the material boxes ask for the same cells again and again); safe to
  /// call from several threads.
  const std::vector<UnitPiece>& unit_pieces(int i, int j) const;
  void compute_unit_pieces(int i, int j, std::vector<UnitPiece>& out) const;
  struct PieceCache {
    std::shared_mutex mutex;
    std::unordered_map<int64_t, std::vector<UnitPiece>> cells;
  };
  const nurbs::TrimPolygons* trim_ = nullptr;
  const nurbs::ParamGrid* grid_ = nullptr;
  double side_step_ = 0.0;
  BandedTrim banded_;
  std::unordered_map<int64_t, std::vector<std::pair<int, int>>> cells_;  ///< cell -> (loop, edge)
  std::shared_ptr<PieceCache> piece_cache_ = std::make_shared<PieceCache>();  ///< (copies share the trim too)
};

}  // namespace queries
