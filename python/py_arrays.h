// numpy arrays to and from the library's 3 × n matrices: (n, 3) C-contiguous float64 is
// a 3 × n column-major matrix, so points cross without a copy.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "py_module.h"

namespace ffd::py {

/// A C-contiguous float64 array: the caller's own when it is one (no copy), else a copy.
using Float64Array = pb::array_t<double, pb::array::c_style | pb::array::forcecast>;

/// `points` as a 3 × n matrix over its memory. \throw InputError naming `what` unless its
/// shape is (n, 3), or (3,) when `single` (one point, n = 1).
Eigen::Map<const Eigen::Matrix3Xd> point_matrix(const Float64Array& points, const std::string& what,
                                                bool single = false);
/// The same as a list of points (a copy).
std::vector<Eigen::Vector3d> point_list(const Float64Array& points, const std::string& what, bool single = false);

/// \throw InputError at "what[i]" for the first point with a coordinate that is not finite.
void check_finite(const std::vector<Eigen::Vector3d>& points, const std::string& what);

/// An (n, 3) float64 array over `data` (3 n doubles) that keeps `owner` alive; read-only
/// unless `writeable`.
pb::array vec3_view(double* data, std::size_t n, pb::handle owner, bool writeable);
/// A new (n, 3) float64 array.
pb::array_t<double> new_vec3_array(std::size_t n);

/// An int64 array of `shape` filled from `values`.
template <class T>
pb::array_t<std::int64_t> int_array(const std::vector<T>& values, std::vector<pb::ssize_t> shape) {
  pb::array_t<std::int64_t> out(shape);
  std::int64_t* p = out.mutable_data();
  for (std::size_t i = 0; i < values.size(); ++i) p[i] = static_cast<std::int64_t>(values[i]);
  return out;
}

}  // namespace ffd::py
