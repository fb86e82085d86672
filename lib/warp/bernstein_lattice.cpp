#include "warp/bernstein_lattice.h"

#include "common/errors.h"

namespace ffd {

BernsteinLattice::BernsteinLattice(const Parallelepiped& box, Index3 degrees) : Lattice(box, degrees) {
  for (int a = 0; a < 3; ++a)
    if (degrees[a] < 1 || degrees[a] > kMaxDegree)
      throw InputError("a Bernstein lattice's degree per axis must be in 1.." + std::to_string(kMaxDegree));
  init_points({0, 0, 0}, {degrees[0] + 1, degrees[1] + 1, degrees[2] + 1});
}

void BernsteinLattice::movable_span(int axis, int& lo, int& hi) const {
  lo = 0;
  hi = cells_[axis];
}

void BernsteinLattice::bernstein(int n, double u, double* out) {
  const double v = 1 - u;
  out[0] = 1;
  for (int d = 1; d <= n; ++d) {
    out[d] = u * out[d - 1];
    for (int i = d - 1; i >= 1; --i) out[i] = v * out[i] + u * out[i - 1];
    out[0] *= v;
  }
}

void BernsteinLattice::axis_weights(int axis, double u, int& first, double* w, double* dw) const {
  const int n = cells_[axis];
  first = 0;
  bernstein(n, u, w);
  // d/du B_i^n = n (B_{i-1}^{n-1} - B_i^{n-1}).
  double lower[kMaxDegree + 1];
  bernstein(n - 1, u, lower);
  for (int i = 0; i <= n; ++i) {
    const double left = i > 0 ? lower[i - 1] : 0.0;
    const double right = i < n ? lower[i] : 0.0;
    dw[i] = n * (left - right);
  }
}

}  // namespace ffd

namespace ffd {
namespace {
typedef double v4d __attribute__((vector_size(32)));
}  // namespace

void BernsteinLattice::apply(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                             const Eigen::Ref<const Eigen::Matrix3Xd>& in_nrm,
                             const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
                             Eigen::Ref<Eigen::Matrix3Xd> out_nrm, WarpCounts& counts) const {
  const int n0 = cells_[0] + 1, n1 = cells_[1] + 1, n2 = cells_[2] + 1;
  if (packed_stale_) {
    packed_.assign(4 * displacement_.size(), 0.0);
    for (int i = 0; i < n0; ++i)
      for (int j = 0; j < n1; ++j)
        for (int k = 0; k < n2; ++k) {
          const Eigen::Vector3d& d = displacement_[flat({i, j, k})];
          double* slot = packed_.data() + 4 * ((static_cast<std::size_t>(i) * n1 + j) * n2 + k);
          slot[0] = d[0];
          slot[1] = d[1];
          slot[2] = d[2];
        }
    packed_stale_ = false;
  }
  const v4d* P = reinterpret_cast<const v4d*>(packed_.data());
  const Eigen::Matrix3d& inv = box_.inverse_axes();
  const Eigen::Vector3d& origin = box_.origin();
  std::size_t folded = 0, evaluated = 0;
  const std::ptrdiff_t n_ids = static_cast<std::ptrdiff_t>(ids.size());
#pragma omp parallel for schedule(static) reduction(+ : folded, evaluated)
  for (std::ptrdiff_t t = 0; t < n_ids; ++t) {
    const std::uint32_t v = ids[t];
    const Eigen::Vector3d x = in_pos.col(v);
    const Eigen::Vector3d u = inv * (x - origin);
    if (!inside(u)) {
      out_pos.col(v) = x;
      out_nrm.col(v) = in_nrm.col(v);
      continue;
    }
    ++evaluated;
    double w[3][kMaxDegree + 1], dw[3][kMaxDegree + 1];
    int first;
    for (int a = 0; a < 3; ++a) axis_weights(a, u[a], first, w[a], dw[a]);
    // Sederberg & Parry's triple sum, contracted one axis at a time (w, then v, then u).
    v4d value{0, 0, 0, 0}, du{0, 0, 0, 0}, dv{0, 0, 0, 0}, dwv{0, 0, 0, 0};
    for (int i = 0; i < n0; ++i) {
      v4d si{0, 0, 0, 0}, si_v{0, 0, 0, 0}, si_w{0, 0, 0, 0};
      for (int j = 0; j < n1; ++j) {
        const v4d* row = P + (static_cast<std::size_t>(i) * n1 + j) * n2;
        v4d sj{0, 0, 0, 0}, sj_w{0, 0, 0, 0};
        for (int k = 0; k < n2; ++k) {
          sj += w[2][k] * row[k];
          sj_w += dw[2][k] * row[k];
        }
        si += w[1][j] * sj;
        si_v += dw[1][j] * sj;
        si_w += w[1][j] * sj_w;
      }
      value += w[0][i] * si;
      du += dw[0][i] * si;
      dv += w[0][i] * si_v;
      dwv += w[0][i] * si_w;
    }
    out_pos.col(v) = x + Eigen::Vector3d(value[0], value[1], value[2]);
    Eigen::Matrix3d G;  // columns: dD/du, dD/dv, dD/dw in box coordinates
    G << du[0], dv[0], dwv[0], du[1], dv[1], dwv[1], du[2], dv[2], dwv[2];
    const Eigen::Matrix3d J = Eigen::Matrix3d::Identity() + G * inv;
    out_nrm.col(v) = transformed_normal(J, in_nrm.col(v));
    if (J.determinant() <= 0) ++folded;
  }
  counts.evaluated += evaluated;
  counts.folded += folded;
}

}  // namespace ffd
