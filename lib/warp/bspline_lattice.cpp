#include "warp/bspline_lattice.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#endif

#include "common/errors.h"
#include "common/madd.h"
#include "common/ordered_select.h"

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
  const std::size_t size = static_cast<std::size_t>(3) * n * n * n;  // also a block's size
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
          double acc = 0;  // +0.0: a sum from it is never -0.0 (horner_lanes relies on it)
          for (int i = 0; i < n; ++i) acc += M(p, i) * t2[((c * n + i) * n + q) * n + r];
          out[((c * n + p) * n + q) * n + r] = acc;  // [xyz][p][q][r]
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

// Eight doubles, one per vertex: the lanes of the evaluation (GCC vector extension: one
// AVX-512 register with FFD_ARCH=native on an AVX-512 CPU, AVX or SSE2 pieces elsewhere).
// Every lane does exactly the arithmetic of its vertex alone, so no result depends on
// which vertices share a register, on the order of the ids or on the thread count.
constexpr int kLanes = 8;
typedef double v8d __attribute__((vector_size(kLanes * sizeof(double))));

// Horner's rule over one cell's power coefficients C[xyz][p][q][r] (Gain & Dodgson eq. 1
// in power form) at eight points (s, t, r) of that cell, coordinate by coordinate: the
// displacement V and, with kGrad, its partial derivatives (eq. 5-7 in power form) by the
// derivative-carrying Horner scheme. The coefficients are broadcast: all lanes share the cell.
template <int D, bool kGrad>
inline void horner_lanes(const double* C, v8d s, v8d t, v8d r, v8d V[3], v8d Vs[3], v8d Vt[3], v8d Vr[3]) {
  constexpr int N = D + 1;
  const v8d zero = {};
  for (int c = 0; c < 3; ++c) {
    v8d v = zero, vs = zero, vt = zero, vr = zero;
    for (int p = D; p >= 0; --p) {
      v8d b = zero, bt = zero, br = zero;
      for (int q = D; q >= 0; --q) {
        const double* cq = C + ((c * N + p) * N + q) * N;
        // The leading coefficient broadcast: no block holds -0.0 (compute_block's sums start
        // at +0.0), so this is 0 + cq[D] bit for bit, without a scalar add per coefficient.
        v8d a = {cq[D], cq[D], cq[D], cq[D], cq[D], cq[D], cq[D], cq[D]}, ar = zero;
        for (int k = D - 1; k >= 0; --k) {
          if (kGrad) ar = ar * r + a;
          a = a * r + cq[k];
        }
        if (kGrad) {
          bt = bt * t + b;
          br = br * t + ar;
        }
        b = b * t + a;
      }
      if (kGrad) {
        vs = vs * s + v;
        vt = vt * s + bt;
        vr = vr * s + br;
      }
      v = v * s + b;
    }
    V[c] = v;
    Vs[c] = vs;
    Vt[c] = vt;
    Vr[c] = vr;
  }
}

// m = cof(J) n (cofactor_times) and det J for eight lanes, with J = I + G K: G's columns are
// the displacement's partials (dD/dσ, dD/dτ, dD/dρ), K the local-to-world Jacobian dσ/dx.
inline void cofactor_lanes(const v8d Vs[3], const v8d Vt[3], const v8d Vr[3], const Eigen::Matrix3d& K,
                           const v8d n[3], v8d m[3], v8d& det) {
  v8d J[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) J[i][j] = (i == j ? 1.0 : 0.0) + (Vs[i] * K(0, j) + Vt[i] * K(1, j) + Vr[i] * K(2, j));
  const auto cross = [&J](int a, int b, v8d out[3]) {  // column a × column b
    for (int i = 0; i < 3; ++i) out[i] = J[(i + 1) % 3][a] * J[(i + 2) % 3][b] - J[(i + 2) % 3][a] * J[(i + 1) % 3][b];
  };
  v8d c0[3], c1[3], c2[3];
  cross(1, 2, c0);
  cross(2, 0, c1);
  cross(0, 1, c2);
  for (int i = 0; i < 3; ++i) m[i] = c0[i] * n[0] + c1[i] * n[1] + c2[i] * n[2];
  det = J[0][0] * c0[0] + J[1][0] * c0[1] + J[2][0] * c0[2];
}

constexpr int kChunkSize = 2048;  // ids located and evaluated together

