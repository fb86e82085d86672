#include "warp/bspline_lattice.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "common/errors.h"

namespace ffd {

BSplineLattice::BSplineLattice(const Parallelepiped& box, Index3 cells, int degree)
    : Lattice(box, cells), degree_(degree) {
  if (degree < 1 || degree > 3) throw InputError("B-spline degree must be 1, 2 or 3");
  for (int a = 0; a < 3; ++a)
    if (cells[a] < 1) throw InputError("a lattice needs at least one cell per axis");
  const int lo = -(degree / 2);
  init_points({lo, lo, lo}, {cells[0] + degree, cells[1] + degree, cells[2] + degree});
  power_ = power_matrix(degree);
  local_to_world_jac_ = Eigen::Vector3d(cells[0], cells[1], cells[2]).asDiagonal() * box.inverse_axes();
  block_of_.assign(static_cast<std::size_t>(cells[0]) * cells[1] * cells[2], -1);
  stale_.assign(block_of_.size(), 0);
}

Eigen::MatrixXd BSplineLattice::power_matrix(int degree) {
  // Uniform B-spline segment matrices (rows: powers 0..d of the local coordinate).
  switch (degree) {
    case 1:
      return (Eigen::MatrixXd(2, 2) << 1, 0, -1, 1).finished();
    case 2:
      return (Eigen::MatrixXd(3, 3) << 1, 1, 0, -2, 2, 0, 1, -2, 1).finished() / 2.0;
    default:
      return (Eigen::MatrixXd(4, 4) << 1, 4, 1, 0, -3, 0, 3, 0, 3, -6, 3, 0, -1, 3, -3, 1).finished() / 6.0;
  }
}

double BSplineLattice::node(int axis, int i) const {
  const double shift = degree_ % 2 == 0 ? 0.5 : 0.0;
  return (i + shift) / cells_[axis];
}

bool BSplineLattice::movable(const Index3& ijk) const {
  for (int a = 0; a < 3; ++a) {
    int lo, hi;
    movable_span(a, lo, hi);
    if (ijk[a] < lo || ijk[a] > hi) return false;
  }
  return true;
}

void BSplineLattice::movable_span(int axis, int& lo, int& hi) const {
  // Point i is used by cells i + d/2 - d .. i + d/2; all of them must be inside the box.
  movable_span(degree_, cells_[axis], lo, hi);
}

void BSplineLattice::pieces_of_point(int axis, int i, int& lo, int& hi) const {
  lo = std::max(0, i + degree_ / 2 - degree_);
  hi = std::min(cells_[axis] - 1, i + degree_ / 2);
}

void BSplineLattice::axis_weights(int axis, double u, int& first, double* w, double* dw) const {
  int cell;
  double s;
  locate(axis, u, cell, s);
  first = cell - degree_ / 2;
  const int n = degree_ + 1;
  for (int i = 0; i < n; ++i) {
    double value = 0, slope = 0;
    for (int p = degree_; p >= 0; --p) {
      slope = slope * s + value;
      value = value * s + power_(p, i);
    }
    w[i] = value;
    dw[i] = slope * cells_[axis];  // d/du = cells · d/dσ
  }
}

void BSplineLattice::piece_changed(std::size_t piece) {
  if (!stale_[piece]) {
    stale_[piece] = 1;
    stale_list_.push_back(piece);
  }
}

void BSplineLattice::compute_block(std::size_t piece) const {
  const int n = degree_ + 1;
  const std::size_t size = static_cast<std::size_t>(3) * n * n * n;
  const std::size_t stored = static_cast<std::size_t>(4) * n * n * n;
  const Index3 cell = {static_cast<int>(piece % cells_[0]),
                       static_cast<int>((piece / cells_[0]) % cells_[1]),
                       static_cast<int>(piece / (static_cast<std::size_t>(cells_[0]) * cells_[1]))};
  const int off = degree_ / 2;
  // Gather the cell's control displacements; a cell with none keeps no block (identity).
  std::vector<double> g(size);  // [c][i][j][k]
  bool any = false;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const Eigen::Vector3d& d = displacement_[flat({cell[0] - off + i, cell[1] - off + j, cell[2] - off + k})];
        for (int c = 0; c < 3; ++c) g[((c * n + i) * n + j) * n + k] = d[c];
        any = any || !d.isZero(0.0);
      }
  std::int32_t& slot = block_of_[piece];
  if (!any) {
    if (slot >= 0) free_blocks_.push_back(slot);
    slot = -1;
    return;
  }
  if (slot < 0) {
    if (!free_blocks_.empty()) {
      slot = free_blocks_.back();
      free_blocks_.pop_back();
    } else {
      slot = static_cast<std::int32_t>(blocks_.size() / stored);
      blocks_.resize(blocks_.size() + stored);
    }
  }
  // Three mode products with the power matrix: C[c][p][q][r] = Σ M(p,i) M(q,j) M(r,k) g[c][i][j][k].
  std::vector<double> t1(size), t2(size);
  const Eigen::MatrixXd& M = power_;
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int r = 0; r < n; ++r) {
          double acc = 0;
          for (int k = 0; k < n; ++k) acc += M(r, k) * g[((c * n + i) * n + j) * n + k];
          t1[((c * n + i) * n + j) * n + r] = acc;
        }
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < n; ++i)
      for (int q = 0; q < n; ++q)
        for (int r = 0; r < n; ++r) {
          double acc = 0;
          for (int j = 0; j < n; ++j) acc += M(q, j) * t1[((c * n + i) * n + j) * n + r];
          t2[((c * n + i) * n + q) * n + r] = acc;
        }
  double* out = blocks_.data() + static_cast<std::size_t>(slot) * stored;
  for (int c = 0; c < 3; ++c)
    for (int p = 0; p < n; ++p)
      for (int q = 0; q < n; ++q)
        for (int r = 0; r < n; ++r) {
          double acc = 0;
          for (int i = 0; i < n; ++i) acc += M(p, i) * t2[((c * n + i) * n + q) * n + r];
          out[4 * ((p * n + q) * n + r) + c] = acc;  // [p][q][r][xyz_]
        }
  for (std::size_t k = 3; k < stored; k += 4) out[k] = 0;
}

