#pragma once
/// \file bounds_report.h
/// `nurbsgl info --bounds`: per face, how tight the Filip bound is (bound / sampled second
/// derivatives on the certified grid) and what the knot-aligned grid costs against the former
/// uniform grid at the same tolerance. Text table or JSON; no GPU.
#include <nlohmann/json.hpp>
#include <string>

#include "nurbs/model.h"

namespace cli {

/// The report for every face at `rel_tolerance` x model size: {"tolerance", "faces": [...],
/// "bound_ratio": {"median", "p90", "max", "faces_over_4"}, "samples", "uniform_samples"}.
nlohmann::json bounds_report(const nurbs::Model& model, double rel_tolerance, bool progress);

/// The same as a table for people.
std::string bounds_text(const nlohmann::json& report);

}  // namespace cli
