#include "common/supernodal_cholesky.h"

#include <Eigen/CholmodSupport>
#include <Eigen/Dense>

#include <vector>

#include "common/errors.h"
#include "common/timer.h"
#include "common/zeroed_array.h"

namespace ffd {
namespace {

using Sparse = Eigen::SparseMatrix<double>;
using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Eigen's dense products run on one thread here: its GEMM blocking depends on the thread
// count, so more threads would change rounding and break bit-identical results.
class OneEigenThread {
public:
  OneEigenThread() : saved_(Eigen::nbThreads()) { Eigen::setNbThreads(1); }
  ~OneEigenThread() { Eigen::setNbThreads(saved_); }

private:
  int saved_;
};

}  // namespace

struct SupernodalCholesky::Impl {
  cholmod_common common;
  cholmod_factor* factor = nullptr;
  double analyze_ms = 0, numeric_ms = 0, flops = 0;

  Impl() {
    cholmod_start(&common);
    common.print = 0;  // failures are reported by the caller, in one line
  }
  ~Impl() {
    if (factor) cholmod_free_factor(&factor, &common);
    cholmod_finish(&common);
  }

  // The supernode's dense block: rows L->s[pi[s] ..], columns super[s] .., column-major.
  Eigen::Map<Eigen::MatrixXd> block(int s) const {
    const int* super = static_cast<const int*>(factor->super);
    const int* pi = static_cast<const int*>(factor->pi);
    const int* px = static_cast<const int*>(factor->px);
    return {static_cast<double*>(factor->x) + px[s], pi[s + 1] - pi[s], super[s + 1] - super[s]};
  }

