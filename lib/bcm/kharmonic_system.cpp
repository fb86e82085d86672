#include "bcm/kharmonic_system.h"

#include <algorithm>
#include <vector>

namespace ffd {
namespace {

using Sparse = Eigen::SparseMatrix<double>;
using RowMajorSparse = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

// Rows of an operator in compressed form, for some vertices (`slot[v]`: v's row or -1).
struct Rows {
  std::vector<int> slot;
  std::vector<int> offset{0};
  std::vector<int> index;
  std::vector<double> value;
};

// row_i(next) = Σ_l W_il · scale_l · row_l(prev) for every i in `which` (ascending), with a
// dense accumulator; each row's columns come out ascending.
Rows next_rows(const Sparse& w, const Eigen::VectorXd& scale, const Rows& prev, const std::vector<int>& which) {
  const Eigen::Index n = w.rows();
  Rows out;
  out.slot.assign(static_cast<std::size_t>(n), -1);
  out.index.reserve(which.size() * 40);
  out.value.reserve(which.size() * 40);
  std::vector<double> sum_storage(static_cast<std::size_t>(n), 0.0);
  std::vector<int> stamp_storage(static_cast<std::size_t>(n), -1), touched_storage(static_cast<std::size_t>(n));
  // Raw pointers: the accumulation loop is the hot spot and must not reload them.
  double* const sum = sum_storage.data();
  int* const stamp = stamp_storage.data();
  int* const touched = touched_storage.data();
  const int* const offset = prev.offset.data();
  const int* const index = prev.index.data();
  const double* const value = prev.value.data();
  for (int i : which) {
    int count = 0;
    for (Sparse::InnerIterator it(w, i); it; ++it) {  // W is symmetric: column i is row i
      const int l = static_cast<int>(it.row());
      const double factor = it.value() * scale[l];
      const int r = prev.slot[static_cast<std::size_t>(l)];
      if (factor == 0.0 || r < 0) continue;
      for (int e = offset[r], end = offset[r + 1]; e < end; ++e) {
        const int col = index[e];
        touched[count] = col;  // kept only the first time the row meets col (no branch)
        count += stamp[col] != i;
        stamp[col] = i;
        sum[col] += factor * value[e];
      }
    }
    std::sort(touched, touched + count);
    out.slot[static_cast<std::size_t>(i)] = static_cast<int>(out.offset.size()) - 1;
    for (int t = 0; t < count; ++t) {
      const int col = touched[t];
      if (sum[col] != 0.0) {  // a λ of zero cuts columns off exactly
        out.index.push_back(col);
        out.value.push_back(sum[col]);
      }
      sum[col] = 0.0;
    }
    out.offset.push_back(static_cast<int>(out.index.size()));
  }
  return out;
}

}  // namespace

double smoothness_lambda(int j, double c) { return std::clamp(c - (j - 1), 0.0, 1.0); }

KHarmonicSystem kharmonic_system(const Laplacian& laplacian, Eigen::Index num_free, const Eigen::VectorXd& continuity,
                                 int k) {
  const Sparse& w = laplacian.weights;
  const Eigen::Index n = w.rows();
  KHarmonicSystem system;
  for (Eigen::Index v = 0; v < continuity.size(); ++v)
    for (int j = 2; j <= k - 1; ++j)
      if (smoothness_lambda(j, continuity[v]) != smoothness_lambda(1, continuity[v])) system.symmetric = false;

  // scale[j][v] = λ_j(v) / M_v: the factor between Δ̄^j at v and the next Δ (eq. 3 with
  // the λ recursion); free vertices have λ = 1.
  std::vector<Eigen::VectorXd> scale(static_cast<std::size_t>(k));
  for (int j = 1; j < k; ++j) {
    scale[static_cast<std::size_t>(j)].resize(n);
    for (Eigen::Index v = 0; v < n; ++v)
      scale[static_cast<std::size_t>(j)][v] =
          (v < num_free ? 1.0 : smoothness_lambda(j, continuity[v - num_free])) / laplacian.areas[v];
  }

  // Rows each level needs: rows[k] = the free vertices; Δ̄^j is needed where the level
  // above reaches and λ_j is not zero (so only k−1 rings of constrained rows are built).
  std::vector<std::vector<int>> needed(static_cast<std::size_t>(k) + 1);
  for (int v = 0; v < num_free; ++v) needed[static_cast<std::size_t>(k)].push_back(v);
  for (int j = k - 1; j >= 1; --j) {
    std::vector<char> mark(static_cast<std::size_t>(n), 0);
    for (int i : needed[static_cast<std::size_t>(j) + 1])
      for (Sparse::InnerIterator it(w, i); it; ++it)
        if (scale[static_cast<std::size_t>(j)][it.row()] != 0.0) mark[static_cast<std::size_t>(it.row())] = 1;
    for (int v = 0; v < n; ++v)
      if (mark[static_cast<std::size_t>(v)]) needed[static_cast<std::size_t>(j)].push_back(v);
  }

  // Level 1: W itself at its needed rows (the M⁻¹ of each Δ goes into the next scale;
  // the outermost one is cancelled by scaling the rows by M, which makes the free block
  // symmetric when it is).
  Rows rows;
  rows.slot.assign(static_cast<std::size_t>(n), -1);
  for (int i : needed[1]) {
    rows.slot[static_cast<std::size_t>(i)] = static_cast<int>(rows.offset.size()) - 1;
    for (Sparse::InnerIterator it(w, i); it; ++it) {
      rows.index.push_back(static_cast<int>(it.row()));
      rows.value.push_back(it.value());
    }
    rows.offset.push_back(static_cast<int>(rows.index.size()));
  }
  // Levels 2..k: (−1)^k W_P Λ_(k−1) M⁻¹ W … Λ_1 M⁻¹ W, right to left.
  for (int j = 2; j <= k; ++j) rows = next_rows(w, scale[static_cast<std::size_t>(j) - 1], rows, needed[static_cast<std::size_t>(j)]);

  // Split the free rows by column into the free and the constrained block (compressed
  // rows, then one conversion each to column-major).
  const double sign = k % 2 == 1 ? -1.0 : 1.0;
  std::vector<int> free_offset{0}, free_index, constrained_offset{0}, constrained_index;
  std::vector<double> free_value, constrained_value;
  free_index.reserve(rows.index.size());
  free_value.reserve(rows.index.size());
  for (int i = 0; i < num_free; ++i) {
    const int r = rows.slot[static_cast<std::size_t>(i)];
    for (int e = rows.offset[static_cast<std::size_t>(r)]; e < rows.offset[static_cast<std::size_t>(r) + 1]; ++e) {
      const int col = rows.index[static_cast<std::size_t>(e)];
      const double v = sign * rows.value[static_cast<std::size_t>(e)];
      if (col < num_free) {
        free_index.push_back(col);
        free_value.push_back(v);
      } else {
        constrained_index.push_back(col - static_cast<int>(num_free));
        constrained_value.push_back(v);
      }
    }
    free_offset.push_back(static_cast<int>(free_index.size()));
    constrained_offset.push_back(static_cast<int>(constrained_index.size()));
  }
  system.free_block = Eigen::Map<const RowMajorSparse>(num_free, num_free, static_cast<Eigen::Index>(free_index.size()),
                                                       free_offset.data(), free_index.data(), free_value.data());
  system.constrained_block =
      Eigen::Map<const RowMajorSparse>(num_free, n - num_free, static_cast<Eigen::Index>(constrained_index.size()),
                                       constrained_offset.data(), constrained_index.data(), constrained_value.data());
  return system;
}

}  // namespace ffd
