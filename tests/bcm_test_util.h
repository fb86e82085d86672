// Helpers shared by the boundary-constraint modeling tests: vertex picks, random 9-dof
// poses, and an independent reference solve of Δ^k p = 0 over the whole mesh.
#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseLU>

#include <functional>
#include <random>
#include <vector>

#include "bcm/cotan_laplacian.h"
#include "mesh/mesh.h"

namespace ffd::test {

/// Vertices (ascending) whose current position satisfies `keep`.
inline std::vector<std::uint32_t> pick(const Mesh& mesh, const std::function<bool(const Eigen::Vector3d&)>& keep) {
  std::vector<std::uint32_t> out;
  const auto p = mesh.positions();
  for (Eigen::Index v = 0; v < p.cols(); ++v)
    if (keep(p.col(v))) out.push_back(static_cast<std::uint32_t>(v));
  return out;
}

/// Every face of a triangle mesh.
inline std::vector<Triangle> all_triangles(const Mesh& mesh) {
  std::vector<Triangle> out;
  std::vector<std::uint32_t> ids;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    mesh.face_vertices(f, ids);
    out.push_back({ids[0], ids[1], ids[2]});
  }
  return out;
}

/// A 9-dof affine map x -> linear·x + translation about `center`.
struct Pose {
  Eigen::Matrix3d linear = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d operator()(const Eigen::Vector3d& x) const { return linear * x + translation; }
};

/// A random rotation (any axis, up to 60°), scale 0.7..1.3 per axis and translation up to
/// `reach`, about `center`.
inline Pose random_pose(std::mt19937& rng, const Eigen::Vector3d& center, double reach) {
  std::uniform_real_distribution<double> unit(-1, 1);
  const Eigen::Vector3d axis = Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
  const Eigen::Vector3d scale(1 + 0.3 * unit(rng), 1 + 0.3 * unit(rng), 1 + 0.3 * unit(rng));
  const Eigen::Vector3d translate(reach * unit(rng), reach * unit(rng), reach * unit(rng));
  Pose pose;
  pose.linear = Eigen::AngleAxisd(unit(rng) * M_PI / 3, axis).toRotationMatrix() * scale.asDiagonal();
  pose.translation = center + translate - pose.linear * center;
  return pose;
}

/// The reference for eq. 5 with C^(k−1) boundaries: rows `free` of (M⁻¹W)^k over the
/// whole mesh (cotangent Laplacian of `setup`, 3 × n), every other vertex at `target`
/// (3 × n), solved by a sparse LU. Returns 3 × free.size().
inline Eigen::Matrix3Xd direct_kharmonic(const Mesh& mesh, const Eigen::Matrix3Xd& setup, const std::vector<std::uint32_t>& free,
                                         const Eigen::Matrix3Xd& target, int k, bool uniform = false) {
  using Sparse = Eigen::SparseMatrix<double>;
  const std::vector<Triangle> triangles = all_triangles(mesh);
  const Laplacian lap = uniform ? uniform_laplacian(setup.cols(), triangles) : cotan_laplacian(setup, triangles);
  const Sparse l = Sparse(lap.areas.cwiseInverse().asDiagonal() * lap.weights);
  Sparse lk = l;
  for (int i = 1; i < k; ++i) lk = Sparse(l * lk);
  const Eigen::Index n = setup.cols();
  std::vector<Eigen::Index> slot(static_cast<std::size_t>(n), -1);
  for (std::size_t i = 0; i < free.size(); ++i) slot[free[i]] = static_cast<Eigen::Index>(i);
  const Eigen::Index p = static_cast<Eigen::Index>(free.size());
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(p, 3);
  const Sparse rows = lk.transpose();  // column i = row i of L^k
  for (Eigen::Index i = 0; i < p; ++i)
    for (Sparse::InnerIterator it(rows, free[static_cast<std::size_t>(i)]); it; ++it) {
      const Eigen::Index j = it.row();
      if (slot[static_cast<std::size_t>(j)] >= 0)
        entries.emplace_back(static_cast<int>(i), static_cast<int>(slot[static_cast<std::size_t>(j)]), it.value());
      else
        rhs.row(i) -= it.value() * target.col(j).transpose();
    }
  Sparse a(p, p);
  a.setFromTriplets(entries.begin(), entries.end());
  a.makeCompressed();
  Eigen::SparseLU<Sparse> lu(a);
  return Eigen::MatrixXd(lu.solve(rhs)).transpose();
}

}  // namespace ffd::test
