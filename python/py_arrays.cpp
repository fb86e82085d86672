#include "py_arrays.h"

#include "common/errors.h"

namespace ffd::py {
namespace {

std::string shape_text(const Float64Array& a) {
  std::string s = "(";
  for (pb::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

}  // namespace

Eigen::Map<const Eigen::Matrix3Xd> point_matrix(const Float64Array& points, const std::string& what, bool single) {
  const bool one = single && points.ndim() == 1 && points.shape(0) == 3;
  if (!one && (points.ndim() != 2 || points.shape(1) != 3))
    throw InputError(what + ": expected an (n, 3) array of points" + (single ? " or one point (3,)" : "") +
                     ", got shape " + shape_text(points));
  const Eigen::Index n = one ? 1 : static_cast<Eigen::Index>(points.shape(0));
  return {points.data(), 3, n};
}

std::vector<Eigen::Vector3d> point_list(const Float64Array& points, const std::string& what, bool single) {
  const Eigen::Map<const Eigen::Matrix3Xd> m = point_matrix(points, what, single);
  std::vector<Eigen::Vector3d> out(static_cast<std::size_t>(m.cols()));
  for (Eigen::Index i = 0; i < m.cols(); ++i) out[static_cast<std::size_t>(i)] = m.col(i);
  return out;
}

void check_finite(const std::vector<Eigen::Vector3d>& points, const std::string& what) {
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!points[i].allFinite())
      throw InputError(At{what + "[" + std::to_string(i) + "]"}, "a coordinate is not a finite number");
}

pb::array vec3_view(double* data, std::size_t n, pb::handle owner, bool writeable) {
  pb::array view(pb::dtype::of<double>(), {static_cast<pb::ssize_t>(n), pb::ssize_t{3}},
                 {static_cast<pb::ssize_t>(3 * sizeof(double)), static_cast<pb::ssize_t>(sizeof(double))}, data, owner);
  if (!writeable) pb::detail::array_proxy(view.ptr())->flags &= ~pb::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return view;
}

pb::array_t<double> new_vec3_array(std::size_t n) {
  return pb::array_t<double>({static_cast<pb::ssize_t>(n), pb::ssize_t{3}});
}

}  // namespace ffd::py