// Where points lie among a lattice's cells, for the ids [begin, end) of a chunk: the flat
// cell (-1 outside the box), the local coordinates in it, as Lattice::locate finds them,
// and the position.
struct ChunkCells {
  // Rows padded so that the same entry of two rows is not a multiple of 4 KiB apart: a
  // store to one row and a load from another would falsely wait on each other.
  static constexpr int kRow = kChunkSize + 24;
  std::int64_t flat[kRow];
  double local[3][kRow];
  double x[3][kRow];
};

// One chunk of a thread's vertices, sorted by cell so that the eight lanes of a register
// share their cell's coefficients, in structure-of-arrays form so that a register loads
// its lanes straight from memory. Cells are numbered in the order they first appear (a
// small open-addressing table: a chunk of a mesh's vertices spans few cells).
struct CellChunk {
  static constexpr int kSize = kChunkSize, kSlots = 1024, kMaxCells = kSlots / 2;
  // As located, in id order: the vertex, its cell here and its entry in ChunkCells.
  int count = 0, cells = 0;
  std::uint32_t vertex[kSize];
  std::uint16_t cell_of[kSize];
  std::uint16_t located[kSize];
  // Sorted by cell (kLanes of padding: a cell's last register reads into the next cell).
  std::int32_t cell_block[kMaxCells];
  int cell_start[kMaxCells + 1];
  std::uint32_t sorted_vertex[kSize + kLanes];
  double sorted[9][kSize + kLanes];  // local σ τ ρ, position x y z, normal x y z
  std::int32_t slot_block[kSlots];
  std::uint16_t slot_cell[kSlots];

  CellChunk() {
    for (std::int32_t& b : slot_block) b = -1;
    for (double* row : sorted) std::fill(row, row + kSize + kLanes, 0.0);
  }
  /// Whether block numbers index the table directly (a lattice of at most kSlots blocks:
  /// no probing, whose unpredictable branches cost more than the rest of a point's locate).
  bool direct = false;

  /// Adds a vertex in `block`, located at ChunkCells entry `at`; false (nothing added)
  /// when full.
  bool add(std::uint32_t v, std::int32_t block, std::ptrdiff_t at) {
    if (count == kSize) return false;
    int h = direct ? block : static_cast<int>((static_cast<std::uint32_t>(block) * 2654435761u) >> 22);
    if (!direct)
      while (slot_block[h] != -1 && slot_block[h] != block) h = (h + 1) % kSlots;
    if (slot_block[h] == -1) {
      if (cells == kMaxCells) return false;
      slot_block[h] = block;
      slot_cell[h] = static_cast<std::uint16_t>(cells);
      cell_block[cells++] = block;
    }
    vertex[count] = v;
    cell_of[count] = slot_cell[h];
    located[count] = static_cast<std::uint16_t>(at);
    ++count;
    return true;
  }
  void sort(const ChunkCells& where, const Eigen::Ref<const Eigen::Matrix3Xd>* nrm);
  void clear() {
    if (direct)
      for (int c = 0; c < cells; ++c) slot_block[cell_block[c]] = -1;
    else
      for (int h = 0; h < kSlots && cells > 0; ++h) slot_block[h] = -1;
    count = cells = 0;
  }
};

// Counting sort of the chunk by cell (stable), gathering each vertex's local coordinates,
// position and normal.
void CellChunk::sort(const ChunkCells& where, const Eigen::Ref<const Eigen::Matrix3Xd>* nrm) {
  std::fill(cell_start, cell_start + cells + 1, 0);
  for (int i = 0; i < count; ++i) ++cell_start[cell_of[i] + 1];
  for (int c = 0; c < cells; ++c) cell_start[c + 1] += cell_start[c];
  int fill[kMaxCells];
  for (int c = 0; c < cells; ++c) fill[c] = cell_start[c];
  for (int i = 0; i < count; ++i) {
    const int at = fill[cell_of[i]]++;
    const std::uint32_t v = vertex[i];
    const int from = located[i];
    sorted_vertex[at] = v;
    for (int a = 0; a < 3; ++a) {
      sorted[a][at] = where.local[a][from];
      sorted[3 + a][at] = where.x[a][from];
      if (nrm) sorted[6 + a][at] = (*nrm)(a, v);
    }
  }
}

