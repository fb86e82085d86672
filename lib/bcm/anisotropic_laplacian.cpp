#include "bcm/anisotropic_laplacian.h"

#include <CGAL/Surface_mesh_parameterization/LSCM_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>

#include <Eigen/Eigenvalues>

#include <algorithm>

#include "common/errors.h"
#include "bcm/bcm_options.h"
#include "mesh/halfedge_view_cgal.h"

namespace ffd {
namespace {

namespace SMP = CGAL::Surface_mesh_parameterization;

[[noreturn]] void not_a_disk(const std::string& what) {
  throw TopologyError("anisotropic bending parametrizes the support and the rings around it, which must "
                      "be a topological disk; " + what + " (use \"cotan\" for such supports)",
                      {"laplacian"});
}

// The connected pieces of `n` vertices joined by `triangles` (union-find).
std::size_t count_pieces(std::size_t n, const std::vector<Triangle>& triangles) {
  std::vector<std::uint32_t> parent(n);
  for (std::size_t v = 0; v < n; ++v) parent[v] = static_cast<std::uint32_t>(v);
  const auto find = [&](std::uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const Triangle& t : triangles)
    for (int c = 1; c < 3; ++c) parent[find(t[c])] = find(t[0]);
  std::size_t pieces = 0;
  for (std::size_t v = 0; v < n; ++v) pieces += find(static_cast<std::uint32_t>(v)) == v;
  return pieces;
}

}  // namespace

Eigen::Matrix3Xd equal_diameter_conformal_map(const Eigen::Ref<const Eigen::Matrix3Xd>& positions,
                                              const std::vector<Triangle>& triangles) {
  const Eigen::Index n = positions.cols();
  SurfaceMesh sm;
  sm.reserve(static_cast<SurfaceMesh::size_type>(n), 0, static_cast<SurfaceMesh::size_type>(triangles.size()));
  for (Eigen::Index v = 0; v < n; ++v) sm.add_vertex(to_point(positions.col(v)));
  for (const Triangle& t : triangles)
    if (sm.add_face(VertexIndex(t[0]), VertexIndex(t[1]), VertexIndex(t[2])) == SurfaceMesh::null_face())
      not_a_disk("its triangles meet at a vertex like a bow tie");

  // One piece, one boundary loop, V − E + F = 1.
  const std::size_t pieces = count_pieces(static_cast<std::size_t>(n), triangles);
  if (pieces != 1) not_a_disk("here it falls into " + std::to_string(pieces) + " pieces");
  std::vector<char> seen(sm.number_of_halfedges(), 0);
  std::size_t loops = 0;
  HalfedgeIndex border;
  for (HalfedgeIndex h : sm.halfedges()) {
    if (!sm.is_border(h) || seen[h.idx()]) continue;
    ++loops;
    border = h;
    for (HalfedgeIndex g = h; !seen[g.idx()]; g = sm.next(g)) seen[g.idx()] = 1;
  }
  const long euler = static_cast<long>(sm.number_of_vertices()) - static_cast<long>(sm.number_of_edges()) +
                     static_cast<long>(sm.number_of_faces());
  if (loops != 1 || euler != 1)
    not_a_disk("here it has " + std::to_string(loops) + " boundary loops and Euler characteristic " +
               std::to_string(euler));

  auto uv = sm.add_property_map<VertexIndex, Kernel::Point_2>("v:bcm_uv").first;
  const SMP::Error_code status = SMP::parameterize(sm, SMP::LSCM_parameterizer_3<SurfaceMesh>(), border, uv);
  if (status != SMP::OK)
    throw InputError(std::string("the conformal parametrization of the support failed: ") +
                         SMP::get_error_message(status),
                     {"laplacian"});

  // Principal axes of the planar region (its exact area second moments), then the minor
  // axis stretched so that both axes span the same diameter (the paper's "scale this
  // planar triangulation along its principal axes such that its diameter is
  // approximately the same in each direction").
  Eigen::Matrix2Xd p(2, n);
  for (Eigen::Index v = 0; v < n; ++v) p.col(v) << uv[VertexIndex(static_cast<std::uint32_t>(v))].x(),
                                                   uv[VertexIndex(static_cast<std::uint32_t>(v))].y();
  double area = 0;
  Eigen::Vector2d first = Eigen::Vector2d::Zero();
  Eigen::Matrix2d second = Eigen::Matrix2d::Zero();
  for (const Triangle& t : triangles) {
    const Eigen::Vector2d a = p.col(t[0]), b = p.col(t[1]), c = p.col(t[2]);
    const Eigen::Vector2d e1 = b - a, e2 = c - a;
    const double ta = std::abs(e1.x() * e2.y() - e1.y() * e2.x()) / 2;
    const Eigen::Vector2d sum = a + b + c;
    area += ta;
    first += ta * sum / 3;
    second += ta / 12 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + sum * sum.transpose());
  }
  if (!(area > 0)) throw InputError("the conformal parametrization of the support has no area", {"laplacian"});
  const Eigen::Vector2d mean = first / area;
  const Eigen::Matrix2d covariance = second / area - mean * mean.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(covariance);
  // Columns: major axis, then minor (eigenvalues ascend); a fixed sign per axis keeps
  // the result deterministic.
  Eigen::Matrix2d axes;
  axes.col(0) = eigen.eigenvectors().col(1);
  axes.col(1) = eigen.eigenvectors().col(0);
  for (int a = 0; a < 2; ++a)
    if (axes(0, a) < 0 || (axes(0, a) == 0 && axes(1, a) < 0)) axes.col(a) = -axes.col(a);
  const Eigen::Matrix2Xd local = axes.transpose() * (p.colwise() - mean);
  const Eigen::Vector2d diameter = local.rowwise().maxCoeff() - local.rowwise().minCoeff();
  const double stretch = diameter[1] > 0 ? diameter[0] / diameter[1] : 1.0;
  Eigen::Matrix3Xd out = Eigen::Matrix3Xd::Zero(3, n);
  out.row(0) = local.row(0);
  out.row(1) = stretch * local.row(1);
  return out;
}

Laplacian anisotropic_laplacian(const Eigen::Ref<const Eigen::Matrix3Xd>& positions, const std::vector<Triangle>& domain,
                                const std::vector<Triangle>& triangles) {
  std::uint32_t used = 0;
  for (const Triangle& t : triangles) used = std::max({used, t[0] + 1, t[1] + 1, t[2] + 1});
  const Eigen::Matrix3Xd map = equal_diameter_conformal_map(positions, domain);
  // Standard weights, negative ones kept, as on the surface: the paper computes "the
  // weights for the Laplace operator" of eq. 4 on the scaled triangulation. On a planar
  // triangulation they have exact linear precision and −W is the stiffness matrix of a
  // planar finite-element mesh (positive semidefinite), so the energy is the planar
  // k-harmonic one the anisotropy correction is meant to give. Dropping them would cost
  // the most here: the stretch along the minor axis turns right and acute triangles
  // obtuse, making non-Delaunay edges common even where the surface had none.
  return cotan_laplacian(map.leftCols(used), triangles, CotanWeights::Standard);
}

}  // namespace ffd
