#include "warp/bernstein_lattice.h"

#include <algorithm>
#include <cmath>

#include "common/errors.h"
#include "common/ordered_select.h"

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

template <int L>
using Lanes = double[L];
using Block = Lanes<BernsteinLattice::kBlock>;
// The Jacobian kernel's block: its dozen partial sums per coordinate fit in registers at
// 8 lanes (one AVX-512 register each), where 16 lanes spill them and zero them in memory.
constexpr int kJacobianLanes = 8;

// B_i^n at each lane's u, out[i][lane], by bernstein()'s recurrence. Every loop over the
// lanes is `omp simd`: left alone, GCC unrolls the lanes and vectorizes the loop over k.
template <int L, int N = 0>
void bernstein_block(int degree, const Lanes<L>& u, Lanes<L>* out) {
  const int n = N > 0 ? N : degree;  // N > 0: the degree, known when compiled
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
// N > 0: every degree is N, known when compiled (unrolled loops, the same sums).
template <int L, int N = 0>
void contract_block(const int* degrees, const double* D, const Lanes<L>* const* w, Lanes<L> (&acc)[3]) {
  const int n[3] = {N > 0 ? N : degrees[0], N > 0 ? N : degrees[1], N > 0 ? N : degrees[2]};
  for (Lanes<L>& a : acc) std::fill(a, a + L, 0.0);
  for (int i = 0; i <= n[0]; ++i) {
    Lanes<L> si[3] = {};
    for (int j = 0; j <= n[1]; ++j) {
      const double* row = D + 3 * (static_cast<std::size_t>(i) * (n[1] + 1) + j) * (n[2] + 1);
      Lanes<L> sj[3] = {};
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

// B_i^n and dB_i^n/du at each lane's u, as axis_weights() computes them one point at a
// time: d/du B_i^n = n (B_{i-1}^{n-1} - B_i^{n-1}).
template <int L>
void bernstein_derivative_block(int n, const Lanes<L>& u, Lanes<L>* w, Lanes<L>* dw) {
  bernstein_block<L>(n, u, w);
  Lanes<L> lower[BernsteinLattice::kMaxDegree + 1];
  bernstein_block<L>(n - 1, u, lower);
  for (int i = 0; i <= n; ++i) {
#pragma omp simd
    for (int l = 0; l < L; ++l) {
      const double left = i > 0 ? lower[i - 1][l] : 0.0;
      const double right = i < n ? lower[i][l] : 0.0;
      dw[i][l] = n * (left - right);
    }
  }
}

// The displacement and its derivatives along the box's axes u, v, w per lane and
// coordinate.
template <int L>
struct BlockSums {
  Lanes<L> value[3], du[3], dv[3], dw[3];
};

// contract_block with the three derivatives: the same sums over k, then j, then i, with
// one axis's basis replaced by its derivative, in the order the derivatives share partial
// sums (sum_k B_k(w) D and sum_k B_k'(w) D, then over j, then over i).
template <int L, int N = 0>
void contract_jacobian_block(const int* degrees, const double* D, const Lanes<L>* const* w, const Lanes<L>* const* dw,
                             BlockSums<L>& out) {
  const int n[3] = {N > 0 ? N : degrees[0], N > 0 ? N : degrees[1], N > 0 ? N : degrees[2]};
  out = BlockSums<L>{};
  for (int i = 0; i <= n[0]; ++i) {
    Lanes<L> si[3] = {}, si_v[3] = {}, si_w[3] = {};
    for (int j = 0; j <= n[1]; ++j) {
      const double* row = D + 3 * (static_cast<std::size_t>(i) * (n[1] + 1) + j) * (n[2] + 1);
      Lanes<L> sj[3] = {}, sj_w[3] = {};
      for (int k = 0; k <= n[2]; ++k)
        for (int c = 0; c < 3; ++c) {
          const double d = row[3 * k + c];
#pragma omp simd
          for (int l = 0; l < L; ++l) {
            sj[c][l] += w[2][k][l] * d;
            sj_w[c][l] += dw[2][k][l] * d;
          }
        }
      for (int c = 0; c < 3; ++c) {
#pragma omp simd
        for (int l = 0; l < L; ++l) {
          si[c][l] += w[1][j][l] * sj[c][l];
          si_v[c][l] += dw[1][j][l] * sj[c][l];
          si_w[c][l] += w[1][j][l] * sj_w[c][l];
        }
      }
    }
    for (int c = 0; c < 3; ++c) {
#pragma omp simd
      for (int l = 0; l < L; ++l) {
        out.value[c][l] += w[0][i][l] * si[c][l];
        out.du[c][l] += dw[0][i][l] * si[c][l];
        out.dv[c][l] += w[0][i][l] * si_v[c][l];
        out.dw[c][l] += w[0][i][l] * si_w[c][l];
      }
    }
  }
}

// A block's points: box coordinates per axis and lane, whether each lies in the box, and
// how many lanes are real (lanes past the end repeat the block's first point).
template <int L>
struct BlockPoints {
  Lanes<L> u[3];
  bool in[L];
  int lanes = 0;
};

// The points ids[first ..] (without ids: the columns first ..) of `count` in all.
template <int L>
void load_block(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const std::uint32_t* ids, std::size_t count,
                std::size_t first, const Parallelepiped& box, BlockPoints<L>& p) {
  p.lanes = static_cast<int>(std::min<std::size_t>(L, count - first));
  for (int l = 0; l < L; ++l) {
    const std::size_t k = first + (l < p.lanes ? l : 0);
    const Eigen::Vector3d local = box.inverse_axes() * (in_pos.col(ids ? ids[k] : k) - box.origin());
    p.in[l] = Lattice::inside(local);
    for (int a = 0; a < 3; ++a) p.u[a][l] = local[a];
  }
}

bool zero_normals(const Eigen::Ref<const Eigen::Matrix3Xd>& nrm, const std::vector<std::uint32_t>& ids, std::size_t first,
                  int lanes) {
  for (int l = 0; l < lanes; ++l)
    if (!nrm.col(ids[first + l]).isZero(0.0)) return false;
  return true;
}

// A block's positions, the value part of contract_jacobian_block (the same sums), its
// normals zero; returns how many of its points lie in the box.
template <int L>
std::size_t positions_block(const int* n, const double* D, const BlockPoints<L>& p,
                            const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const std::vector<std::uint32_t>& ids,
                            std::size_t first, Eigen::Ref<Eigen::Matrix3Xd>& out_pos, Eigen::Ref<Eigen::Matrix3Xd>& out_nrm) {
  Lanes<L> w[3][BernsteinLattice::kMaxDegree + 1];
  for (int a = 0; a < 3; ++a) bernstein_block<L>(n[a], p.u[a], w[a]);
  const Lanes<L>* const axes[3] = {w[0], w[1], w[2]};
  Lanes<L> acc[3];
  contract_block<L>(n, D, axes, acc);
  std::size_t inside = 0;
  for (int l = 0; l < p.lanes; ++l) {
    const std::uint32_t v = ids[first + l];
    inside += p.in[l];
    for (int c = 0; c < 3; ++c) out_pos(c, v) = p.in[l] ? in_pos(c, v) + acc[c][l] : in_pos(c, v);
    out_nrm.col(v).setZero();
  }
  return inside;
}

}  // namespace

std::vector<double> BernsteinLattice::packed_displacements() const {
  const int n[3] = {cells_[0], cells_[1], cells_[2]};
  std::vector<double> D(3 * displacement_.size());  // [i][j][k][x, y, z]
  for (int i = 0; i <= n[0]; ++i)
    for (int j = 0; j <= n[1]; ++j)
      for (int k = 0; k <= n[2]; ++k) {
        const std::size_t slot = (static_cast<std::size_t>(i) * (n[1] + 1) + j) * (n[2] + 1) + k;
        for (int c = 0; c < 3; ++c) D[3 * slot + c] = displacement_[flat({i, j, k})][c];
      }
  return D;
}

void BernsteinLattice::apply(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                             const Eigen::Ref<const Eigen::Matrix3Xd>& in_nrm,
                             const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
                             Eigen::Ref<Eigen::Matrix3Xd> out_nrm, WarpCounts& counts) const {
  const int n[3] = {cells_[0], cells_[1], cells_[2]};
  const std::vector<double> D = packed_displacements();
  const Eigen::Matrix3d& inv = box_.inverse_axes();
  std::size_t folded = 0, evaluated = 0;
  constexpr int L = kJacobianLanes;
  const auto blocks = static_cast<std::ptrdiff_t>((ids.size() + L - 1) / L);
  // Where no point can fold and no normal is to be carried (a point cloud's, or a run's
  // that needs none: zero), the Jacobian is not needed: positions only.
  const bool no_folds = fold_free();
  const bool cubic = is_cubic();
#pragma omp parallel for schedule(static) reduction(+ : folded, evaluated)
  for (std::ptrdiff_t b = 0; b < blocks; ++b) {
    const std::size_t first = static_cast<std::size_t>(b) * L;
    BlockPoints<L> p;
    load_block(in_pos, ids.data(), ids.size(), first, box_, p);
    if (no_folds && zero_normals(in_nrm, ids, first, p.lanes)) {
      evaluated += positions_block<L>(n, D.data(), p, in_pos, ids, first, out_pos, out_nrm);
      continue;
    }
    Lanes<L> w[3][kMaxDegree + 1], dw[3][kMaxDegree + 1];
    for (int a = 0; a < 3; ++a) bernstein_derivative_block<L>(n[a], p.u[a], w[a], dw[a]);
    const Lanes<L>* const axes[3] = {w[0], w[1], w[2]};
    const Lanes<L>* const slopes[3] = {dw[0], dw[1], dw[2]};
    BlockSums<L> s;
    if (cubic)
      contract_jacobian_block<L, 3>(n, D.data(), axes, slopes, s);
    else
      contract_jacobian_block<L>(n, D.data(), axes, slopes, s);
    for (int l = 0; l < p.lanes; ++l) {
      const std::uint32_t v = ids[first + l];
      if (!p.in[l]) {
        out_pos.col(v) = in_pos.col(v);
        out_nrm.col(v) = in_nrm.col(v);
        continue;
      }
      ++evaluated;
      out_pos.col(v) = in_pos.col(v) + Eigen::Vector3d(s.value[0][l], s.value[1][l], s.value[2][l]);
      Eigen::Matrix3d G;  // columns: dD/du, dD/dv, dD/dw in box coordinates
      G << s.du[0][l], s.dv[0][l], s.dw[0][l], s.du[1][l], s.dv[1][l], s.dw[1][l], s.du[2][l], s.dv[2][l], s.dw[2][l];
      const Eigen::Matrix3d J = Eigen::Matrix3d::Identity() + G * inv;
      // A zero normal (a point cloud's) stays zero: transformed_normal's result, without its work.
      const bool normal = !in_nrm.col(v).isZero(0.0);
      out_nrm.col(v) = normal ? transformed_normal(J, in_nrm.col(v)) : Eigen::Vector3d::Zero();
      if (J.determinant() <= 0) ++folded;
    }
  }
  counts.evaluated += evaluated;
  counts.folded += folded;
}

void BernsteinLattice::apply_positions(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                                       const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos) const {
  positions(in_pos, &ids, out_pos);
}

bool BernsteinLattice::apply_without_normals(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                                             const std::vector<std::uint32_t>& ids,
                                             Eigen::Ref<Eigen::Matrix3Xd> out_pos, WarpCounts& counts) const {
  if (!fold_free()) return false;  // apply() counts the folds through the Jacobian
  counts.evaluated += positions(in_pos, &ids, out_pos);
  return true;
}

bool BernsteinLattice::apply_changed(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                                     const Eigen::Ref<const Eigen::Matrix3Xd>* in_nrm, std::vector<std::uint32_t>& ids,
                                     Eigen::Ref<Eigen::Matrix3Xd> out_pos, Eigen::Ref<Eigen::Matrix3Xd>* out_nrm,
                                     WarpCounts& counts) const {
  if (in_nrm || !fold_free()) return false;  // the normals' or the folds' path: the two calls
  if (any_changed_) counts.evaluated += positions(in_pos, nullptr, out_pos, &ids);  // its one piece changed
  return true;
}

std::size_t BernsteinLattice::positions(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                                        const std::vector<std::uint32_t>* ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
                                        std::vector<std::uint32_t>* found) const {
  const int n[3] = {cells_[0], cells_[1], cells_[2]};
  const std::vector<double> D = packed_displacements();
  const std::size_t count = ids ? ids->size() : static_cast<std::size_t>(in_pos.cols());
  const std::uint32_t* const id = ids ? ids->data() : nullptr;
  const auto blocks = static_cast<std::ptrdiff_t>((count + kBlock - 1) / kBlock);
  std::size_t inside = 0;
  const bool cubic = is_cubic();
  ThreadParts parts;  // found, per thread
#pragma omp parallel reduction(+ : inside)
  {
    std::vector<std::uint32_t>* const mine = id ? nullptr : &parts.mine(static_cast<std::int64_t>(count));
#pragma omp for schedule(static)
    for (std::ptrdiff_t b = 0; b < blocks; ++b) {
      const std::size_t first = static_cast<std::size_t>(b) * kBlock;
      BlockPoints<kBlock> p;
      load_block(in_pos, id, count, first, box_, p);
      Block w[3][kMaxDegree + 1];
      const Block* const axes[3] = {w[0], w[1], w[2]};
      Block acc[3];
      if (cubic) {
        for (int a = 0; a < 3; ++a) bernstein_block<kBlock, 3>(3, p.u[a], w[a]);
        contract_block<kBlock, 3>(n, D.data(), axes, acc);
      } else {
        for (int a = 0; a < 3; ++a) bernstein_block<kBlock>(n[a], p.u[a], w[a]);
        contract_block<kBlock>(n, D.data(), axes, acc);
      }
      for (int l = 0; l < p.lanes; ++l) {
        const std::uint32_t v = id ? id[first + l] : static_cast<std::uint32_t>(first + l);
        if (mine) {  // only what changed_points() would list: the points in the box
          if (!p.in[l]) continue;
          mine->push_back(v);
        }
        for (int c = 0; c < 3; ++c) out_pos(c, v) = p.in[l] ? in_pos(c, v) + acc[c][l] : in_pos(c, v);
        inside += p.in[l];
      }
    }
  }
  if (found) parts.append_to(*found);
  return inside;
}

}  // namespace ffd
