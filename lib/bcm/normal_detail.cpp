#include "bcm/normal_detail.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Geometry>

#include "bcm/triangle_normals.h"

namespace ffd {

NormalDetail::NormalDetail(const Eigen::Ref<const Eigen::Matrix3Xd>& base, const Eigen::Ref<const Eigen::Matrix3Xd>& detailed,
                           std::size_t count, const std::vector<Triangle>& triangles)
    : count_(count) {
  number_slots(count, static_cast<std::size_t>(base.cols()), triangles);
  positions_.setZero(4, static_cast<Eigen::Index>(slots_.size()));
  face_normals_.resize(4, static_cast<Eigen::Index>(triangles_.size()));
  // Whole blocks, zeros past count: reconstruction reads a block's coefficients as rows.
  coefficients_.setZero(3, static_cast<Eigen::Index>((count + kBlock - 1) / kBlock * kBlock));
  choose_references(base);
  gather(base);
  face_normals();
  Block3 normal, tangent, bitangent;
  BlockFlags flat;
  for (long first = 0; first < static_cast<long>(count); first += kBlock) {
    block_frames(first, normal, tangent, bitangent, flat);
    for (long j = 0; j < kBlock && first + j < static_cast<long>(count); ++j) {
      const long s = first + j;
      const std::uint32_t v = slots_[static_cast<std::size_t>(s)];
      const Eigen::Vector3d d = detailed.col(v) - base.col(v);
      if (flat[j]) {
        coefficients_.col(s) = d;
      } else {
        coefficients_(0, s) = d.dot(normal.col(j).matrix());
        coefficients_(1, s) = d.dot(tangent.col(j).matrix());
        coefficients_(2, s) = d.dot(bitangent.col(j).matrix());
      }
    }
  }
}

void NormalDetail::number_slots(std::size_t count, std::size_t n, const std::vector<Triangle>& triangles) {
  std::vector<Triangle> local;
  for (const Triangle& t : triangles)
    if (t[0] < count || t[1] < count || t[2] < count) local.push_back(t);
  std::vector<std::uint32_t> offset(n + 1, 0), around;
  for (const Triangle& t : local)
    for (std::uint32_t v : t) ++offset[v + 1];
  for (std::size_t v = 0; v < n; ++v) offset[v + 1] += offset[v];
  around.resize(offset.back());
  std::vector<std::uint32_t> fill(offset.begin(), offset.end() - 1);
  for (std::size_t t = 0; t < local.size(); ++t)
    for (std::uint32_t v : local[t]) around[fill[v]++] = static_cast<std::uint32_t>(t);
  // Detail vertices breadth first, each connected part from its lowest vertex; then the rest.
  std::vector<std::uint32_t> slot_of(n, UINT32_MAX);
  slots_.clear();
  const auto take = [&](std::uint32_t v) {
    slot_of[v] = static_cast<std::uint32_t>(slots_.size());
    slots_.push_back(v);
  };
  for (std::uint32_t seed = 0; seed < count; ++seed) {
    if (slot_of[seed] != UINT32_MAX) continue;
    take(seed);
    for (std::size_t q = slots_.size() - 1; q < slots_.size(); ++q)
      for (std::uint32_t e = offset[slots_[q]]; e < offset[slots_[q] + 1]; ++e)
        for (std::uint32_t u : local[around[e]])
          if (u < count && slot_of[u] == UINT32_MAX) take(u);
  }
  for (const Triangle& t : local)
    for (std::uint32_t u : t)
      if (slot_of[u] == UINT32_MAX) take(u);
  slot_of_ = slot_of;
  // Triangles in slots, by lowest slot, so that a vertex's triangles sit close together.
  triangles_.clear();
  for (const Triangle& t : local) triangles_.push_back({slot_of[t[0]], slot_of[t[1]], slot_of[t[2]]});
  std::stable_sort(triangles_.begin(), triangles_.end(), [](const Triangle& a, const Triangle& b) {
    return std::min({a[0], a[1], a[2]}) < std::min({b[0], b[1], b[2]});
  });
  incident_offset_.assign(count + 1, 0);
  for (const Triangle& t : triangles_)
    for (std::uint32_t s : t)
      if (s < count) ++incident_offset_[s + 1];
  for (std::size_t s = 0; s < count; ++s) incident_offset_[s + 1] += incident_offset_[s];
  incident_.resize(incident_offset_.back());
  std::vector<std::uint32_t> next(incident_offset_.begin(), incident_offset_.end() - 1);
  for (std::size_t t = 0; t < triangles_.size(); ++t)
    for (std::uint32_t s : triangles_[t])
      if (s < count) incident_[next[s]++] = static_cast<std::uint32_t>(t);
}

void NormalDetail::choose_references(const Eigen::Ref<const Eigen::Matrix3Xd>& base) {
  reference_.assign(count_, 0);
  for (std::size_t s = 0; s < count_; ++s) {
    const Eigen::Vector3d p = base.col(slots_[s]);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (std::uint32_t e = incident_offset_[s]; e < incident_offset_[s + 1]; ++e) {
      const Triangle& t = triangles_[incident_[e]];
      const Eigen::Vector3d a = base.col(slots_[t[0]]);
      sum += (base.col(slots_[t[1]]) - a).cross(base.col(slots_[t[2]]) - a);
    }
    const Eigen::Vector3d normal = sum.norm() > 0 ? Eigen::Vector3d(sum.normalized()) : Eigen::Vector3d::Zero();
    double best = -1;
    for (std::uint32_t e = incident_offset_[s]; e < incident_offset_[s + 1]; ++e)
      for (std::uint32_t j : triangles_[incident_[e]]) {
        if (j == s) continue;
        const Eigen::Vector3d d = base.col(slots_[j]) - p;
        const double tangential = (d - d.dot(normal) * normal).norm();
        if (tangential > best || (tangential == best && slots_[j] < slots_[reference_[s]])) {
          best = tangential;
          reference_[s] = j;
        }
      }
  }
}

void NormalDetail::gather(const Eigen::Ref<const Eigen::Matrix3Xd>& base) const {
  const long slots = static_cast<long>(slots_.size());
  // Inside a parallel region this loop shares the work; outside it it runs alone.
#pragma omp for schedule(static)
  for (long s = 0; s < slots; ++s) positions_.col(s).head<3>() = base.col(slots_[static_cast<std::size_t>(s)]);
}

void NormalDetail::face_normals() const {
  // Twice the area times the unit normal: area-weighted vertex normals.
  static_assert(sizeof(Triangle) == 3 * sizeof(std::uint32_t), "triangles are three corners apart");
  constexpr long kRun = 1024;  // triangles per share of the work
  const long faces = static_cast<long>(triangles_.size()), runs = (faces + kRun - 1) / kRun;
  const std::uint32_t* corners = triangles_.empty() ? nullptr : triangles_.front().data();
#pragma omp for schedule(static)
  for (long run = 0; run < runs; ++run)
    triangle_normals(positions_.data(), corners, run * kRun, std::min(faces, (run + 1) * kRun), face_normals_.data());
}

void NormalDetail::block_frames(long first, Block3& n, Block3& t, Block3& b, BlockFlags& flat) const {
  // Gather: summed face normals into n, the direction to the reference into t.
  for (long j = 0; j < kBlock; ++j) {
    const std::size_t s = static_cast<std::size_t>(first + j);
    if (s >= count_) {  // padding: any regular frame
      n.col(j) = Eigen::Vector3d::UnitZ().array();
      t.col(j) = Eigen::Vector3d::UnitX().array();
      continue;
    }
    Eigen::Vector4d sum = Eigen::Vector4d::Zero();
    for (std::uint32_t e = incident_offset_[s]; e < incident_offset_[s + 1]; ++e) sum += face_normals_.col(incident_[e]);
    n.col(j) = sum.head<3>().array();
    t.col(j) = (positions_.col(reference_[s]).head<3>() - positions_.col(static_cast<Eigen::Index>(s)).head<3>()).array();
  }
  // Row arithmetic: n = sum/|sum|, t = (d − (d·n)n)/|…|, b = n × t.
  using Row = Eigen::Array<double, 1, kBlock>;
  const Row length2 = n.row(0).square() + n.row(1).square() + n.row(2).square();
  const Row reference2 = t.row(0).square() + t.row(1).square() + t.row(2).square();
  const Row inverse_length = length2.sqrt().inverse();
  for (int r = 0; r < 3; ++r) n.row(r) *= inverse_length;
  const Row along = t.row(0) * n.row(0) + t.row(1) * n.row(1) + t.row(2) * n.row(2);
  for (int r = 0; r < 3; ++r) t.row(r) -= along * n.row(r);
  const Row tangent2 = t.row(0).square() + t.row(1).square() + t.row(2).square();
  const Row inverse_tangent = tangent2.sqrt().inverse();
  for (int r = 0; r < 3; ++r) t.row(r) *= inverse_tangent;
  b.row(0) = n.row(1) * t.row(2) - n.row(2) * t.row(1);
  b.row(1) = n.row(2) * t.row(0) - n.row(0) * t.row(2);
  b.row(2) = n.row(0) * t.row(1) - n.row(1) * t.row(0);
  // Degenerate: no normal, or a reference direction (nearly) along the normal. A bitwise |,
  // so that the tests run over the whole block as vectors (|| made them a branch per slot).
  for (int j = 0; j < kBlock; ++j) flat[j] = !(length2[j] > 0) | !(tangent2[j] > 1e-24 * reference2[j]);
}

void NormalDetail::block_detail(long first, const Block3& n, const Block3& t, const Block3& b, const BlockFlags& flat,
                                Block3& detail) const {
  const auto rows = [](const Block3& a) {
    return std::array<const double*, 3>{a.row(0).data(), a.row(1).data(), a.row(2).data()};
  };
  const double* const c[3] = {coefficients_.row(0).data() + first, coefficients_.row(1).data() + first,
                              coefficients_.row(2).data() + first};
  const auto n_rows = rows(n), t_rows = rows(t), b_rows = rows(b);
  double* const out[3] = {detail.row(0).data(), detail.row(1).data(), detail.row(2).data()};
  // The flags as bytes (a bool is one byte, 0 or 1): GCC vectorizes a select on those.
  const auto* flags = reinterpret_cast<const unsigned char*>(flat.data());
  detail_rows(c, n_rows.data(), t_rows.data(), b_rows.data(), flags, out);
}

void NormalDetail::reconstruct(const Eigen::Ref<const Eigen::Matrix3Xd>& base, Eigen::Ref<Eigen::Matrix3Xd> out,
                               const std::vector<std::uint32_t>& columns) const {
#pragma omp parallel
  {
    gather(base);
    reconstruct_in_team(out, columns);
  }
}

void NormalDetail::reconstruct_in_team(Eigen::Ref<Eigen::Matrix3Xd> out, const std::vector<std::uint32_t>& columns) const {
  const long count = static_cast<long>(count_), blocks = (count + kBlock - 1) / kBlock;
  // Two passes shared by the team, each element written by one thread with the same
  // arithmetic whatever their number: the face normals, then per block of detail slots
  // their frames and their detail added back, straight into `out`.
  face_normals();
  Block3 normal, tangent, bitangent, detail;
  BlockFlags flat;
  // No barrier after the last pass: the caller's team ends right after (the end of its
  // parallel region waits for every thread).
#pragma omp for schedule(static) nowait
  for (long block = 0; block < blocks; ++block) {
    const long first = block * kBlock;
    block_frames(first, normal, tangent, bitangent, flat);
    block_detail(first, normal, tangent, bitangent, flat, detail);
    for (long j = 0; j < kBlock && first + j < count; ++j) {
      const long s = first + j;
      out.col(columns[slots_[static_cast<std::size_t>(s)]]) = positions_.col(s).head<3>() + detail.col(j).matrix();
    }
  }
}

Eigen::Matrix3Xd NormalDetail::coefficients() const {
  Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(count_));
  for (std::size_t s = 0; s < count_; ++s) out.col(slots_[s]) = coefficients_.col(static_cast<Eigen::Index>(s)).matrix();
  return out;
}

}  // namespace ffd
