#include "bcm/cotan_laplacian.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace ffd {
namespace {

// Builds W from per-edge weights gathered as (i, j, w) with i != j, each edge possibly
// several times (once per triangle); the diagonal makes every row sum to zero. With
// `drop_negative`, an edge whose summed weight is negative gets weight zero (its entry
// stays, as an explicit zero, so both variants have the same sparsity).
Eigen::SparseMatrix<double> assemble(Eigen::Index n, std::vector<Eigen::Triplet<double>>& edges,
                                     bool drop_negative) {
  Eigen::SparseMatrix<double> offdiag(n, n);
  offdiag.setFromTriplets(edges.begin(), edges.end());  // sums the triangles' shares
  if (drop_negative)
    for (Eigen::Index c = 0; c < offdiag.outerSize(); ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(offdiag, c); it; ++it) it.valueRef() = std::max(it.value(), 0.0);
  Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(n);
  for (Eigen::Index c = 0; c < offdiag.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(offdiag, c); it; ++it) diagonal[c] -= it.value();
  std::vector<Eigen::Triplet<double>> all;
  all.reserve(static_cast<std::size_t>(offdiag.nonZeros() + n));
  for (Eigen::Index c = 0; c < offdiag.outerSize(); ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(offdiag, c); it; ++it)
      all.emplace_back(static_cast<int>(it.row()), static_cast<int>(c), it.value());
    all.emplace_back(static_cast<int>(c), static_cast<int>(c), diagonal[c]);
  }
  Eigen::SparseMatrix<double> w(n, n);
  w.setFromTriplets(all.begin(), all.end());
  return w;
}

}  // namespace

Laplacian cotan_laplacian(const Eigen::Ref<const Eigen::Matrix3Xd>& positions, const std::vector<Triangle>& triangles,
                          CotanWeights weights) {
  const Eigen::Index n = positions.cols();
  std::vector<Eigen::Triplet<double>> edges;
  edges.reserve(triangles.size() * 6);
  Eigen::VectorXd area = Eigen::VectorXd::Zero(n);
  std::vector<char> used(static_cast<std::size_t>(n), 0);
  for (const Triangle& t : triangles) {
    const Eigen::Vector3d p[3] = {positions.col(t[0]), positions.col(t[1]), positions.col(t[2])};
    const double doubled_area = (p[1] - p[0]).cross(p[2] - p[0]).norm();
    double cot[3], dot[3];
    for (int c = 0; c < 3; ++c) {
      // Corner c, between the edges to the other two corners; |u × v| = twice the area.
      const Eigen::Vector3d u = p[(c + 1) % 3] - p[c], v = p[(c + 2) % 3] - p[c];
      dot[c] = u.dot(v);
      const double sine = u.cross(v).norm();
      // cot = cos/sin, clamped only at near-degenerate corners (below 1° or above 179°,
      // see kMaxCotangent); every other corner gets its exact cotangent.
      cot[c] = sine > std::abs(dot[c]) / kMaxCotangent ? dot[c] / sine : (dot[c] >= 0 ? kMaxCotangent : -kMaxCotangent);
      used[t[c]] = 1;
    }
    for (int c = 0; c < 3; ++c) {
      // The corner c's cotangent weighs the opposite edge (eq. 4: α_ij, β_ij are the
      // angles opposite edge ij); ½ per triangle, so W_ij = ½(cot α + cot β).
      const int i = static_cast<int>(t[(c + 1) % 3]), j = static_cast<int>(t[(c + 2) % 3]);
      edges.emplace_back(i, j, 0.5 * cot[c]);
      edges.emplace_back(j, i, 0.5 * cot[c]);
    }
    // Mixed Voronoi areas (Meyer et al. 2003, section 3.3): the Voronoi share in a
    // non-obtuse triangle, area/2 at an obtuse corner and area/4 at the other two.
    if (!(doubled_area > 0)) continue;
    const bool obtuse = dot[0] < 0 || dot[1] < 0 || dot[2] < 0;
    for (int c = 0; c < 3; ++c) {
      double share;
      if (!obtuse) {
        const int a = (c + 1) % 3, b = (c + 2) % 3;
        // |p_c p_a|² cot(angle at b) + |p_c p_b|² cot(angle at a), over 8; the exact
        // cotangents here (a non-obtuse triangle has no degenerate angle).
        const double cot_a = dot[a] / doubled_area, cot_b = dot[b] / doubled_area;
        share = ((p[a] - p[c]).squaredNorm() * cot_b + (p[b] - p[c]).squaredNorm() * cot_a) / 8.0;
      } else {
        share = doubled_area / 2.0 * (dot[c] < 0 ? 0.5 : 0.25);
      }
      area[t[c]] += share;
    }
  }
  double total = 0;
  Eigen::Index counted = 0;
  for (Eigen::Index v = 0; v < n; ++v)
    if (used[v]) {
      total += area[v];
      ++counted;
    }
  const double floor = counted && total > 0 ? 1e-12 * total / static_cast<double>(counted) : 1.0;
  for (Eigen::Index v = 0; v < n; ++v) area[v] = used[v] ? std::max(area[v], floor) : 1.0;
  // Standard: eq. 4 as printed, negative weights (non-Delaunay edges) kept. −W is the
  // linear finite-element stiffness matrix, positive semidefinite on any triangulation,
  // so the systems built from it stay positive definite, and on a planar mesh W has
  // exact linear precision (Σ_j W_ij (p_j − p_i) = 0 inside), Delaunay or not.
  // Positive: negative weights set to zero, a graph Laplacian with a maximum principle.
  return {assemble(n, edges, weights == CotanWeights::Positive), area};
}

Laplacian uniform_laplacian(Eigen::Index n, const std::vector<Triangle>& triangles) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  pairs.reserve(triangles.size() * 3);
  for (const Triangle& t : triangles)
    for (int c = 0; c < 3; ++c) pairs.emplace_back(std::minmax(t[c], t[(c + 1) % 3]));
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  std::vector<Eigen::Triplet<double>> edges;
  edges.reserve(pairs.size() * 2);
  Eigen::VectorXd valence = Eigen::VectorXd::Zero(n);
  for (const auto& [i, j] : pairs) {
    edges.emplace_back(static_cast<int>(i), static_cast<int>(j), 1.0);
    edges.emplace_back(static_cast<int>(j), static_cast<int>(i), 1.0);
    valence[i] += 1;
    valence[j] += 1;
  }
  for (Eigen::Index v = 0; v < n; ++v)
    if (valence[v] == 0) valence[v] = 1;
  return {assemble(n, edges, false), valence};
}

}  // namespace ffd
