// Discrete Laplace operators of a triangle set, as Δ = M⁻¹ W (Botsch & Kobbelt eq. 4).
//
// Promises: W is symmetric with non-negative off-diagonal weights and rows that sum to
// zero (a weighted graph Laplacian, so −W is positive semidefinite); M is a positive
// diagonal. A vertex's row is complete only if every triangle around it was given.
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
constexpr double kMaxCotangent = 57.289961630759425;

/// The cotangent Laplacian of eq. 4 (Meyer et al. 2003) of `triangles` (indices into the
/// columns of `positions`, 3 × n): W_ij = ½(cot α_ij + cot β_ij) and M_ii the mixed
/// Voronoi area of vertex i (Voronoi region in non-obtuse triangles, half or a quarter
/// of the area in obtuse ones). Degenerate input stays finite: corner cotangents are
/// clamped to ±kMaxCotangent, an edge weight that still comes out negative (opposite
/// angles summing to more than 180°) is set to zero, and an area below 1e-12 of the mean
/// is raised to it. Vertices in no triangle get a zero row and area 1.
Laplacian cotan_laplacian(const Eigen::Ref<const Eigen::Matrix3Xd>& positions,
                          const std::vector<Triangle>& triangles);

/// The uniform (umbrella) Laplacian of `triangles` over `num_vertices` vertices:
/// W_ij = 1 per edge, M_ii = valence (1 for a vertex in no triangle).
Laplacian uniform_laplacian(Eigen::Index num_vertices, const std::vector<Triangle>& triangles);

}  // namespace ffd
