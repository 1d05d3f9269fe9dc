#pragma once
/// \file convert.h
/// numpy arrays in and out of the Python module: input checked (shape, finite coordinates within
/// the model's coordinate limit) with ValueError naming the argument and row, output copied into
/// new arrays.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

namespace nurbsgl_python {

namespace py = pybind11;

/// An (N, 3) array of float64 (any array numpy converts) as points; ValueError for another shape, a
/// coordinate that is not finite or of magnitude above `limit` (nurbs::coordinate_limit), naming
/// `what` and the row.
std::vector<glm::dvec3> points_from(const py::handle& array, const char* what, double limit);

/// (N, 3) float64.
py::array_t<double> array3(const std::vector<glm::dvec3>& v);
/// (N, 2) float64.
py::array_t<double> array2(const std::vector<glm::dvec2>& v);

/// A 1-D array of `v` (copied).
template <class T>
py::array_t<T> array1(const std::vector<T>& v) {
  py::array_t<T> out(py::ssize_t(v.size()));
  std::copy(v.begin(), v.end(), out.mutable_data());
  return out;
}

/// A 1-D bool array (std::vector<bool> holds bits).
py::array_t<bool> bools(const std::vector<char>& v);

}  // namespace nurbsgl_python
