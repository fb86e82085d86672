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
#include "bcm/detail_rows.h"

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

  std::size_t size() const { return count_; }

  /// out.col(columns[i]) = base_i + α_i n_i + β_i t_i + γ_i (n_i × t_i) for i < size(),
  /// with the frames of the moved `base` (3 × n). No allocation; runs on all cores and
  /// gives the same result whatever their number.
  void reconstruct(const Eigen::Ref<const Eigen::Matrix3Xd>& base, Eigen::Ref<Eigen::Matrix3Xd> out,
                   const std::vector<std::uint32_t>& columns) const;
  /// The base as the detail holds it, one column per slot: a caller that moves the base
  /// itself writes the moved positions here (rows 0-2 of column slot(v) for vertex v; row 3
  /// stays zero) and then calls reconstruct_in_team(), saving reconstruct()'s copy of the
  /// whole base.
  Eigen::Matrix4Xd& base_in_slots() const { return positions_; }
  /// Vertex v's column in base_in_slots(), or UINT32_MAX where the detail does not read it.
  std::uint32_t slot(std::uint32_t v) const { return v < slot_of_.size() ? slot_of_[v] : UINT32_MAX; }
  /// reconstruct() from base_in_slots(), called by every thread of an enclosing OpenMP team
  /// (they share the work). Its last pass ends without a barrier: `out` is complete at the
  /// team's next barrier or the end of its parallel region.
  void reconstruct_in_team(Eigen::Ref<Eigen::Matrix3Xd> out, const std::vector<std::uint32_t>& columns) const;

  /// The stored coefficients (α normal, β tangent, γ bitangent), 3 × size(), by vertex.
  Eigen::Matrix3Xd coefficients() const;

private:
  // Rows x, y, z of per-vertex vectors, so that the frame arithmetic runs on whole rows
  // (vectorized square roots and divisions).
  using Rows3 = Eigen::Array<double, 3, Eigen::Dynamic, Eigen::RowMajor>;

  // Numbers the vertices in slots: the detail vertices first, breadth first over their
  // triangles (neighbours close together in memory, however the file ordered them), then
  // the other vertices of their triangles. Fills slot_of_, triangles_ and incident_*.
  void number_slots(std::size_t count, std::size_t n, const std::vector<Triangle>& triangles);
  // Copies `base` into the slots.
  void gather(const Eigen::Ref<const Eigen::Matrix3Xd>& base) const;
  // The face normals from the slots.
  void face_normals() const;
  // The frames of detail slots first .. first + kBlock − 1 (past size(): padding),
  // after gather(): normal, tangent and bitangent rows, and where they are degenerate (the
  // world axes stand in). The one routine for encoding and reconstructing, so that an
  // unchanged base reproduces the surface.
  static constexpr int kBlock = kDetailRowLength;  // detail slots per block of frame arithmetic (fits in L1)
  using Block3 = Eigen::Array<double, 3, kBlock, Eigen::RowMajor>;
  using BlockFlags = Eigen::Array<bool, 1, kBlock>;
  void block_frames(long first, Block3& normal, Block3& tangent, Block3& bitangent, BlockFlags& flat) const;
  // The detail of those slots in those frames (detail_rows.h), one row per coordinate.
  void block_detail(long first, const Block3& normal, const Block3& tangent, const Block3& bitangent,
                    const BlockFlags& flat, Block3& detail) const;
  // The reference neighbour of each detail slot (the longest part in the tangent plane,
  // ties to the lowest vertex), fixed at encoding so that the frame turns with the surface
  // instead of jumping between neighbours.
  void choose_references(const Eigen::Ref<const Eigen::Matrix3Xd>& base);

  std::size_t count_ = 0;
  std::vector<std::uint32_t> slots_;      // slot -> local vertex
  std::vector<std::uint32_t> slot_of_;    // vertex -> its slot (UINT32_MAX: none)
  std::vector<Triangle> triangles_;       // those with a detail vertex, in slots
  std::vector<std::uint32_t> incident_offset_, incident_;  // triangles around each detail slot
  std::vector<std::uint32_t> reference_;  // tangent reference neighbour per detail slot, a slot
  Rows3 coefficients_;                    // per detail slot, in whole blocks (zeros past count_)
  // Scratch, sized once.
  // Per slot: rows x, y, z and a zero, so that the face normals load each corner as one
  // 4-wide vector (triangle_normals.h).
  mutable Eigen::Matrix4Xd positions_;
  // Rows x, y, z and a zero: each face normal is one aligned 4-wide load, and the sum
  // around a vertex one 4-wide add per triangle: the same additions, coordinate by
  // coordinate, as with three scalars, in about half the instructions.
  mutable Eigen::Matrix4Xd face_normals_;
};

}  // namespace ffd
