// Helpers shared by the boundary-constraint modeling tests: vertex picks, random 9-dof
// poses, and an independent reference solve of Δ^k p = 0 over the whole mesh.
#pragma once

#include <Eigen/Dense>

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
/// (3 × n), solved by a sparse LU. Returns 3 × free.size(). In bcm_test_util.cpp, compiled
/// once: defined here, its sparse products and SparseLU were instantiated in every unity
/// batch holding a file that includes this header (three batches in each build).
Eigen::Matrix3Xd direct_kharmonic(const Mesh& mesh, const Eigen::Matrix3Xd& setup, const std::vector<std::uint32_t>& free,
                                  const Eigen::Matrix3Xd& target, int k, bool uniform = false);

}  // namespace ffd::test
