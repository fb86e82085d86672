// The squared distance from a point to a triangle: the inner loop of the Hausdorff
// distance (mesh/hausdorff.h), where CGAL's squared_distance(Point_3, Triangle_3) costs
// several times more. Tested against CGAL's in mesh_compare_test.cpp.
#pragma once

#include <algorithm>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ffd {

/// |p - q|² for q the point of triangle (a, b, c) closest to p (Ericson, Real-Time
/// Collision Detection, 5.1.5: p's Voronoi region of the triangle's vertices, edges and
/// face). A triangle whose corners lie on a line (to 1e-6 radians) gives the distance
/// to its edges.
inline double point_triangle_squared_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                              const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  // Corners on a line or at one place, or a sliver whose plane rounding cannot place
  // (its angles below 1e-6): the three edges.
  if (!(ab.cross(ac).squaredNorm() > 1e-12 * ab.squaredNorm() * ac.squaredNorm())) {
    const auto segment = [&p](const Eigen::Vector3d& s, const Eigen::Vector3d& e) {
      const Eigen::Vector3d d = e - s;
      const double len2 = d.squaredNorm();
      const double t = len2 > 0 ? std::clamp((p - s).dot(d) / len2, 0.0, 1.0) : 0.0;
      return (p - s - t * d).squaredNorm();
    };
    return std::min({segment(a, b), segment(b, c), segment(a, c)});
  }
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.squaredNorm();  // vertex a
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.squaredNorm();  // vertex b
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (ap - (d1 / (d1 - d3)) * ab).squaredNorm();  // edge ab
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.squaredNorm();  // vertex c
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (ap - (d2 / (d2 - d6)) * ac).squaredNorm();  // edge ac
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)  // edge bc
    return (bp - ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b)).squaredNorm();
  const double sum = va + vb + vc;  // |ab x ac|^2 > 0
  return (ap - (vb / sum) * ab - (vc / sum) * ac).squaredNorm();  // inside the face
}

}  // namespace ffd
