// Multiresolution detail for boundary-constraint modeling (Botsch & Kobbelt section 4,
// after Kobbelt et al. 1998/1999): detail = surface − smooth base, stored per vertex in
// the base's local frame (normal, tangent, bitangent), so that after the base is edited
// the detail is added back in the moved frames and bumps follow the surface's turn.
//
// The paper's normal displacements (Kobbelt et al. 1999) attach each detail vertex to a
// foot point on the base along the base normal, which needs a projection onto the base.
// Here the displacement is attached to the base vertex of the same index instead, with
// its normal component and the (small) tangential rest, so that no projection is needed
// and an unmoved base gives back the input surface exactly (up to rounding).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "bcm/cotan_laplacian.h"

namespace ffd {

/// Detail of vertices 0 .. count−1 of a local vertex set over a base surface.
///
/// The frame at vertex i is n_i, the unit area-weighted normal of the base's triangles
/// around i; t_i, the direction to a reference neighbour (chosen at encoding: the longest
/// in the tangent plane) projected onto the tangent plane; and n_i × t_i. Where the base is
/// degenerate (a zero normal or tangent) the world axes stand in, so output stays finite.
/// Reconstructing with the unchanged base returns the detailed surface (up to rounding).
class NormalDetail {
public:
  NormalDetail() = default;
  /// Encodes `detailed − base` at columns 0 .. count−1. `base` and `detailed` are 3 × n;
  /// `triangles` (local indices) must include every triangle around those vertices.
  NormalDetail(const Eigen::Ref<const Eigen::Matrix3Xd>& base, const Eigen::Ref<const Eigen::Matrix3Xd>& detailed,
               std::size_t count, const std::vector<Triangle>& triangles);

  std::size_t size() const { return reference_.size(); }

  /// out.col(columns[i]) = base_i + α_i n_i + β_i t_i + γ_i (n_i × t_i) for i < size(),
  /// with the frames of the moved `base` (3 × n). No allocation.
  void reconstruct(const Eigen::Ref<const Eigen::Matrix3Xd>& base, Eigen::Ref<Eigen::Matrix3Xd> out,
                   const std::vector<std::uint32_t>& columns) const;

  /// The stored coefficients (α normal, β tangent, γ bitangent), 3 × size().
  Eigen::Matrix3Xd coefficients() const { return coefficients_.matrix(); }

private:
  // Rows x, y, z of per-vertex vectors, so that the frame arithmetic runs on whole rows
  // (vectorized square roots and divisions).
  using Rows3 = Eigen::Array<double, 3, Eigen::Dynamic, Eigen::RowMajor>;

  // The frames at the base: normal_, tangent_, bitangent_ and degenerate_ (1 where the
  // world axes stand in). The one routine for encoding and reconstructing, so that an
  // unchanged base reproduces the surface.
  void frames(const Eigen::Ref<const Eigen::Matrix3Xd>& base) const;

  std::vector<Triangle> triangles_;       // those with a detail vertex
  std::vector<std::uint32_t> incident_offset_, incident_;  // triangles around each detail vertex
  std::vector<std::uint32_t> reference_;  // tangent reference neighbour per vertex
  Rows3 coefficients_;
  // Scratch, sized once.
  mutable Eigen::Matrix3Xd face_normals_;
  mutable Rows3 normal_, tangent_, bitangent_;
  mutable Eigen::Array<bool, 1, Eigen::Dynamic> degenerate_;
};

}  // namespace ffd
