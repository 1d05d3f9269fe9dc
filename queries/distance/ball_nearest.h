#pragma once
/// \file ball_nearest.h
/// The closest-point query of the rolling-ball thickness (nurbs/raycast/ball_thickness.h) by the
/// batched point query (point_batch.h): each centre searched below its `within` less the batch's
/// bound (so the ball sees every point it must, and the descent prunes the cells about r away);
/// an answer with no point within it carries the batch's bound at that centre.
#include "nurbs/raycast/ball_thickness.h"
#include "queries/distance/point_batch.h"

namespace queries {

/// The GPU batch (twin = false) or its CPU twin, point by point (twin = true). `batch` must
/// outlive the function.
[[nodiscard]] nurbs::ray::NearestFn ball_nearest(PointBatch& batch, bool twin = false);

}  // namespace queries
