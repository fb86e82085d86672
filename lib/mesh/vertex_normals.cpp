#include "mesh/vertex_normals.h"

#include <Eigen/Geometry>

#include <cmath>


namespace ffd {

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
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d p = positions.col(ids[i]);
      const Eigen::Vector3d a = positions.col(ids[(i + n - 1) % n]) - p;
      const Eigen::Vector3d b = positions.col(ids[(i + 1) % n]) - p;
      // atan2 of |a×b| and a·b is accurate for every angle, unlike acos.
      const double angle = std::atan2(a.cross(b).norm(), a.dot(b));
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