  bool numeric(const Sparse& a);
};

// Left-looking supernodal LLᵀ (the algorithm of CHOLMOD's t_cholmod_super_numeric): each
// supernode gathers its columns of P·A·Pᵀ, subtracts the updates of the descendants whose
// rows reach it (one GEMM each, scattered by a row map), then factors its diagonal block
// and solves the rows below it.
bool SupernodalCholesky::Impl::numeric(const Sparse& a) {
  if (!cholmod_change_factor(CHOLMOD_REAL, true, true, true, true, factor, &common))
    throw SolverError("sparse Cholesky: out of memory for the factor");
  const int n = static_cast<int>(factor->n), nsuper = static_cast<int>(factor->nsuper);
  const int* super = static_cast<const int*>(factor->super);
  const int* pi = static_cast<const int*>(factor->pi);
  const int* rows = static_cast<const int*>(factor->s);
  const int* perm = static_cast<const int*>(factor->Perm);
  double* values = static_cast<double*>(factor->x);
  advise_huge_pages(values, factor->xsize * sizeof(double));  // fresh from CHOLMOD, written whole below
  std::fill(values, values + factor->xsize, 0.0);

  // C = P·A·Pᵀ, lower triangle: C(k, l) = A(perm[k], perm[l]).
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> p(n);
  for (int k = 0; k < n; ++k) p.indices()[perm[k]] = k;
  Sparse c(n, n);
  c.selfadjointView<Eigen::Lower>() = a.selfadjointView<Eigen::Lower>().twistedBy(p);

  std::vector<int> supernode_of(static_cast<std::size_t>(n));
  for (int s = 0; s < nsuper; ++s)
    for (int j = super[s]; j < super[s + 1]; ++j) supernode_of[static_cast<std::size_t>(j)] = s;
  // head[s]: descendants whose next unprocessed row lies in supernode s (linked by next);
  // next_row[d]: that row's position in d's row list.
  std::vector<int> map(static_cast<std::size_t>(n), -1), head(static_cast<std::size_t>(nsuper), -1),
      next(static_cast<std::size_t>(nsuper), -1), next_row(static_cast<std::size_t>(nsuper), 0);
  Eigen::VectorXd work(static_cast<Eigen::Index>(factor->maxcsize));
  const auto link = [&](int d, int row_position) {
    next_row[static_cast<std::size_t>(d)] = row_position;
    const int target = supernode_of[static_cast<std::size_t>(rows[pi[d] + row_position])];
    next[static_cast<std::size_t>(d)] = head[static_cast<std::size_t>(target)];
    head[static_cast<std::size_t>(target)] = d;
  };

  for (int s = 0; s < nsuper; ++s) {
    const int k1 = super[s], k2 = super[s + 1], ncol = k2 - k1;
    Eigen::Map<Eigen::MatrixXd> ls = block(s);
    const int nrow = static_cast<int>(ls.rows());
    for (int i = 0; i < nrow; ++i) map[static_cast<std::size_t>(rows[pi[s] + i])] = i;
    for (int j = k1; j < k2; ++j)
      for (Sparse::InnerIterator it(c, j); it; ++it) ls(map[static_cast<std::size_t>(it.row())], j - k1) = it.value();

    for (int d = head[static_cast<std::size_t>(s)]; d != -1;) {
      const int following = next[static_cast<std::size_t>(d)];
      Eigen::Map<Eigen::MatrixXd> ld = block(d);
      const int first = next_row[static_cast<std::size_t>(d)], drow = static_cast<int>(ld.rows());
      int last = first;  // rows of d inside s's columns: [first, last)
      while (last < drow && rows[pi[d] + last] < k2) ++last;
      const int inside = last - first, below = drow - first;
      Eigen::Map<Eigen::MatrixXd> update(work.data(), below, inside);
      update.noalias() = ld.middleRows(first, below) * ld.middleRows(first, inside).transpose();
      for (int jj = 0; jj < inside; ++jj) {
        const int col = rows[pi[d] + first + jj] - k1;
        for (int ii = jj; ii < below; ++ii)
          ls(map[static_cast<std::size_t>(rows[pi[d] + first + ii])], col) -= update(ii, jj);
      }
      if (last < drow) link(d, last);
      d = following;
    }

    auto top = ls.topRows(ncol);
    Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(top);  // in place, lower triangle
    if (llt.info() != Eigen::Success || !top.diagonal().allFinite()) return false;
    if (nrow > ncol) {
      top.triangularView<Eigen::Lower>().adjoint().solveInPlace<Eigen::OnTheRight>(ls.bottomRows(nrow - ncol));
      link(s, ncol);
    }
  }
  factor->minor = static_cast<std::size_t>(n);
  return true;
}

SupernodalCholesky::SupernodalCholesky() : impl_(std::make_unique<Impl>()) {}
SupernodalCholesky::~SupernodalCholesky() = default;

bool SupernodalCholesky::compute(const Eigen::SparseMatrix<double>& a) {
  Impl& s = *impl_;
  if (s.factor) cholmod_free_factor(&s.factor, &s.common);
  Stopwatch clock;
  s.common.supernodal = CHOLMOD_SUPERNODAL;
  s.common.nmethods = 1;
  s.common.method[0].ordering = CHOLMOD_AMD;  // METIS saves a third of the flops but costs more than that to run
  s.common.postorder = true;
  cholmod_sparse view = Eigen::viewAsCholmod(a.selfadjointView<Eigen::Lower>());
  s.factor = cholmod_analyze(&view, &s.common);
  if (!s.factor) throw SolverError("sparse Cholesky: the symbolic analysis ran out of memory");
  s.flops = s.common.fl;
  s.analyze_ms = clock.ms();
  clock.restart();
  OneEigenThread one_thread;
  const bool ok = s.numeric(a);
  s.numeric_ms = clock.ms();
  return ok;
}

Eigen::MatrixXd SupernodalCholesky::solve(const Eigen::MatrixXd& b) const {
  const Impl& s = *impl_;
  OneEigenThread one_thread;
  const int n = static_cast<int>(s.factor->n), nsuper = static_cast<int>(s.factor->nsuper);
  const int* super = static_cast<const int*>(s.factor->super);
  const int* pi = static_cast<const int*>(s.factor->pi);
  const int* rows = static_cast<const int*>(s.factor->s);
  const int* perm = static_cast<const int*>(s.factor->Perm);
  const Eigen::Index m = b.cols();
  RowMajorMatrix y(n, m);
  for (int k = 0; k < n; ++k) y.row(k) = b.row(perm[k]);
  RowMajorMatrix scratch;
  // Forward: L·z = P·b, supernode by supernode.
  for (int t = 0; t < nsuper; ++t) {
    const Eigen::Map<Eigen::MatrixXd> l = s.block(t);
    const int ncol = super[t + 1] - super[t], nrow = static_cast<int>(l.rows());
    auto x = y.middleRows(super[t], ncol);
    l.topRows(ncol).triangularView<Eigen::Lower>().solveInPlace(x);
    if (nrow == ncol) continue;
    scratch.noalias() = l.bottomRows(nrow - ncol) * x;
    for (int i = 0; i < nrow - ncol; ++i) y.row(rows[pi[t] + ncol + i]) -= scratch.row(i);
  }
  // Backward: Lᵀ·w = z, in reverse.
  for (int t = nsuper - 1; t >= 0; --t) {
    const Eigen::Map<Eigen::MatrixXd> l = s.block(t);
    const int ncol = super[t + 1] - super[t], nrow = static_cast<int>(l.rows());
    auto x = y.middleRows(super[t], ncol);
    if (nrow > ncol) {
      scratch.resize(nrow - ncol, m);
      for (int i = 0; i < nrow - ncol; ++i) scratch.row(i) = y.row(rows[pi[t] + ncol + i]);
      x.noalias() -= l.bottomRows(nrow - ncol).transpose() * scratch;
    }
    l.topRows(ncol).triangularView<Eigen::Lower>().adjoint().solveInPlace(x);
  }
  Eigen::MatrixXd out(n, m);
  for (int k = 0; k < n; ++k) out.row(perm[k]) = y.row(k);
  return out;
}

std::size_t SupernodalCholesky::factor_nonzeros() const {
  return impl_->factor ? static_cast<std::size_t>(impl_->factor->xsize) : 0;
}
double SupernodalCholesky::factor_flops() const { return impl_->flops; }
double SupernodalCholesky::analyze_ms() const { return impl_->analyze_ms; }
double SupernodalCholesky::numeric_ms() const { return impl_->numeric_ms; }

}  // namespace ffd
