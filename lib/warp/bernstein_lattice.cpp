#include "warp/bernstein_lattice.h"

#include <algorithm>

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

namespace {

using Block = double[BernsteinLattice::kBlock];

// B_i^n at each lane's u, out[i][lane], by bernstein()'s recurrence. Every loop over the
// lanes is `omp simd`: left alone, GCC unrolls the lanes and vectorizes the loop over k.
void bernstein_block(int n, const Block& u, Block* out) {
  constexpr int L = BernsteinLattice::kBlock;
#pragma omp simd
  for (int l = 0; l < L; ++l) out[0][l] = 1;
  for (int d = 1; d <= n; ++d) {
#pragma omp simd
    for (int l = 0; l < L; ++l) out[d][l] = u[l] * out[d - 1][l];
    for (int i = d - 1; i >= 1; --i) {
#pragma omp simd
      for (int l = 0; l < L; ++l) out[i][l] = (1 - u[l]) * out[i][l] + u[l] * out[i - 1][l];
    }
#pragma omp simd
    for (int l = 0; l < L; ++l) out[0][l] *= 1 - u[l];
  }
}

// sum_i B_i(u) sum_j B_j(v) sum_k B_k(w) D_ijk per lane and coordinate, D the displacements
// as [i][j][k][x, y, z]: k, then j, then i, as apply() sums. The three coordinates go
// together, so each basis value is loaded once.
void contract_block(const int* n, const double* D, const Block* const* w, Block (&acc)[3]) {
  constexpr int L = BernsteinLattice::kBlock;
  for (Block& a : acc) std::fill(a, a + L, 0.0);
  for (int i = 0; i <= n[0]; ++i) {
    Block si[3] = {};
    for (int j = 0; j <= n[1]; ++j) {
      const double* row = D + 3 * (static_cast<std::size_t>(i) * (n[1] + 1) + j) * (n[2] + 1);
      Block sj[3] = {};
      for (int k = 0; k <= n[2]; ++k) {
        const double dx = row[3 * k], dy = row[3 * k + 1], dz = row[3 * k + 2];
#pragma omp simd
        for (int l = 0; l < L; ++l) {
          sj[0][l] += w[2][k][l] * dx;
          sj[1][l] += w[2][k][l] * dy;
          sj[2][l] += w[2][k][l] * dz;
        }
      }
      for (int c = 0; c < 3; ++c) {
#pragma omp simd
        for (int l = 0; l < L; ++l) si[c][l] += w[1][j][l] * sj[c][l];
      }
    }
    for (int c = 0; c < 3; ++c) {
#pragma omp simd
      for (int l = 0; l < L; ++l) acc[c][l] += w[0][i][l] * si[c][l];
    }
  }
}

}  // namespace

void BernsteinLattice::apply_positions(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                                       const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos) const {
  const int n[3] = {cells_[0], cells_[1], cells_[2]};
  std::vector<double> D(3 * displacement_.size());  // [i][j][k][x, y, z]
  for (int i = 0; i <= n[0]; ++i)
    for (int j = 0; j <= n[1]; ++j)
      for (int k = 0; k <= n[2]; ++k) {
        const std::size_t slot = (static_cast<std::size_t>(i) * (n[1] + 1) + j) * (n[2] + 1) + k;
        for (int c = 0; c < 3; ++c) D[3 * slot + c] = displacement_[flat({i, j, k})][c];
      }
  const Eigen::Matrix3d& inv = box_.inverse_axes();
  const Eigen::Vector3d& origin = box_.origin();
  const auto blocks = static_cast<std::ptrdiff_t>((ids.size() + kBlock - 1) / kBlock);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t b = 0; b < blocks; ++b) {
    const std::size_t first = static_cast<std::size_t>(b) * kBlock;
    const int lanes = static_cast<int>(std::min<std::size_t>(kBlock, ids.size() - first));
    Block u[3];
    bool in[kBlock];
    for (int l = 0; l < kBlock; ++l) {  // lanes past the end repeat the block's first point
      const Eigen::Vector3d local = inv * (in_pos.col(ids[first + (l < lanes ? l : 0)]) - origin);
      in[l] = inside(local);
      for (int a = 0; a < 3; ++a) u[a][l] = local[a];
    }
    Block w[3][kMaxDegree + 1];
    for (int a = 0; a < 3; ++a) bernstein_block(n[a], u[a], w[a]);
    const Block* const axes[3] = {w[0], w[1], w[2]};
    Block acc[3];
    contract_block(n, D.data(), axes, acc);
    for (int l = 0; l < lanes; ++l) {
      const std::uint32_t v = ids[first + l];
      for (int c = 0; c < 3; ++c) out_pos(c, v) = in[l] ? in_pos(c, v) + acc[c][l] : in_pos(c, v);
    }
  }
}

}  // namespace ffd
