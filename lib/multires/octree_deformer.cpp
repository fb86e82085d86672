// OctreeLattice's side of the Deformer seam: points named by grid node, moves and weights
// by point index (octree_lattice.cpp, octree_warp.cpp do the work).
#include "multires/octree_lattice.h"

namespace ffd {

std::string octree_points_text(int level, int resolution) {
  return "the corners of level " + std::to_string(level) + "'s cells, grid nodes [i, j, k] in [0, " +
         std::to_string(resolution) + "]";
}

std::string OctreeLattice::movable_text(int level) const { return octree_points_text(level, resolution(level)); }

std::optional<std::size_t> OctreeLattice::find_point(int level, const PointIndex& index) const {
  if (!index.grid) return std::nullopt;
  const std::int32_t id = point_index(level, index.ijk);
  if (id < 0) return std::nullopt;
  return static_cast<std::size_t>(id);
}

std::string OctreeLattice::missing_point(int level, const PointIndex& index) const {
  if (const std::optional<std::string> form = index_form_problem(index, true, "points")) return *form;
  return "point " + index.text() + " is no corner of a cell of level " + std::to_string(level) +
         " (its cells were cut: they hold no vertex of the region)";
}

PointIndex OctreeLattice::point_index(int level, std::size_t id) const {
  PointIndex index;
  index.ijk = is_local(level) ? local(level).nodes()[id] : complex(level).points[id];
  return index;
}

MoveReport OctreeLattice::move_points(int level, const std::vector<std::size_t>& ids,
                                      const std::vector<Eigen::Vector3d>& targets) {
  const std::vector<std::int32_t> points(ids.begin(), ids.end());
  const OctreeMove moved = move_level_points(level, points, targets);
  MoveReport report;
  report.points_moved = moved.points_moved;
  report.counts = {{"cells_subdivided", moved.cells_subdivided, "cells subdivided"},
                   {"cells_relocated", moved.cells_marked, ""}};
  return report;
}

void OctreeLattice::movable_weights(int level, const Eigen::Vector3d& x, PointWeights& out) const {
  std::vector<std::pair<std::int32_t, double>> weights;
  point_weights(level, x, weights);
  out.clear();
  for (const auto& [p, w] : weights) out.emplace_back(static_cast<std::size_t>(p), w);
}

std::vector<std::array<std::uint32_t, 2>> OctreeLattice::net_edges(int level) const {
  std::vector<std::array<std::uint32_t, 2>> out;
  for (const auto& e : edges(level)) out.push_back({static_cast<std::uint32_t>(e[0]), static_cast<std::uint32_t>(e[1])});
  return out;
}

}  // namespace ffd
