// SupernodalCholesky: A = L·Lᵀ for a sparse symmetric positive definite A, stored as a
// factorization (never an inverse) and reused for any number of right-hand sides.
//
// CHOLMOD does the fill-reducing ordering (AMD) and the supernodal symbolic analysis, and
// the factor lives in CHOLMOD's supernodal format. The numeric factorization and the
// solves run on Eigen's dense kernels (LLT, triangular solve, GEMM) instead of CHOLMOD's
// calls into the system BLAS. On the 35k-vertex k = 3 system of the bcm benchmark (2.6
// GFlop, `ffdbench --suite cholesky`) this numeric phase takes 96 ms (27 GFlop/s, one
// thread); CHOLMOD's own takes 630 ms with Debian's default reference BLAS, 280 ms with
// OpenBLAS on one thread and 180-210 ms on two (libopenblas0-pthread, picked through
// update-alternatives), and Eigen's SimplicialLLT 520 ms. The arithmetic is the same
// left-looking supernodal algorithm, and a test checks the factors agree.
//
// Deterministic: one thread, fixed ordering; the same matrix gives bit-identical factors.
#pragma once

#include <memory>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace ffd {

class SupernodalCholesky {
public:
  SupernodalCholesky();
  ~SupernodalCholesky();
  SupernodalCholesky(const SupernodalCholesky&) = delete;
  SupernodalCholesky& operator=(const SupernodalCholesky&) = delete;

  /// Orders, analyzes and factorizes `a` (square; only its lower triangle is read).
  /// Returns false when `a` is not numerically positive definite.
  bool compute(const Eigen::SparseMatrix<double>& a);
  /// X with A·X = B (B: n × any). Precondition: compute() returned true.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& b) const;

  /// Entries of L (its supernodal storage, zeros inside supernodes included).
  std::size_t factor_nonzeros() const;
  /// Floating-point operations of the numeric factorization (CHOLMOD's count).
  double factor_flops() const;
  /// Times of the last compute(): ordering and symbolic analysis, numeric factorization.
  double analyze_ms() const;
  double numeric_ms() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ffd
