#include "python/convert.h"

#include <fmt/format.h>

#include <cmath>

namespace nurbsgl_python {

std::vector<glm::dvec3> points_from(const py::handle& array, const char* what, double limit) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(array);
  if (!a) throw py::value_error(fmt::format("{}: not an array of numbers", what));
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw py::value_error(fmt::format("{}: an (N, 3) array is wanted, not shape ({})", what,
                                      fmt::join(std::vector<py::ssize_t>(a.shape(), a.shape() + a.ndim()), ", ")));
  const double* d = a.data();
  std::vector<glm::dvec3> out(size_t(a.shape(0)));
  for (size_t i = 0; i < out.size(); ++i) {
    out[i] = {d[3 * i], d[3 * i + 1], d[3 * i + 2]};
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(out[i][c]) || std::abs(out[i][c]) > limit)
        throw py::value_error(fmt::format("{}: row {}: coordinate {} is {} (finite, at most {:g} in magnitude for "
                                          "this model, are wanted)",
                                          what, i, c, out[i][c], limit));
  }
  return out;
}

py::array_t<double> array3(const std::vector<glm::dvec3>& v) {
  py::array_t<double> out({py::ssize_t(v.size()), py::ssize_t(3)});
  double* d = out.mutable_data();
  for (size_t i = 0; i < v.size(); ++i) d[3 * i] = v[i].x, d[3 * i + 1] = v[i].y, d[3 * i + 2] = v[i].z;
  return out;
}

py::array_t<double> array2(const std::vector<glm::dvec2>& v) {
  py::array_t<double> out({py::ssize_t(v.size()), py::ssize_t(2)});
  double* d = out.mutable_data();
  for (size_t i = 0; i < v.size(); ++i) d[2 * i] = v[i].x, d[2 * i + 1] = v[i].y;
  return out;
}

py::array_t<bool> bools(const std::vector<char>& v) {
  py::array_t<bool> out(py::ssize_t(v.size()));
  bool* d = out.mutable_data();
  for (size_t i = 0; i < v.size(); ++i) d[i] = v[i] != 0;
  return out;
}

}  // namespace nurbsgl_python
