// Deformer applied to points: positions and Jacobians, control-point weights, and the
// sensitivities dx/dp of a mesh's vertices (warp/sensitivity.h, with no warp after it).
#include <pybind11/stl.h>

#include <algorithm>

#include "common/errors.h"
#include "py_arrays.h"
#include "py_deformer.h"
#include "py_mesh.h"
#include "warp/sensitivity.h"
#include "warp/warp_points.h"

namespace ffd::py {
namespace {

/// Rows of a CSR matrix: indptr (rows + 1), indices, data.
struct Csr {
  std::vector<std::int64_t> indptr{0}, indices;
  std::vector<double> data;
};

pb::tuple csr_tuple(const Csr& m, std::size_t rows, std::size_t cols) {
  pb::array_t<double> data(static_cast<pb::ssize_t>(m.data.size()));
  std::copy(m.data.begin(), m.data.end(), data.mutable_data());
  return pb::make_tuple(data, int_array(m.indices, {static_cast<pb::ssize_t>(m.indices.size())}),
                        int_array(m.indptr, {static_cast<pb::ssize_t>(m.indptr.size())}), pb::make_tuple(rows, cols));
}

// Each point's weights at `level` (movable points only, ids ascending), one row per point.
// Serial, as the library's sensitivity writer gathers: a deformer's weights may fill
// caches (an octree level is subdivided at its first use).
std::vector<PointWeights> weight_rows(const Deformer& d, int level, const Eigen::Ref<const Eigen::Matrix3Xd>& x) {
  std::vector<PointWeights> rows(static_cast<std::size_t>(x.cols()));
  for (Eigen::Index i = 0; i < x.cols(); ++i) d.movable_weights(level, x.col(i), rows[static_cast<std::size_t>(i)]);
  return rows;
}

// `out` as the result array for `n` points: an (n, 3) C-contiguous writable float64 array
// that does not overlap `in`, or a new one when none is given.
pb::array_t<double> result_array(const pb::object& out, const Float64Array& in, std::size_t n, const std::string& label) {
  if (out.is_none()) return new_vec3_array(n);
  const auto a = out.cast<pb::array>();
  const bool fits = a.dtype().is(pb::dtype::of<double>()) && (a.flags() & pb::array::c_style) && a.writeable() &&
                    a.ndim() == 2 && a.shape(0) == static_cast<pb::ssize_t>(n) && a.shape(1) == 3;
  if (!fits) throw InputError(At{label + "(out=)"}, "out must be a writable C-contiguous float64 array of shape (n, 3)");
  const auto* lo = static_cast<const char*>(a.data());
  const auto* in_lo = reinterpret_cast<const char*>(in.data());
  const std::size_t bytes = 3 * n * sizeof(double);
  if (lo < in_lo + bytes && in_lo < lo + bytes) throw InputError(At{label + "(out=)"}, "out overlaps the points");
  return pb::reinterpret_borrow<pb::array_t<double>>(a);
}

pb::object apply(pb::object self, const Float64Array& points, bool jacobians, int threads, const pb::object& out_arg) {
  PyDeformer& d = self.cast<PyDeformer&>();
  const Eigen::Map<const Eigen::Matrix3Xd> in = point_matrix(points, d.label + "(points)");
  const auto n = static_cast<std::size_t>(in.cols());
  pb::array_t<double> out = result_array(out_arg, points, n, d.label);
  pb::array_t<double> jac = jacobians ? pb::array_t<double>({static_cast<pb::ssize_t>(n), pb::ssize_t{3}, pb::ssize_t{3}})
                                      : pb::array_t<double>();
  Eigen::Map<Eigen::Matrix3Xd> out_map(out.mutable_data(), 3, in.cols());
  double* jac_data = jacobians ? jac.mutable_data() : nullptr;
  with_deformer(d, threads, [&] {
    d.deformer->prepare();
    warp_points(*d.deformer, in, out_map, jac_data);
  });
  if (jacobians) return pb::make_tuple(out, jac);
  return std::move(out);
}

pb::tuple weights(PyDeformer& d, const Float64Array& points, std::optional<int> level, int threads) {
  const Eigen::Map<const Eigen::Matrix3Xd> x = point_matrix(points, d.label + ".weights: points");
  Csr m;
  std::size_t cols = 0;
  with_deformer(d, threads, [&] {
    const int l = d.level_of(level);
    cols = d.deformer->num_points(l);
    for (const PointWeights& row : weight_rows(*d.deformer, l, x)) {
      for (const auto& [id, w] : row) {
        m.indices.push_back(static_cast<std::int64_t>(id));
        m.data.push_back(w);
      }
      m.indptr.push_back(static_cast<std::int64_t>(m.indices.size()));
    }
  });
  return csr_tuple(m, static_cast<std::size_t>(x.cols()), cols);
}

// dx/dp at the vertices: row 3 v + a, column 3 m + a for the m-th movable point, w_j I
// blocks (what `save`'s sensitivity writes for a deformer with no warp after it).
Csr sensitivity_matrix(const Deformer& d, int level, const Eigen::Ref<const Eigen::Matrix3Xd>& x,
                       std::size_t& columns) {
  const std::vector<std::uint32_t> column_of = movable_columns(d, level);
  columns = 3 * static_cast<std::size_t>(std::count_if(column_of.begin(), column_of.end(),
                                                       [](std::uint32_t c) { return c != kFixedPoint; }));
  Csr m;
  for (const PointWeights& row : weight_rows(d, level, x))
    for (std::int64_t a = 0; a < 3; ++a) {
      for (const auto& [id, w] : row) {
        if (w == 0.0 || column_of[id] == kFixedPoint) continue;
        m.indices.push_back(3 * std::int64_t{column_of[id]} + a);
        m.data.push_back(w);
      }
      m.indptr.push_back(static_cast<std::int64_t>(m.indices.size()));
    }
  return m;
}

pb::tuple sensitivity(PyDeformer& d, const pb::object& at, std::optional<int> level, int threads) {
  const bool is_mesh = pb::isinstance<PyMesh>(at);
  Float64Array points;
  if (!is_mesh) points = at.cast<Float64Array>();
  const Mesh* mesh = is_mesh ? &at.cast<const PyMesh&>().scene->mesh : nullptr;
  const Eigen::Map<const Eigen::Matrix3Xd> x =
      mesh ? Eigen::Map<const Eigen::Matrix3Xd>(mesh->positions().data(), 3, mesh->positions().cols())
           : point_matrix(points, d.label + ".sensitivity: mesh");
  Csr m;
  std::size_t columns = 0;
  with_deformer(d, threads, [&] { m = sensitivity_matrix(*d.deformer, d.level_of(level), x, columns); });
  return csr_tuple(m, 3 * static_cast<std::size_t>(x.cols()), columns);
}

}  // namespace

void bind_deformer_evaluation(pb::class_<PyDeformer>& c) {
  c.def("_apply", &apply, pb::arg("points"), pb::arg("jacobians"), pb::arg("threads"), pb::arg("out"),
        "The deformation at (n, 3) points: (n, 3) (into `out` when given), and (n, 3, 3) Jacobians "
        "J[i, r, c] = dF_r/dx_c when asked.");
  c.def("_weights", &weights, pb::arg("points"), pb::arg("level"), pb::arg("threads"),
        "Movable points' weights at (n, 3) points as CSR arrays (data, indices, indptr, shape).");
  c.def("_sensitivity", &sensitivity, pb::arg("mesh"), pb::arg("level"), pb::arg("threads"),
        "dx/dp at a Mesh's vertices or (n, 3) points as CSR arrays (data, indices, indptr, shape).");
}

}  // namespace ffd::py
