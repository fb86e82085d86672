#include "warp/scattered_deformer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/errors.h"
#include "warp/point_tree.h"

namespace ffd {
double smallest_spacing(const std::vector<Eigen::Vector3d>& points, std::array<std::size_t, 2>* pair) {
  double best = std::numeric_limits<double>::infinity();
  if (points.size() < 2) return best;
  const PointTree tree(points);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto [j, d] = tree.nearest_other(i);
    if (d < best) {
      best = d;
      if (pair) *pair = {std::min(i, j), std::max(i, j)};
    }
  }
  return best;
}

ScatteredDeformer::ScatteredDeformer(std::vector<Eigen::Vector3d> rest, std::string noun, const std::string& subject)
    : rest_(std::move(rest)), current_(rest_), noun_(std::move(noun)) {
  // One pass of nearest neighbours gives the spacing and the first two points at one
  // place (the lowest-numbered point that has a twin, and its lowest-numbered twin).
  std::array<std::size_t, 2> pair{0, 0};
  spacing_ = smallest_spacing(rest_, &pair);
  if (spacing_ == 0)
    throw InputError(noun_ + " " + std::to_string(pair[0]) + " and " + std::to_string(pair[1]) + " are at the same place",
                     {subject});
  if (!std::isfinite(spacing_)) spacing_ = 0;
}

Eigen::Matrix3Xd ScatteredDeformer::points(int) const {
  Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(current_.size()));
  for (std::size_t i = 0; i < current_.size(); ++i) out.col(static_cast<Eigen::Index>(i)) = current_[i];
  return out;
}

Eigen::Matrix3Xd ScatteredDeformer::points(int, const std::vector<std::size_t>& ids) const {
  Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(ids.size()));
  for (std::size_t i = 0; i < ids.size(); ++i) out.col(static_cast<Eigen::Index>(i)) = current_[ids[i]];
  return out;
}

std::optional<std::size_t> ScatteredDeformer::find_point(int, const PointIndex& index) const {
  if (index.grid || index.n < 0 || static_cast<std::size_t>(index.n) >= rest_.size()) return std::nullopt;
  return static_cast<std::size_t>(index.n);
}

std::string ScatteredDeformer::missing_point(int level, const PointIndex& index) const {
  if (const std::optional<std::string> form = index_form_problem(index, false, noun_)) return *form;
  return "point " + index.text() + " is not one of its " + noun_ + " (" + movable_text(level) + ")";
}

std::string ScatteredDeformer::movable_text(int) const {
  return noun_ + " 0 to " + std::to_string(rest_.size() - 1);
}

MoveReport ScatteredDeformer::move_points(int, const std::vector<std::size_t>& ids,
                                          const std::vector<Eigen::Vector3d>& targets) {
  for (std::size_t i = 0; i < ids.size(); ++i) current_.at(ids[i]) = targets[i];
  moved_ = current_ != rest_;
  changed_ = changed_ || !ids.empty();
  update_after_move();
  MoveReport report;
  report.points_moved = ids.size();
  return report;
}

double ScatteredDeformer::scale() const {
  Eigen::Vector3d lo = rest_[0], hi = rest_[0];
  for (const Eigen::Vector3d& p : rest_) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  return (hi - lo).norm();
}

void ScatteredDeformer::apply(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                              const Eigen::Ref<const Eigen::Matrix3Xd>& in_nrm, const std::vector<std::uint32_t>& ids,
                              Eigen::Ref<Eigen::Matrix3Xd> out_pos, Eigen::Ref<Eigen::Matrix3Xd> out_nrm,
                              WarpCounts& counts) const {
  std::size_t folded = 0;
  const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(ids.size());
#pragma omp parallel for schedule(static) reduction(+ : folded)
  for (std::ptrdiff_t t = 0; t < count; ++t) {
    const std::uint32_t v = ids[static_cast<std::size_t>(t)];
    Eigen::Matrix3d J;
    out_pos.col(v) = apply(in_pos.col(v), &J);
    out_nrm.col(v) = J.isIdentity(0.0) ? Eigen::Vector3d(in_nrm.col(v)) : transformed_normal(J, in_nrm.col(v));
    if (J.determinant() <= 0) ++folded;
  }
  counts.folded += folded;
  counts.evaluated += ids.size();
}

void ScatteredDeformer::changed_points(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                                       std::vector<std::uint32_t>& ids) const {
  if (!changed_) return;
  for (Eigen::Index v = 0; v < in_pos.cols(); ++v) ids.push_back(static_cast<std::uint32_t>(v));
}

}  // namespace ffd