// What one evaluation reads and writes. out_nrm null: positions only.
struct CellKernel {
  const double* blocks;    // per block: [xyz][p][q][r]
  std::size_t block_size;  // doubles per block
  Eigen::Matrix3d K;       // dσ/dx
  Eigen::Ref<Eigen::Matrix3Xd>& out_pos;
  Eigen::Ref<Eigen::Matrix3Xd>* out_nrm;
  bool count_folds = false;  // without normals: still count det J <= 0 (out_nrm null)
};

v8d load_lanes(const double* p) {
  v8d x;
  std::memcpy(&x, p, sizeof x);
  return x;
}

// Evaluates the sorted chunk's vertices at [at, at + lanes) (all in one cell, lanes <= 8):
// positions, and normals carried by the cofactor of the Jacobian. The lanes past `lanes`
// hold the next cell's vertices or padding; their results are dropped.
template <int D>
void evaluate_lanes(const CellKernel& k, const CellChunk& chunk, int cell, int at, int lanes, std::size_t& folded) {
  const double* C = k.blocks + static_cast<std::size_t>(chunk.cell_block[cell]) * k.block_size;
  const v8d s = load_lanes(chunk.sorted[0] + at), t = load_lanes(chunk.sorted[1] + at),
            r = load_lanes(chunk.sorted[2] + at);
  v8d V[3], Vs[3], Vt[3], Vr[3], m[3], det, len;
  if (k.out_nrm || k.count_folds)
    horner_lanes<D, true>(C, s, t, r, V, Vs, Vt, Vr);
  else
    horner_lanes<D, false>(C, s, t, r, V, Vs, Vt, Vr);
  if (k.count_folds) {  // det J as the normals' kernel computes it, for a zero normal
    const v8d zero = {};
    const v8d n[3] = {zero, zero, zero};
    cofactor_lanes(Vs, Vt, Vr, k.K, n, m, det);
  }
  if (k.out_nrm) {
    const v8d n[3] = {load_lanes(chunk.sorted[6] + at), load_lanes(chunk.sorted[7] + at),
                      load_lanes(chunk.sorted[8] + at)};
    cofactor_lanes(Vs, Vt, Vr, k.K, n, m, det);
    const v8d len2 = m[0] * m[0] + m[1] * m[1] + m[2] * m[2];
    for (int i = 0; i < kLanes; ++i) len[i] = std::sqrt(len2[i]);
    for (int c = 0; c < 3; ++c) m[c] = m[c] / len;
  }
  for (int c = 0; c < 3; ++c) V[c] += load_lanes(chunk.sorted[3 + c] + at);
  for (int i = 0; i < lanes; ++i) {
    const std::uint32_t v = chunk.sorted_vertex[at + i];
    k.out_pos.col(v) = Eigen::Vector3d(V[0][i], V[1][i], V[2][i]);
    if (k.count_folds) folded += det[i] <= 0;
    if (!k.out_nrm) continue;
    k.out_nrm->col(v) = len[i] > 0 ? Eigen::Vector3d(m[0][i], m[1][i], m[2][i]) : Eigen::Vector3d::Zero();
    folded += det[i] <= 0;
  }
}

// Evaluates the chunk cell by cell, eight vertices at a time, and empties it. With
// `no_folds` (Lattice::fold_free) and every normal of the chunk zero (a point cloud's, or
// a run's that needs none), the Jacobian is not needed: positions only (the same
// values), normals zero, and no fold to count.
template <int D>
void evaluate_chunk(const CellKernel& k, CellChunk& chunk, const ChunkCells& where,
                    const Eigen::Ref<const Eigen::Matrix3Xd>* in_nrm, bool no_folds, std::size_t& folded) {
  bool positions_only = false;
  if (k.out_nrm && no_folds) {
    positions_only = true;
    for (int i = 0; i < chunk.count && positions_only; ++i) positions_only = in_nrm->col(chunk.vertex[i]).isZero(0.0);
  }
  const CellKernel positions{k.blocks, k.block_size, k.K, k.out_pos, nullptr, false};
  const CellKernel& kernel = positions_only ? positions : k;
  chunk.sort(where, kernel.out_nrm ? in_nrm : nullptr);
  for (int cell = 0; cell < chunk.cells; ++cell)
    for (int at = chunk.cell_start[cell]; at < chunk.cell_start[cell + 1]; at += kLanes)
      evaluate_lanes<D>(kernel, chunk, cell, at, std::min(kLanes, chunk.cell_start[cell + 1] - at), folded);
  if (positions_only)
    for (int i = 0; i < chunk.count; ++i) k.out_nrm->col(chunk.vertex[i]).setZero();
  chunk.clear();
}

