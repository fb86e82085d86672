#include "warp/bspline_lattice.h"

#include <algorithm>
#include <cmath>

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
      slot = static_cast<std::int32_t>(blocks_.size() / size);
      blocks_.resize(blocks_.size() + size);
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
  double* out = blocks_.data() + static_cast<std::size_t>(slot) * size;
  for (int c = 0; c < 3; ++c)
    for (int p = 0; p < n; ++p)
      for (int q = 0; q < n; ++q)
        for (int r = 0; r < n; ++r) {
          double acc = 0;
          for (int i = 0; i < n; ++i) acc += M(p, i) * t2[((c * n + i) * n + q) * n + r];
          out[((c * n + p) * n + q) * n + r] = acc;
        }
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

constexpr int kChunk = 8;  // vertices evaluated together; the inner loops vectorize over them

// Horner's rule over one cell's power coefficients for up to kChunk points:
// value V = Σ_pqr C_pqr σ^p τ^q ρ^r and, with kGrad, its three partial derivatives.
template <int D, bool kGrad>
inline void horner_chunk(const double* C, const double* s, const double* t, const double* r,
                         double (&V)[3][kChunk], double (&S)[3][kChunk], double (&T)[3][kChunk],
                         double (&R)[3][kChunk]) {
  constexpr int N = D + 1;
  for (int c = 0; c < 3; ++c) {
    double v[kChunk] = {}, vs[kChunk] = {}, vt[kChunk] = {}, vr[kChunk] = {};
    for (int p = D; p >= 0; --p) {
      double b[kChunk] = {}, bt[kChunk] = {}, br[kChunk] = {};
      for (int q = D; q >= 0; --q) {
        const double* cpq = C + ((c * N + p) * N + q) * N;
        double a[kChunk], ar[kChunk];
        for (int w = 0; w < kChunk; ++w) {
          a[w] = cpq[D];
          ar[w] = 0;
        }
        for (int k = D - 1; k >= 0; --k)
          for (int w = 0; w < kChunk; ++w) {
            if (kGrad) ar[w] = ar[w] * r[w] + a[w];
            a[w] = a[w] * r[w] + cpq[k];
          }
        for (int w = 0; w < kChunk; ++w) {
          if (kGrad) {
            bt[w] = bt[w] * t[w] + b[w];
            br[w] = br[w] * t[w] + ar[w];
          }
          b[w] = b[w] * t[w] + a[w];
        }
      }
      for (int w = 0; w < kChunk; ++w) {
        if (kGrad) {
          vs[w] = vs[w] * s[w] + v[w];
          vt[w] = vt[w] * s[w] + bt[w];
          vr[w] = vr[w] * s[w] + br[w];
        }
        v[w] = v[w] * s[w] + b[w];
      }
    }
    for (int w = 0; w < kChunk; ++w) {
      V[c][w] = v[w];
      if (kGrad) {
        S[c][w] = vs[w];
        T[c][w] = vt[w];
        R[c][w] = vr[w];
      }
    }
  }
}

}  // namespace

template <int D>
void BSplineLattice::evaluate(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                              const Eigen::Ref<const Eigen::Matrix3Xd>* in_nrm,
                              const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd>& out_pos,
                              Eigen::Ref<Eigen::Matrix3Xd>* out_nrm, WarpCounts& counts) const {
  constexpr int N = D + 1;
  constexpr std::size_t kBlock = 3 * N * N * N;
  refresh_blocks();
  const std::size_t num_cells = block_of_.size();
  const Eigen::Matrix3d& inv = box_.inverse_axes();
  const Eigen::Vector3d& origin = box_.origin();

  // Bin the points by cell (counting sort, stable: deterministic order within a cell).
  // Points outside the box or in cells without displacement are copied unchanged.
  std::vector<std::int32_t> cell_of(ids.size());
  std::vector<double> local(3 * ids.size());
  std::vector<std::uint32_t> count(num_cells + 1, 0);
  const std::ptrdiff_t n_ids = static_cast<std::ptrdiff_t>(ids.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t t = 0; t < n_ids; ++t) {
    const std::uint32_t v = ids[t];
    const Eigen::Vector3d u = inv * (in_pos.col(v) - origin);
    std::int32_t cell = -1;
    if (inside(u)) {
      Index3 p;
      for (int a = 0; a < 3; ++a) locate(a, u[a], p[a], local[3 * t + a]);
      const std::size_t f = flat_piece(p);
      if (block_of_[f] >= 0) cell = static_cast<std::int32_t>(f);
    }
    cell_of[t] = cell;
    if (cell < 0) {
      out_pos.col(v) = in_pos.col(v);
      if (out_nrm) out_nrm->col(v) = in_nrm->col(v);
    }
  }
  for (std::ptrdiff_t t = 0; t < n_ids; ++t)
    if (cell_of[t] >= 0) ++count[cell_of[t] + 1];
  std::vector<std::size_t> active;  // cells with points, in cell order
  for (std::size_t c = 0; c < num_cells; ++c)
    if (count[c + 1]) active.push_back(c);
  for (std::size_t c = 0; c < num_cells; ++c) count[c + 1] += count[c];
  std::vector<std::uint32_t> order(count[num_cells]);
  {
    std::vector<std::uint32_t> next(count.begin(), count.end() - 1);
    for (std::ptrdiff_t t = 0; t < n_ids; ++t)
      if (cell_of[t] >= 0) order[next[cell_of[t]]++] = static_cast<std::uint32_t>(t);
  }

  const Eigen::Matrix3d K = local_to_world_jac_;
  std::size_t folded = 0;
  const std::ptrdiff_t n_active = static_cast<std::ptrdiff_t>(active.size());
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : folded)
  for (std::ptrdiff_t ai = 0; ai < n_active; ++ai) {
    const std::size_t cell = active[ai];
    const double* C = blocks_.data() + static_cast<std::size_t>(block_of_[cell]) * kBlock;
    for (std::uint32_t start = count[cell]; start < count[cell + 1]; start += kChunk) {
      const int m = static_cast<int>(std::min<std::uint32_t>(kChunk, count[cell + 1] - start));
      double s[kChunk] = {}, t[kChunk] = {}, r[kChunk] = {};
      for (int w = 0; w < m; ++w) {
        const std::size_t k = order[start + w];
        s[w] = local[3 * k];
        t[w] = local[3 * k + 1];
        r[w] = local[3 * k + 2];
      }
      double V[3][kChunk], S[3][kChunk], T[3][kChunk], R[3][kChunk];
      if (out_nrm)
        horner_chunk<D, true>(C, s, t, r, V, S, T, R);
      else
        horner_chunk<D, false>(C, s, t, r, V, S, T, R);
      for (int w = 0; w < m; ++w) {
        const std::uint32_t v = ids[order[start + w]];
        out_pos.col(v) = in_pos.col(v) + Eigen::Vector3d(V[0][w], V[1][w], V[2][w]);
        if (!out_nrm) continue;
        Eigen::Matrix3d G;  // dD/dσ, dD/dτ, dD/dρ as columns
        G << S[0][w], T[0][w], R[0][w], S[1][w], T[1][w], R[1][w], S[2][w], T[2][w], R[2][w];
        const Eigen::Matrix3d J = Eigen::Matrix3d::Identity() + G * K;
        const Eigen::Vector3d nn = cofactor_times(J, in_nrm->col(v));
        const double len = nn.norm();
        out_nrm->col(v) = len > 0 ? Eigen::Vector3d(nn / len) : Eigen::Vector3d::Zero();
        if (J.determinant() <= 0) ++folded;
      }
    }
  }
  counts.evaluated += order.size();
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
