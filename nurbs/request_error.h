#pragma once
/// \file request_error.h
/// A request the library will not answer as asked: a tolerance below what the model's grids or
/// floats allow, a preparation beyond the memory free, a model without a size for relative
/// tolerances. what() is the whole message, naming the setting and what would work. The command
/// line exits 2 on it; Python raises ValueError.
#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace nurbs {

class RequestError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The range of a tolerance relative to the model size: below 1e-9 no grid could be stored within
/// the sample limits (and float GPU samples carry about 1e-7 of the size anyway).
inline constexpr double kMinRelativeTolerance = 1e-9, kMaxRelativeTolerance = 1.0;

/// Throws RequestError "NAME: VALUE is not a finite number from 1e-9 to 1 (a fraction of the model
/// size)" for a relative tolerance outside the range.
inline void require_relative_tolerance(double value, const std::string& name) {
  if (std::isfinite(value) && value >= kMinRelativeTolerance && value <= kMaxRelativeTolerance) return;
  throw RequestError(fmt::format("{}: {:g} is not a finite number from 1e-9 to 1 (a fraction of the model size)",
                                 name, value));
}

}  // namespace nurbs
