// ScatteredDeformer: what the deformers whose control points are a plain list share (RBF
// centres, IDW points, cage vertices): one level, points named by their number 0..n-1,
// all movable, no grid; a global map, so a move re-evaluates every point; the batch
// evaluation is apply(x, J) at each point, in parallel (static schedule: the same result
// at any thread count).
//
// A kind provides apply(x, J) and, in update_after_move(), brings its coefficients up to
// date after move_points() placed the targets.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "warp/deformer.h"

namespace ffd {

class ScatteredDeformer : public Deformer {
public:
  /// The points at rest, as the deformer was made.
  const std::vector<Eigen::Vector3d>& rest_points() const { return rest_; }

  // Deformer
  std::size_t num_points(int) const override { return rest_.size(); }
  Eigen::Matrix3Xd points(int level) const override;
  Eigen::Matrix3Xd points(int level, const std::vector<std::size_t>& ids) const override;
  bool grid_indexed() const override { return false; }
  std::optional<std::size_t> find_point(int, const PointIndex& index) const override;
  std::string missing_point(int level, const PointIndex& index) const override;
  PointIndex point_index(int, std::size_t id) const override { return {false, {0, 0, 0}, static_cast<long long>(id)}; }
  std::string movable_text(int) const override;
  MoveReport move_points(int level, const std::vector<std::size_t>& ids,
                         const std::vector<Eigen::Vector3d>& targets) override;
  std::vector<std::array<std::uint32_t, 2>> net_edges(int) const override { return {}; }
  /// The diagonal of the rest points' bounding box.
  double scale() const override;

  // Warp
  using Warp::apply;
  void apply(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const Eigen::Ref<const Eigen::Matrix3Xd>& in_nrm,
             const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
             Eigen::Ref<Eigen::Matrix3Xd> out_nrm, WarpCounts& counts) const override;
  /// Every point once a move happened: the map is global.
  void changed_points(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, std::vector<std::uint32_t>& ids) const override;
  bool has_changes() const override { return changed_; }
  void clear_changes() override { changed_ = false; }
  /// The smallest distance between two rest points: the finest scale of the control.
  double feature_size() const override { return spacing_; }

protected:
  /// `noun` names the points in messages: "control points", "cage vertices".
  /// \throw InputError about `subject` (the op's key) naming the first two rest points at
  /// the same place.
  ScatteredDeformer(std::vector<Eigen::Vector3d> rest, std::string noun, const std::string& subject = "points");
  /// Whether some point is off its rest position (else the map is the identity).
  bool moved() const { return moved_; }
  virtual void update_after_move() = 0;

  std::vector<Eigen::Vector3d> rest_, current_;

private:
  std::string noun_;
  double spacing_ = 0;
  bool moved_ = false, changed_ = false;
};

/// The smallest distance between two of `points` (a k-d tree's nearest neighbours), and in
/// `pair`, when given, the first pair at that distance: the lowest-numbered point with a
/// neighbour that near, and the lowest-numbered such neighbour. Infinity for fewer than
/// two points.
double smallest_spacing(const std::vector<Eigen::Vector3d>& points, std::array<std::size_t, 2>* pair = nullptr);

}  // namespace ffd
