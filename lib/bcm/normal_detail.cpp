#include "bcm/normal_detail.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace ffd {

NormalDetail::NormalDetail(const Eigen::Ref<const Eigen::Matrix3Xd>& base, const Eigen::Ref<const Eigen::Matrix3Xd>& detailed,
                           std::size_t count, const std::vector<Triangle>& triangles) {
  for (const Triangle& t : triangles)
    if (t[0] < count || t[1] < count || t[2] < count) triangles_.push_back(t);
  // By lowest vertex, so that a vertex's triangles sit close together in memory (the
  // per-frame gather of face normals is bound by memory latency).
  std::stable_sort(triangles_.begin(), triangles_.end(), [](const Triangle& a, const Triangle& b) {
    return std::min({a[0], a[1], a[2]}) < std::min({b[0], b[1], b[2]});
  });
  incident_offset_.assign(count + 1, 0);
  for (const Triangle& t : triangles_)
    for (std::uint32_t v : t)
      if (v < count) ++incident_offset_[v + 1];
  for (std::size_t i = 0; i < count; ++i) incident_offset_[i + 1] += incident_offset_[i];
  incident_.resize(incident_offset_.back());
  std::vector<std::uint32_t> fill(incident_offset_.begin(), incident_offset_.end() - 1);
  for (std::size_t t = 0; t < triangles_.size(); ++t)
    for (std::uint32_t v : triangles_[t])
      if (v < count) incident_[fill[v]++] = static_cast<std::uint32_t>(t);
  const Eigen::Index n = static_cast<Eigen::Index>(count);
  face_normals_.resize(3, static_cast<Eigen::Index>(triangles_.size()));
  normal_.resize(3, n);
  tangent_.resize(3, n);
  bitangent_.resize(3, n);
  degenerate_.resize(n);
  coefficients_.resize(3, n);

  // The reference neighbour: the one with the longest part in the tangent plane (ties to
  // the lowest index), fixed now so that the frame turns with the surface instead of
  // jumping between neighbours.
  reference_.assign(count, 0);
  for (std::size_t i = 0; i < count; ++i) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (std::uint32_t e = incident_offset_[i]; e < incident_offset_[i + 1]; ++e) {
      const Triangle& t = triangles_[incident_[e]];
      const Eigen::Vector3d a = base.col(t[0]);
      sum += (base.col(t[1]) - a).cross(base.col(t[2]) - a);
    }
    const Eigen::Vector3d normal = sum.norm() > 0 ? Eigen::Vector3d(sum.normalized()) : Eigen::Vector3d::Zero();
    double best = -1;
    for (std::uint32_t e = incident_offset_[i]; e < incident_offset_[i + 1]; ++e)
      for (std::uint32_t j : triangles_[incident_[e]]) {
        if (j == i) continue;
        const Eigen::Vector3d d = base.col(j) - base.col(static_cast<Eigen::Index>(i));
        const double tangential = (d - d.dot(normal) * normal).norm();
        if (tangential > best || (tangential == best && j < reference_[i])) {
          best = tangential;
          reference_[i] = j;
        }
      }
  }

  frames(base);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d d = detailed.col(i) - base.col(i);
    if (degenerate_[i]) {
      coefficients_.col(i) = d;
    } else {
      coefficients_(0, i) = d.dot(normal_.col(i).matrix());
      coefficients_(1, i) = d.dot(tangent_.col(i).matrix());
      coefficients_(2, i) = d.dot(bitangent_.col(i).matrix());
    }
  }
}

void NormalDetail::frames(const Eigen::Ref<const Eigen::Matrix3Xd>& base) const {
  const Eigen::Index n = static_cast<Eigen::Index>(reference_.size());
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const Triangle& tri = triangles_[t];
    const Eigen::Vector3d a = base.col(tri[0]);
    // Twice the area times the unit normal: area-weighted vertex normals.
    face_normals_.col(static_cast<Eigen::Index>(t)) = (base.col(tri[1]) - a).cross(base.col(tri[2]) - a);
  }
  // Gather: summed face normals into normal_, the direction to the reference into tangent_.
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (std::uint32_t e = incident_offset_[static_cast<std::size_t>(i)]; e < incident_offset_[static_cast<std::size_t>(i) + 1]; ++e)
      sum += face_normals_.col(incident_[e]);
    normal_.col(i) = sum;
    tangent_.col(i) = base.col(reference_[static_cast<std::size_t>(i)]) - base.col(i);
  }
  // Row arithmetic: n = sum/|sum|, t = (d − (d·n)n)/|…|, b = n × t.
  const Eigen::Array<double, 1, Eigen::Dynamic> length2 =
      normal_.row(0).square() + normal_.row(1).square() + normal_.row(2).square();
  const Eigen::Array<double, 1, Eigen::Dynamic> reference2 =
      tangent_.row(0).square() + tangent_.row(1).square() + tangent_.row(2).square();
  const Eigen::Array<double, 1, Eigen::Dynamic> inverse_length = length2.sqrt().inverse();
  for (int r = 0; r < 3; ++r) normal_.row(r) *= inverse_length;
  const Eigen::Array<double, 1, Eigen::Dynamic> along =
      tangent_.row(0) * normal_.row(0) + tangent_.row(1) * normal_.row(1) + tangent_.row(2) * normal_.row(2);
  for (int r = 0; r < 3; ++r) tangent_.row(r) -= along * normal_.row(r);
  const Eigen::Array<double, 1, Eigen::Dynamic> tangent2 =
      tangent_.row(0).square() + tangent_.row(1).square() + tangent_.row(2).square();
  const Eigen::Array<double, 1, Eigen::Dynamic> inverse_tangent = tangent2.sqrt().inverse();
  for (int r = 0; r < 3; ++r) tangent_.row(r) *= inverse_tangent;
  bitangent_.row(0) = normal_.row(1) * tangent_.row(2) - normal_.row(2) * tangent_.row(1);
  bitangent_.row(1) = normal_.row(2) * tangent_.row(0) - normal_.row(0) * tangent_.row(2);
  bitangent_.row(2) = normal_.row(0) * tangent_.row(1) - normal_.row(1) * tangent_.row(0);
  // Degenerate: no normal, or a reference direction (nearly) along the normal.
  degenerate_ = !(length2 > 0) || !(tangent2 > 1e-24 * reference2);
}

void NormalDetail::reconstruct(const Eigen::Ref<const Eigen::Matrix3Xd>& base, Eigen::Ref<Eigen::Matrix3Xd> out,
                               const std::vector<std::uint32_t>& columns) const {
  frames(base);
  const Eigen::Index n = static_cast<Eigen::Index>(reference_.size());
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto c = coefficients_.col(i);
    const std::uint32_t target = columns[static_cast<std::size_t>(i)];
    if (degenerate_[i])
      out.col(target) = base.col(i) + c.matrix();
    else
      out.col(target) = base.col(i) + (c[0] * normal_.col(i) + c[1] * tangent_.col(i) + c[2] * bitangent_.col(i)).matrix();
  }
}

}  // namespace ffd