// What locating reads: the box (inverse axes, origin) and the cells per axis.
struct CellGrid {
  Eigen::Matrix3d inv;
  Eigen::Vector3d origin;
  int cells[3];
};

// Box coordinates, cell and local coordinates of one point from its offset d = x - origin,
// into out's entry i. The box coordinates are Eigen's inv * (x - origin) written out
// operation for operation (rows 0 and 1 as its two-lane packet products, row 2 as its
// scalar one, as gcc and clang compile them), so each value is the one Eigen's product
// gives; the rest is Lattice::piece_at, whose floor, clamp and subtraction are exact.
void locate_cell(const CellGrid& grid, std::ptrdiff_t i, ChunkCells& out) {
  const Eigen::Matrix3d& m = grid.inv;
  const double d[3] = {out.local[0][i], out.local[1][i], out.local[2][i]};
  const double u[3] = {madd(m(0, 2), d[2], madd(m(0, 1), d[1], m(0, 0) * d[0])),
                       madd(m(1, 2), d[2], madd(m(1, 1), d[1], m(1, 0) * d[0])),
                       madd(m(2, 0), d[0], madd(m(2, 1), d[1], m(2, 2) * d[2]))};
  if (!Lattice::inside(Eigen::Vector3d(u[0], u[1], u[2]))) {
    out.flat[i] = -1;
    return;
  }
  int c[3];
  for (int a = 0; a < 3; ++a) {
    const double s = u[a] * grid.cells[a];
    c[a] = Lattice::piece_at(s, grid.cells[a]);
    out.local[a][i] = s - c[a];
  }
  out.flat[i] = (static_cast<std::int64_t>(c[2]) * grid.cells[1] + c[1]) * grid.cells[0] + c[0];
}

#if defined(__AVX2__) && defined(__FMA__)
// locate_cell for four points at a time, from entry i on; returns the first entry it left.
// The same operations lane by lane: fused multiply-adds round once, as std::fma does;
// the cell clamp in doubles is the integer clamp's value for every point inside the box.
std::ptrdiff_t locate_cells_avx2(const CellGrid& grid, std::ptrdiff_t i, std::ptrdiff_t n, ChunkCells& out) {
  __m256d m[3][3], count[3], last[3];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m[r][c] = _mm256_set1_pd(grid.inv(r, c));
  for (int a = 0; a < 3; ++a) {
    count[a] = _mm256_set1_pd(grid.cells[a]);
    last[a] = _mm256_set1_pd(grid.cells[a] - 1);
  }
  const __m256d lo = _mm256_set1_pd(-kBoxTolerance), hi = _mm256_set1_pd(1 + kBoxTolerance), zero = _mm256_setzero_pd();
  for (; i + 4 <= n; i += 4) {
    const __m256d d0 = _mm256_loadu_pd(out.local[0] + i), d1 = _mm256_loadu_pd(out.local[1] + i),
                  d2 = _mm256_loadu_pd(out.local[2] + i);
    const __m256d u[3] = {
        _mm256_fmadd_pd(m[0][2], d2, _mm256_fmadd_pd(m[0][1], d1, _mm256_mul_pd(m[0][0], d0))),
        _mm256_fmadd_pd(m[1][2], d2, _mm256_fmadd_pd(m[1][1], d1, _mm256_mul_pd(m[1][0], d0))),
        _mm256_fmadd_pd(m[2][0], d0, _mm256_fmadd_pd(m[2][1], d1, _mm256_mul_pd(m[2][2], d2)))};
    __m256d in = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    for (int a = 0; a < 3; ++a)
      in = _mm256_and_pd(in, _mm256_and_pd(_mm256_cmp_pd(u[a], lo, _CMP_GE_OQ), _mm256_cmp_pd(u[a], hi, _CMP_LE_OQ)));
    __m256d cell[3];
    for (int a = 0; a < 3; ++a) {
      const __m256d s = _mm256_and_pd(in, _mm256_mul_pd(u[a], count[a]));  // 0 outside the box
      cell[a] = _mm256_min_pd(_mm256_max_pd(_mm256_floor_pd(s), zero), last[a]);
      _mm256_storeu_pd(out.local[a] + i, _mm256_sub_pd(s, cell[a]));
    }
    const __m256d flat = _mm256_add_pd(
        _mm256_mul_pd(_mm256_add_pd(_mm256_mul_pd(cell[2], count[1]), cell[1]), count[0]), cell[0]);  // exact
    const __m256d flat_or_none = _mm256_blendv_pd(_mm256_set1_pd(-1), flat, in);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out.flat + i), _mm256_cvtepi32_epi64(_mm256_cvttpd_epi32(flat_or_none)));
  }
  return i;
}
#endif

