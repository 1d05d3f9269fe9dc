#pragma once
/// \file inspection_report.h
/// The inspection's report to hand on (`inspect --report R.html`): one self-contained HTML file
/// that opens with no network. The part's mesh and the scan coloured by deviation in a 3D view
/// (three.js, inlined), a legend of the bands, the histogram (inline SVG), the statistics, the
/// alignment, the model's and scan's names and the certificate: every verdict certain, or how many
/// are undecided and why.
#include <string>

#include "nurbs/triangle_mesh.h"
#include "queries/inspection/inspect.h"

namespace queries {

struct InspectionReportInputs {
  std::string model, scan, unit;  ///< names as the user gave them, the model's unit
  const InspectResult* result = nullptr;
  const nurbs::TriangleMesh* part = nullptr;  ///< the model for display (a coarse tessellation)
  std::string three_js;                       ///< the three.js library's source (a script defining THREE)
  /// The colour scale: green within the first band, full red or blue at |deviation| >= range.
  double range = 0.0;
  size_t max_points = 300000;  ///< points drawn at most (evenly spread over the scan)
};

/// The report's HTML text. Throws std::invalid_argument without a result, a part or three.js.
[[nodiscard]] std::string inspection_report_html(const InspectionReportInputs& in);

}  // namespace queries
