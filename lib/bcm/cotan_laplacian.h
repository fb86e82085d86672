// Discrete Laplace operators of a triangle set, as Δ = M⁻¹ W (Botsch & Kobbelt eq. 4).
//
// Promises: W is symmetric with rows that sum to zero and M is a positive diagonal. The
// standard cotangent W is the paper's operator: its off-diagonal weights are negative
// across non-Delaunay edges, and −W is still positive semidefinite (it is the stiffness
// matrix of linear finite elements), so the k-harmonic systems built from it stay
// positive definite. CotanWeights::Positive and the uniform W have non-negative
// off-diagonals (a weighted graph Laplacian, with a discrete maximum principle). A
// vertex's row is complete only if every triangle around it was given.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace ffd {

using Triangle = std::array<std::uint32_t, 3>;

/// Δ = M⁻¹ W: `weights` is W (n × n), `areas` the diagonal of M (n).
struct Laplacian {
  Eigen::SparseMatrix<double> weights;
  Eigen::VectorXd areas;
};

/// Largest cotangent a corner contributes: the cotangent of 1°. Corners sharper than 1°
/// or blunter than 179° count as 1° or 179°.
///
/// Why: a needle or a cap (an angle near 0° or 180°) has a cotangent that grows without
/// bound (infinite or NaN for a zero-area triangle). The clamp keeps W finite and bounds
/// each corner's share of a weight by cot 1° ≈ 57.3, which keeps the systems well
/// conditioned, most of all at k = 3, whose entries are products of three weights.
/// It is the only change to eq. 4 and
/// acts only there: a triangle with every angle in [1°, 179°] gets its exact cotangents.
/// CGAL's secure cotangent weights (PMP::fair's default) clamp the cosine at ±0.999,
/// i.e. stop at about 2.56°; ours stop at 1°, so meshes with angles between 1° and 2.56°
/// get their exact weights here and clamped ones in CGAL. A triangle with a clamped
/// corner is no longer an exact finite element and its element matrix can be indefinite
/// (a cap of 0.5°, 5° and 174.5° is), so the positive semidefiniteness promised above is exact for
/// meshes whose angles lie in [1°, 179°]; where a sliver breaks it, the editor's
/// Cholesky factorization fails and setup reports a singular system.
constexpr double kMaxCotangent = 57.289961630759425;

/// Which edge weights cotan_laplacian() keeps.
enum class CotanWeights {
  Standard,  // eq. 4 as printed: ½(cot α + cot β), negative across non-Delaunay edges
  Positive,  // negative edge weights set to zero: a graph Laplacian (maximum principle)
};

/// The cotangent Laplacian of eq. 4 (Meyer et al. 2003) of `triangles` (indices into the
/// columns of `positions`, 3 × n): W_ij = ½(cot α_ij + cot β_ij), W_ii = −Σ_j W_ij, and
/// M_ii the mixed Voronoi area of vertex i (its Voronoi region in non-obtuse triangles,
/// half the area of an obtuse triangle at its obtuse corner and a quarter at the other
/// two). Standard weights (the paper's, CGAL's fair, libigl's cotmatrix/harmonic) keep
/// negative W_ij; Positive zeroes them, trading linear precision on non-Delaunay
/// triangulations (and the paper's energy) for a discrete maximum principle. Degenerate
/// input stays finite: corner cotangents are clamped to ±kMaxCotangent and an area below
/// 1e-12 of the mean is raised to it. Vertices in no triangle get a zero row and area 1.
Laplacian cotan_laplacian(const Eigen::Ref<const Eigen::Matrix3Xd>& positions,
                          const std::vector<Triangle>& triangles,
                          CotanWeights weights = CotanWeights::Standard);

/// The uniform (umbrella) Laplacian of `triangles` over `num_vertices` vertices:
/// W_ij = 1 per edge, M_ii = valence (1 for a vertex in no triangle).
Laplacian uniform_laplacian(Eigen::Index num_vertices, const std::vector<Triangle>& triangles);

}  // namespace ffd