void BSplineLattice::prepare() { refresh_blocks(); }

void BSplineLattice::refresh_blocks() const {
  for (std::size_t piece : stale_list_) {
    compute_block(piece);
    stale_[piece] = 0;
  }
  stale_list_.clear();
}

namespace {

// Four doubles (x, y, z, unused) in one register: the three coordinates of a polynomial
// coefficient are evaluated together (GCC vector extension: AVX with -march=native,
// two SSE2 halves otherwise).
typedef double v4d __attribute__((vector_size(32)));

// Horner's rule over one cell's power coefficients C[p][q][r] (Gain & Dodgson eq. 1 in
// power form) at local coordinates (s, t, r): the displacement V and, with kGrad, its
// partial derivatives (eq. 5-7 in power form) by the derivative-carrying Horner scheme.
template <int D, bool kGrad>
inline void horner(const v4d* C, double s, double t, double r, v4d& V, v4d& Vs, v4d& Vt, v4d& Vr) {
  constexpr int N = D + 1;
  V = Vs = Vt = Vr = v4d{0, 0, 0, 0};
  for (int p = D; p >= 0; --p) {
    v4d b{0, 0, 0, 0}, bt{0, 0, 0, 0}, br{0, 0, 0, 0};
    for (int q = D; q >= 0; --q) {
      const v4d* c = C + (p * N + q) * N;
      v4d a = c[D], ar{0, 0, 0, 0};
      for (int k = D - 1; k >= 0; --k) {
        if (kGrad) ar = ar * r + a;
        a = a * r + c[k];
      }
      if (kGrad) {
        bt = bt * t + b;
        br = br * t + ar;
      }
      b = b * t + a;
    }
    if (kGrad) {
      Vs = Vs * s + V;
      Vt = Vt * s + bt;
      Vr = Vr * s + br;
    }
    V = V * s + b;
  }
}

}  // namespace

