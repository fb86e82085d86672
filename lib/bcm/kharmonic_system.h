// The k-harmonic system of boundary-constraint modeling (Botsch & Kobbelt eq. 3 and 5):
// Δ̄^k p = 0 at the free vertices, with the constrained vertices' positions as boundary
// conditions and their smoothness blended from C^0 to C^(k−1) by the λ recursion.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "bcm/cotan_laplacian.h"

namespace ffd {

/// λ_j(c) of the recursion Δ̄^(j+1) = Δ(λ_j · Δ̄^j): 1 where c ≥ j, 0 where c ≤ j − 1,
/// c − (j − 1) in between. (The paper prints "c − k" for the middle case, which would be
/// negative on [k−1, k]; the intended ramp from 0 to 1 is c − k + 1.) A boundary vertex
/// with smoothness c thus keeps its Laplacians up to order ⌊c⌋ and a fraction of the next:
/// c = 0 is hinged (C^0), c = k−1 is clamped to C^(k−1).
double smoothness_lambda(int j, double c);

/// Rows of (−1)^k · M · Δ̄^k at the free vertices, split by columns into free and
/// constrained vertices, for local vertices numbered free first (0 .. num_free−1) then
/// constrained. Scaling the rows by M and the sign makes the free block symmetric
/// positive definite whenever it is symmetric.
struct KHarmonicSystem {
  Eigen::SparseMatrix<double> free_block;         // num_free × num_free
  Eigen::SparseMatrix<double> constrained_block;  // num_free × num_constrained
  /// True when the free block is symmetric in exact arithmetic: every constrained vertex
  /// has λ_1 = … = λ_(k−1) (always for k ≤ 2; for k = 3 when c ∈ {0, 2}, or c ≤ 0, c ≥ 2).
  bool symmetric = true;
};

/// Assembles the system for Δ = M⁻¹W of `laplacian` (rows complete for every vertex within
/// k−1 rings of the free ones). `continuity` holds c for each constrained vertex (size
/// n − num_free); free vertices have λ = 1. The product runs right to left only over the
/// rows it needs: (−1)^k W_P Λ_(k−1) M⁻¹ W … Λ_1 M⁻¹ W. Precondition: 1 ≤ k.
KHarmonicSystem kharmonic_system(const Laplacian& laplacian, Eigen::Index num_free,
                                 const Eigen::VectorXd& continuity, int k);

}  // namespace ffd