#ifdef __AVX512F__
// locate_cell for eight points at a time, read straight from consecutive columns `x` of a
// 3 x n matrix (stride 3) and split into coordinate rows in registers; returns the count
// it located (a multiple of eight). The same operations lane by lane as locate_cell.
std::ptrdiff_t locate_cells_avx512(const CellGrid& grid, const double* x, std::ptrdiff_t n, ChunkCells& out) {
  __m512d m[3][3], count[3], last[3], origin[3];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m[r][c] = _mm512_set1_pd(grid.inv(r, c));
  for (int a = 0; a < 3; ++a) {
    count[a] = _mm512_set1_pd(grid.cells[a]);
    last[a] = _mm512_set1_pd(grid.cells[a] - 1);
    origin[a] = _mm512_set1_pd(grid.origin[a]);
  }
  const __m512d lo = _mm512_set1_pd(-kBoxTolerance), hi = _mm512_set1_pd(1 + kBoxTolerance), zero = _mm512_setzero_pd();
  // Eight columns x0 y0 z0 x1 ... z7 in three registers: lanes 0-5 of a row from the first
  // two, lanes 6-7 from the third (permute indices: 8 + k picks the second source's k).
  const __m512i first[3] = {_mm512_setr_epi64(0, 3, 6, 9, 12, 15, 0, 0), _mm512_setr_epi64(1, 4, 7, 10, 13, 0, 0, 0),
                            _mm512_setr_epi64(2, 5, 8, 11, 14, 0, 0, 0)};
  const __m512i second[3] = {_mm512_setr_epi64(0, 1, 2, 3, 4, 5, 10, 13), _mm512_setr_epi64(0, 1, 2, 3, 4, 8, 11, 14),
                             _mm512_setr_epi64(0, 1, 2, 3, 4, 9, 12, 15)};
  std::ptrdiff_t i = 0;
  for (; i + 8 <= n; i += 8) {
    const double* p = x + 3 * i;
    const __m512d a = _mm512_loadu_pd(p), b = _mm512_loadu_pd(p + 8), c = _mm512_loadu_pd(p + 16);
    __m512d d[3];
    for (int r = 0; r < 3; ++r) {
      const __m512d row = _mm512_permutex2var_pd(_mm512_permutex2var_pd(a, first[r], b), second[r], c);
      _mm512_storeu_pd(out.x[r] + i, row);
      d[r] = _mm512_sub_pd(row, origin[r]);
    }
    const __m512d u[3] = {
        _mm512_fmadd_pd(m[0][2], d[2], _mm512_fmadd_pd(m[0][1], d[1], _mm512_mul_pd(m[0][0], d[0]))),
        _mm512_fmadd_pd(m[1][2], d[2], _mm512_fmadd_pd(m[1][1], d[1], _mm512_mul_pd(m[1][0], d[0]))),
        _mm512_fmadd_pd(m[2][0], d[0], _mm512_fmadd_pd(m[2][1], d[1], _mm512_mul_pd(m[2][2], d[2])))};
    __mmask8 in = 0xff;
    for (int r = 0; r < 3; ++r)
      in &= _mm512_cmp_pd_mask(u[r], lo, _CMP_GE_OQ) & _mm512_cmp_pd_mask(u[r], hi, _CMP_LE_OQ);
    __m512d cell[3];
    for (int r = 0; r < 3; ++r) {
      const __m512d s = _mm512_maskz_mul_pd(in, u[r], count[r]);  // 0 outside the box
      const __m512d floor = _mm512_roundscale_pd(s, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
      cell[r] = _mm512_min_pd(_mm512_max_pd(floor, zero), last[r]);
      _mm512_storeu_pd(out.local[r] + i, _mm512_sub_pd(s, cell[r]));
    }
    const __m512d flat = _mm512_add_pd(
        _mm512_mul_pd(_mm512_add_pd(_mm512_mul_pd(cell[2], count[1]), cell[1]), count[0]), cell[0]);  // exact
    const __m512d flat_or_none = _mm512_mask_blend_pd(in, _mm512_set1_pd(-1), flat);
    _mm512_storeu_si512(out.flat + i, _mm512_cvtepi32_epi64(_mm512_cvttpd_epi32(flat_or_none)));
  }
  return i;
}
#endif

// ChunkCells for the points pos + v * stride, v = id[t] (or t without ids): eight at a
// time straight from consecutive columns where the CPU can; otherwise the offsets
// x - origin gathered first, then located four at a time where it can.
void locate_cells(const CellGrid& grid, const double* pos, Eigen::Index stride, const std::uint32_t* id,
                  std::ptrdiff_t begin, std::ptrdiff_t end, ChunkCells& out) {
  const std::ptrdiff_t n = end - begin;
  std::ptrdiff_t done = 0;
  const double cells = static_cast<double>(grid.cells[0]) * grid.cells[1] * grid.cells[2];
  // The vector paths convert flat cells to int32 (the portable build has neither path).
  [[maybe_unused]] const bool int32_cells = cells < 2147483647.0;
#ifdef __AVX512F__
  if (!id && stride == 3 && int32_cells) done = locate_cells_avx512(grid, pos + 3 * begin, n, out);
#endif
  const double o[3] = {grid.origin[0], grid.origin[1], grid.origin[2]};  // not reloaded after each store
  const auto offset = [&out, o](std::ptrdiff_t i, const double* x) {
    for (int a = 0; a < 3; ++a) {
      out.x[a][i] = x[a];
      out.local[a][i] = x[a] - o[a];
    }
  };
  if (id)
    for (std::ptrdiff_t i = done; i < n; ++i) offset(i, pos + id[begin + i] * stride);
  else
    for (std::ptrdiff_t i = done; i < n; ++i) offset(i, pos + (begin + i) * stride);
#if defined(__AVX2__) && defined(__FMA__)
  if (int32_cells) done = locate_cells_avx2(grid, done, n, out);
#endif
  for (std::ptrdiff_t i = done; i < n; ++i) locate_cell(grid, i, out);
}

}  // namespace