template <int D>
void BSplineLattice::evaluate(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                              const Eigen::Ref<const Eigen::Matrix3Xd>* in_nrm,
                              const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd>& out_pos,
                              Eigen::Ref<Eigen::Matrix3Xd>* out_nrm, WarpCounts& counts) const {
  constexpr int N = D + 1;
  constexpr std::size_t kBlock = 4 * N * N * N;
  refresh_blocks();
  const Eigen::Matrix3d& inv = box_.inverse_axes();
  const Eigen::Vector3d& origin = box_.origin();
  const Eigen::Matrix3d K = local_to_world_jac_;
  const v4d* blocks = reinterpret_cast<const v4d*>(blocks_.data());
  std::size_t folded = 0, evaluated = 0;
  const std::ptrdiff_t n_ids = static_cast<std::ptrdiff_t>(ids.size());
  // Vertices in id order (streaming memory access); each looks up its cell's block.
#pragma omp parallel for schedule(static) reduction(+ : folded, evaluated)
  for (std::ptrdiff_t t = 0; t < n_ids; ++t) {
    const std::uint32_t v = ids[t];
    const Eigen::Vector3d x = in_pos.col(v);
    const Eigen::Vector3d u = inv * (x - origin);
    std::int32_t block = -1;
    double local[3];
    if (inside(u)) {
      int cell[3];
      for (int a = 0; a < 3; ++a) {  // Lattice::locate, inlined for the B-spline's cells
        const double sa = u[a] * cells_[a];
        cell[a] = std::clamp(static_cast<int>(std::floor(sa)), 0, cells_[a] - 1);
        local[a] = sa - cell[a];
      }
      block = block_of_[(static_cast<std::size_t>(cell[2]) * cells_[1] + cell[1]) * cells_[0] + cell[0]];
    }
    if (block < 0) {  // outside, or no moved point reaches this cell: identity, bit for bit
      out_pos.col(v) = x;
      if (out_nrm) out_nrm->col(v) = in_nrm->col(v);
      continue;
    }
    ++evaluated;
    const v4d* C = blocks + static_cast<std::size_t>(block) * (kBlock / 4);
    v4d V, Vs, Vt, Vr;
    if (!out_nrm) {
      horner<D, false>(C, local[0], local[1], local[2], V, Vs, Vt, Vr);
      out_pos.col(v) = x + Eigen::Vector3d(V[0], V[1], V[2]);
      continue;
    }
    horner<D, true>(C, local[0], local[1], local[2], V, Vs, Vt, Vr);
    out_pos.col(v) = x + Eigen::Vector3d(V[0], V[1], V[2]);
    Eigen::Matrix3d G;  // columns: dD/dσ, dD/dτ, dD/dρ
    G << Vs[0], Vt[0], Vr[0], Vs[1], Vt[1], Vr[1], Vs[2], Vt[2], Vr[2];
    const Eigen::Matrix3d J = Eigen::Matrix3d::Identity() + G * K;
    const Eigen::Vector3d m = cofactor_times(J, in_nrm->col(v));
    const double len = m.norm();
    out_nrm->col(v) = len > 0 ? Eigen::Vector3d(m / len) : Eigen::Vector3d::Zero();
    if (J.determinant() <= 0) ++folded;
  }
  counts.evaluated += evaluated;
  counts.folded += folded;
}

void BSplineLattice::apply(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                           const Eigen::Ref<const Eigen::Matrix3Xd>& in_nrm,
                           const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
                           Eigen::Ref<Eigen::Matrix3Xd> out_nrm, WarpCounts& counts) const {
  switch (degree_) {
    case 1:
      evaluate<1>(in_pos, &in_nrm, ids, out_pos, &out_nrm, counts);
      break;
    case 2:
      evaluate<2>(in_pos, &in_nrm, ids, out_pos, &out_nrm, counts);
      break;
    default:
      evaluate<3>(in_pos, &in_nrm, ids, out_pos, &out_nrm, counts);
  }
}

void BSplineLattice::apply_positions(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                                     const std::vector<std::uint32_t>& ids,
                                     Eigen::Ref<Eigen::Matrix3Xd> out_pos) const {
  WarpCounts counts;
  switch (degree_) {
    case 1:
      evaluate<1>(in_pos, nullptr, ids, out_pos, nullptr, counts);
      break;
    case 2:
      evaluate<2>(in_pos, nullptr, ids, out_pos, nullptr, counts);
      break;
    default:
      evaluate<3>(in_pos, nullptr, ids, out_pos, nullptr, counts);
  }
}

}  // namespace ffd
