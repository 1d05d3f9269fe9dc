#pragma once
/// \file clash.h
/// The front door of an assembly's clash report: the clearance of every pair of bodies of one
/// model (or of the pairs a caller asks for, so that a batch of pairs can be sharded over processes).
///  - Pairs whose bodies' control-point boxes lie farther apart than ClashOptions::min_clearance are
///    left out before any grid: the boxes hold the surfaces, so their distance is a lower bound of
///    the clearance.
///  - Every other pair is answered as ClearancePair answers `--body-a I --body-b J` on the same file
///    (same tolerance rule, engine choice and judgement of the reader's doubts): the same distance
///    and bound, bit for bit.
///  - The pairs the CPU answers alone run on the hardware threads; a pair that needs the GPU is
///    answered on the calling thread, where the one GL context lives (GL contexts are bound to a
///    thread).
#include <cstddef>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "gpgpu/gpu.h"
#include "nurbs/model_report.h"
#include "queries/distance/clearance_pair.h"
#include "queries/engine.h"

namespace queries {

struct ClashOptions {
  /// Each pair's options: tolerance (relative to the larger body of the pair, as ClearancePair has
  /// it), engine, accept_partial, search, max_samples, face_cull. body_a and body_b are set per pair.
  ClearanceOptions clearance;
  /// Pairs whose boxes lie farther apart are left out (not computed); infinity: every pair computed.
  double min_clearance = std::numeric_limits<double>::infinity();
  /// The pairs (body index, body index) to answer, each with its first body as A; empty: every pair
  /// i < j of the model.
  std::vector<std::pair<int, int>> pairs;
  int threads = 0;  ///< for the pairs the CPU answers; 0: one per hardware thread
  /// Called after each computed pair with (done, total), from any thread, one call at a time.
  std::function<void(size_t done, size_t total)> progress;
};

/// One pair of bodies of a ClashReport.
struct ClashRow {
  int body_a = -1, body_b = -1;  ///< indices into the model's bodies
  std::string name_a, name_b;
  double box_distance = 0.0;  ///< between the bodies' control-point boxes: a lower bound of the clearance
  bool computed = false;      ///< false: left out, its boxes farther apart than min_clearance
  /// The clearance as ClearancePair answers it, faces indexed within each body (computed rows).
  ClearanceAnswer answer;
  std::string engine;  ///< where it ran: "cpu", "gpu" or "cpu and gpu"
  double prepare_seconds = 0.0;

  /// Beyond the report's min_clearance: left out by its boxes, or computed farther apart.
  [[nodiscard]] bool beyond(double min_clearance) const;
};

struct ClashReport {
  /// Intersecting pairs first, then by clearance, then the pairs left out by box distance (by it).
  std::vector<ClashRow> rows;
  size_t bodies = 0;
  size_t computed = 0;         ///< pairs whose clearance is computed
  size_t beyond_boxes = 0;     ///< pairs left out by box distance
  size_t beyond_computed = 0;  ///< computed pairs farther apart than min_clearance
  size_t intersecting = 0;
  size_t uncertified = 0;      ///< computed pairs whose answer is not certified (limited_by_file not among them)
  size_t limited_by_file = 0;  ///< computed pairs over their tolerance only by the file's precision
  size_t cpu_pairs = 0, gpu_pairs = 0;  ///< computed pairs answered on the CPU alone / with the GPU
  double min_clearance = std::numeric_limits<double>::infinity();
  double seconds = 0.0;  ///< wall time of the whole report
  /// The GL context started for the pairs that needed one (`start`), kept so that its profiler can
  /// be read; null when the caller gave one or none is needed.
  std::unique_ptr<gpgpu::Gpu> gpu;

  /// Which pairs' answers are not certified and why, one line each after a first line that counts
  /// them; empty when every computed answer is certified (meets its tolerance, or, unless
  /// `strict`, is over it only by the file's precision).
  [[nodiscard]] std::string failure(bool strict = false) const;
};

/// The clash report of the bodies of `model`. `gpu`: a GL context for the pairs that need one;
/// null: one started by `start` on the calling thread when the first such pair comes (none when
/// the CPU answers every pair). Throws nurbs::RequestError for a model of fewer than two bodies, a
/// pair naming a body the model does not have (or one body twice), or a pair the clearance query
/// refuses (a face whose grid cannot meet the tolerance).
[[nodiscard]] ClashReport clash_report(const nurbs::LoadedModel& model, const ClashOptions& options, gpgpu::Gpu* gpu,
                                       GpuStart start = {});

}  // namespace queries
