#include "mesh/vertex_normals.h"

#include <Eigen/Geometry>

#include <cmath>


namespace ffd {

namespace {

// The angle between a and b: atan2 of |a×b| and a·b is accurate for every angle, unlike acos.
double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// Adds a triangle's unit normal n, weighted by its angle at each corner, to `out`. The
// angles sum to π, so the largest (at the corner across the longest edge) is taken as π
// minus the other two: one atan2 fewer, and no cancellation since it is at least π/3.
void add_triangle(const std::uint32_t* ids, const Eigen::Ref<const Eigen::Matrix3Xd>& positions,
                  const Eigen::Vector3d& n, Eigen::Ref<Eigen::Matrix3Xd> out) {
  const Eigen::Vector3d p[3] = {positions.col(ids[0]), positions.col(ids[1]), positions.col(ids[2])};
  const Eigen::Vector3d e[3] = {p[2] - p[1], p[0] - p[2], p[1] - p[0]};  // e[i] is across corner i
  const double l[3] = {e[0].squaredNorm(), e[1].squaredNorm(), e[2].squaredNorm()};
  const int big = l[0] >= l[1] ? (l[0] >= l[2] ? 0 : 2) : (l[1] >= l[2] ? 1 : 2);
  double angle[3];
  for (int i = 0; i < 3; ++i)
    if (i != big) angle[i] = angle_between(p[(i + 2) % 3] - p[i], p[(i + 1) % 3] - p[i]);
  angle[big] = M_PI - angle[(big + 1) % 3] - angle[(big + 2) % 3];
  for (int i = 0; i < 3; ++i) out.col(ids[i]) += angle[i] * n;
}

}  // namespace

void compute_vertex_normals(const Mesh& mesh, const Eigen::Ref<const Eigen::Matrix3Xd>& positions,
                            Eigen::Ref<Eigen::Matrix3Xd> out) {
  const MeshElements& el = mesh.elements();
  out.setZero();
  for (std::size_t f = 0; f < el.size(); ++f) {
    if (el.kinds[f] != ElementKind::Polygon || el.degree(f) < 3) continue;
    const std::uint32_t* ids = el.vertices(f);
    const std::size_t n = el.degree(f);
    // Newell's normal: exact for planar polygons, robust for nearly planar ones.
    // Taken relative to the first corner so that far-from-origin meshes lose no digits.
    const Eigen::Vector3d origin = positions.col(ids[0]);
    Eigen::Vector3d face_normal = Eigen::Vector3d::Zero();
    for (std::size_t i = 1; i + 1 < n; ++i)
      face_normal += (positions.col(ids[i]) - origin).cross(positions.col(ids[i + 1]) - origin);
    const double length = face_normal.norm();
    if (!(length > 0)) continue;
    face_normal /= length;
    if (n == 3) {
      add_triangle(ids, positions, face_normal, out);
      continue;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d p = positions.col(ids[i]);
      const double angle = angle_between(positions.col(ids[(i + n - 1) % n]) - p, positions.col(ids[(i + 1) % n]) - p);
      out.col(ids[i]) += angle * face_normal;
    }
  }
  for (Eigen::Index v = 0; v < out.cols(); ++v) {
    const double length = out.col(v).norm();
    if (length > 0) out.col(v) /= length;
  }
}

Eigen::Matrix3Xd vertex_normals(const Mesh& mesh, const Eigen::Ref<const Eigen::Matrix3Xd>& positions) {
  Eigen::Matrix3Xd out(3, positions.cols());
  compute_vertex_normals(mesh, positions, out);
  return out;
}

}  // namespace ffd