template <int D>
void BSplineLattice::evaluate(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                              const Eigen::Ref<const Eigen::Matrix3Xd>* in_nrm, const Visit& visit,
                              Eigen::Ref<Eigen::Matrix3Xd>& out_pos, Eigen::Ref<Eigen::Matrix3Xd>* out_nrm,
                              WarpCounts& counts, bool count_folds) const {
  constexpr int N = D + 1;
  refresh_blocks();
  const CellKernel kernel{blocks_.data(), 3 * N * N * N, local_to_world_jac_, out_pos, out_nrm, count_folds && !out_nrm};
  const CellGrid grid{box_.inverse_axes(), box_.origin(), {cells_[0], cells_[1], cells_[2]}};
  const double* const pos = in_pos.data();
  const Eigen::Index stride = in_pos.outerStride();
  double* const out = out_pos.data();
  const Eigen::Index out_stride = out_pos.outerStride();
  const std::uint32_t* const id = visit.ids ? visit.ids->data() : nullptr;
  const std::int32_t* const block_of = block_of_.data();
  // Without ids, Lattice::changed_points' test: inside the box and in a changed piece (a
  // B-spline's pieces are its cells).
  const std::uint8_t* const changed = all_pieces_changed() ? nullptr : changed_piece_.data();
  std::size_t folded = 0, evaluated = 0;
  const bool no_folds = out_nrm && fold_free();
  constexpr std::ptrdiff_t kChunk = CellChunk::kSize;
  const std::ptrdiff_t n_ids = id ? static_cast<std::ptrdiff_t>(visit.ids->size()) : in_pos.cols();
  const std::ptrdiff_t chunks = (n_ids + kChunk - 1) / kChunk;
  ThreadParts parts;  // found, per thread
  // Chunks of consecutive ids (streaming memory access), each sorted by cell.
#pragma omp parallel reduction(+ : folded, evaluated)
  {
    const std::unique_ptr<CellChunk> chunk(new CellChunk);
    const std::unique_ptr<ChunkCells> where(new ChunkCells);
    chunk->direct = blocks_.size() / kernel.block_size <= static_cast<std::size_t>(CellChunk::kSlots);
    std::vector<std::uint32_t>* const found = id ? nullptr : &parts.mine(n_ids);
#pragma omp for schedule(static)
    for (std::ptrdiff_t c = 0; c < chunks; ++c) {
      const std::ptrdiff_t begin = c * kChunk, end = std::min(n_ids, (c + 1) * kChunk);
      locate_cells(grid, pos, stride, id, begin, end, *where);
      for (std::ptrdiff_t t = begin; t < end; ++t) {
        const std::uint32_t v = id ? id[t] : static_cast<std::uint32_t>(t);
        const std::ptrdiff_t i = t - begin;
        const std::int64_t flat = where->flat[i];
        if (found) {
          if (flat < 0 || (changed && !changed[flat])) continue;
          found->push_back(v);
        }
        const std::int32_t block = flat < 0 ? -1 : block_of[flat];
        if (block < 0) {  // outside, or no moved point reaches this cell: identity, bit for bit
          out_pos.col(v) = in_pos.col(v);
          if (out_nrm) out_nrm->col(v) = in_nrm->col(v);
          continue;
        }
        ++evaluated;
        // The chunk's kernel writes this column later, in cell order: ask for its line now,
        // so the write does not wait for memory (without it, moving one point of a 4^3
        // lattice over a 1M-point cloud took 31.6 ms against 26.8).
        __builtin_prefetch(out + v * out_stride, 1);
        if (!chunk->add(v, block, i)) {
          evaluate_chunk<D>(kernel, *chunk, *where, in_nrm, no_folds, folded);
          chunk->add(v, block, i);
        }
      }
      evaluate_chunk<D>(kernel, *chunk, *where, in_nrm, no_folds, folded);
    }
  }
  if (visit.found) parts.append_to(*visit.found);
  counts.evaluated += evaluated;
  counts.folded += folded;
}

