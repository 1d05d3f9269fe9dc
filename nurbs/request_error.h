#pragma once
/// \file request_error.h
/// A request the library will not answer as asked: a tolerance below what the model's grids or
/// floats allow, a preparation beyond the memory free, a model without a size for relative
/// tolerances. what() is the whole message, naming the setting and what would work. The command
/// line exits 2 on it; Python raises ValueError.
#include <stdexcept>

namespace nurbs {

class RequestError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace nurbs
