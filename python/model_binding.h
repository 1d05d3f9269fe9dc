#pragma once
/// \file model_binding.h
/// What a Python `nurbsgl.Model` holds: the model as read with its report, and the prepared point
/// queries it has answered with (one per set of options, so that a second call, or a Dask worker's
/// second chunk, skips the preparation).
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <tuple>

#include "nurbs/model_report.h"
#include "queries/distance/point_query.h"

namespace nurbsgl_python {

struct ModelBinding {
  std::shared_ptr<const nurbs::LoadedModel> loaded;
  /// Prepared point queries by (tolerance, per point, engine, accept partial, cache, signed).
  using Key = std::tuple<double, bool, int, bool, bool, bool>;
  std::map<Key, std::shared_ptr<queries::PointQuery>> point_queries;
  std::mutex mutex;  ///< guards point_queries
};

}  // namespace nurbsgl_python