void BSplineLattice::evaluate_degree(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                                     const Eigen::Ref<const Eigen::Matrix3Xd>* in_nrm, const Visit& visit,
                                     Eigen::Ref<Eigen::Matrix3Xd>& out_pos, Eigen::Ref<Eigen::Matrix3Xd>* out_nrm,
                                     WarpCounts& counts, bool count_folds) const {
  switch (degree_) {
    case 1:
      return evaluate<1>(in_pos, in_nrm, visit, out_pos, out_nrm, counts, count_folds);
    case 2:
      return evaluate<2>(in_pos, in_nrm, visit, out_pos, out_nrm, counts, count_folds);
    default:
      return evaluate<3>(in_pos, in_nrm, visit, out_pos, out_nrm, counts, count_folds);
  }
}

void BSplineLattice::apply(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                           const Eigen::Ref<const Eigen::Matrix3Xd>& in_nrm,
                           const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
                           Eigen::Ref<Eigen::Matrix3Xd> out_nrm, WarpCounts& counts) const {
  evaluate_degree(in_pos, &in_nrm, {&ids}, out_pos, &out_nrm, counts);
}

bool BSplineLattice::apply_changed(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                                   const Eigen::Ref<const Eigen::Matrix3Xd>* in_nrm, std::vector<std::uint32_t>& ids,
                                   Eigen::Ref<Eigen::Matrix3Xd> out_pos, Eigen::Ref<Eigen::Matrix3Xd>* out_nrm,
                                   WarpCounts& counts) const {
  if (!any_changed_) return true;  // changed_points() lists nothing
  evaluate_degree(in_pos, in_nrm, {nullptr, &ids}, out_pos, out_nrm, counts, !in_nrm && !fold_free());
  return true;
}

bool BSplineLattice::apply_without_normals(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                                           const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
                                           WarpCounts& counts) const {
  // Where the lattice may fold, the Jacobian's determinant is still evaluated, to count
  // the folds apply() would count; the normals' cofactor products are not.
  evaluate_degree(in_pos, nullptr, {&ids}, out_pos, nullptr, counts, !fold_free());
  return true;
}

void BSplineLattice::apply_positions(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                                     const std::vector<std::uint32_t>& ids,
                                     Eigen::Ref<Eigen::Matrix3Xd> out_pos) const {
  WarpCounts counts;
  evaluate_degree(in_pos, nullptr, {&ids}, out_pos, nullptr, counts);
}

}  // namespace ffd
