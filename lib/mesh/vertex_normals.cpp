#include "mesh/vertex_normals.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

#include "common/vector_math.h"

namespace ffd {

namespace {

// The angle between a and b: atan2 of |a×b| and a·b is accurate for every angle, unlike acos.
double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// Triangles whose angles are computed together. Each triangle's largest angle (at the
// corner across its longest edge) is π minus the other two: one atan2 fewer per
// triangle, and no cancellation since it is at least π/3.
struct TriangleBatch {
  static constexpr int kSize = 64;
  int count = 0;
  std::uint32_t ids[kSize][3];
  int big[kSize];
  Eigen::Vector3d normal[kSize];
  double y[2 * kSize], x[2 * kSize], angle[2 * kSize];

  /// Queues triangle `tri` with unit normal n.
  void add(const std::uint32_t* tri, const Eigen::Ref<const Eigen::Matrix3Xd>& positions, const Eigen::Vector3d& n) {
    const Eigen::Vector3d p[3] = {positions.col(tri[0]), positions.col(tri[1]), positions.col(tri[2])};
    const double l[3] = {(p[2] - p[1]).squaredNorm(), (p[0] - p[2]).squaredNorm(), (p[1] - p[0]).squaredNorm()};
    const int b = l[0] >= l[1] ? (l[0] >= l[2] ? 0 : 2) : (l[1] >= l[2] ? 1 : 2);
    for (int k = 0; k < 2; ++k) {  // the angles at corners b+1 and b+2
      const int i = (b + 1 + k) % 3;
      const Eigen::Vector3d u = p[(i + 2) % 3] - p[i], v = p[(i + 1) % 3] - p[i];
      y[2 * count + k] = u.cross(v).norm();  // atan2 of |u×v| and u·v is accurate for every angle, unlike acos
      x[2 * count + k] = u.dot(v);
    }
    for (int k = 0; k < 3; ++k) ids[count][k] = tri[k];
    big[count] = b;
    normal[count++] = n;
  }
  /// Adds the queued triangles' normals, weighted by their angles, to `out`.
  void flush(Eigen::Ref<Eigen::Matrix3Xd> out) {
    atan2_all(y, x, angle, static_cast<std::size_t>(2 * count));
    for (int t = 0; t < count; ++t) {
      const int b = big[t];
      double w[3];
      w[(b + 1) % 3] = angle[2 * t];
      w[(b + 2) % 3] = angle[2 * t + 1];
      w[b] = M_PI - angle[2 * t] - angle[2 * t + 1];
      for (int k = 0; k < 3; ++k) out.col(ids[t][k]) += w[k] * normal[t];
    }
    count = 0;
  }
  TriangleBatch() {
    std::fill(y, y + 2 * kSize, 1.0);
    std::fill(x, x + 2 * kSize, 1.0);
  }
};

}  // namespace

void compute_vertex_normals(const Mesh& mesh, const Eigen::Ref<const Eigen::Matrix3Xd>& positions,
                            Eigen::Ref<Eigen::Matrix3Xd> out) {
  const MeshElements& el = mesh.elements();
  out.setZero();
  TriangleBatch triangles;
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
      triangles.add(ids, positions, face_normal);
      if (triangles.count == TriangleBatch::kSize) triangles.flush(out);
      continue;
    }
    triangles.flush(out);  // contributions in element order, whatever the mix of sizes
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d p = positions.col(ids[i]);
      const double angle = angle_between(positions.col(ids[(i + n - 1) % n]) - p, positions.col(ids[(i + 1) % n]) - p);
      out.col(ids[i]) += angle * face_normal;
    }
  }
  triangles.flush(out);
  for (Eigen::Index v = 0; v < out.cols(); ++v) {
    const double len = out.col(v).norm();
    if (len > 0) out.col(v) /= len;
  }
}

Eigen::Matrix3Xd vertex_normals(const Mesh& mesh, const Eigen::Ref<const Eigen::Matrix3Xd>& positions) {
  Eigen::Matrix3Xd out(3, positions.cols());
  compute_vertex_normals(mesh, positions, out);
  return out;
}

}  // namespace ffd
