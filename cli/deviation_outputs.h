#pragma once
/// \file deviation_outputs.h
/// What `distance --points` writes for a scan on request (queries/distance/deviation_report.h): the
/// points coloured by deviation (PLY), the histogram (PNG, by python/nurbsgl/histogram.py with
/// matplotlib), and the report in JSON and text.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <span>
#include <string>

#include "queries/distance/deviation_report.h"

namespace cli {

/// python/nurbsgl/histogram.py, embedded at build time.
extern const char* const kHistogramScript;

/// Refuses (BadInput) before the work when the Python that draws the histogram cannot import
/// matplotlib: $NURBSGL_PYTHON, else the interpreter found at build time.
void check_histogram_python();

/// Writes the histogram of `report` to `png` (a temporary file renamed), the tolerances drawn as
/// bands. Throws BadInput when the Python fails.
void write_histogram(const std::filesystem::path& png, const queries::DeviationReport& report,
                     std::span<const double> within, const std::string& unit);

/// The report as JSON: signed, min, max, mean, rms, and per tolerance distance, points, share,
/// certain, possible.
[[nodiscard]] nlohmann::json deviation_json(const queries::DeviationReport& report);

/// The report for people: one line of figures, one per tolerance.
void print_deviation(const queries::DeviationReport& report, const std::string& unit);

}  // namespace cli
