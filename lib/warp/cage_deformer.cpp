#include "warp/cage_deformer.h"

#include <cmath>
#include <map>
#include <type_traits>

#include "common/errors.h"

namespace ffd {
namespace {

std::string edge_text(std::uint32_t a, std::uint32_t b) { return std::to_string(a) + "-" + std::to_string(b); }

/// \throw InputError about "cage" for a face with fewer than 3 corners or a repeated corner.
void check_faces(const std::vector<std::vector<std::uint32_t>>& faces) {
  if (faces.empty()) throw InputError("the cage has no faces", {"cage"});
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& face = faces[f];
    if (face.size() < 3) throw InputError("cage face " + std::to_string(f) + " has fewer than 3 corners", {"cage"});
    for (std::size_t i = 0; i < face.size(); ++i)
      for (std::size_t j = i + 1; j < face.size(); ++j)
        if (face[i] == face[j])
          throw InputError("cage face " + std::to_string(f) + " uses vertex " + std::to_string(face[i]) + " twice",
                           {"cage"});
  }
}

/// \throw InputError about "cage" naming the first edge (in face order) used twice in one
/// direction, then the first with no face on its other side.
void check_closed_and_oriented(const std::vector<std::vector<std::uint32_t>>& faces) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::size_t> directed;  // (a, b) -> its face
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (std::size_t i = 0; i < faces[f].size(); ++i) {
      const std::uint32_t a = faces[f][i], b = faces[f][(i + 1) % faces[f].size()];
      const auto [at, fresh] = directed.emplace(std::make_pair(a, b), f);
      if (!fresh)
        throw InputError("cage edge " + edge_text(a, b) + " is used in the same direction by faces " +
                             std::to_string(at->second) + " and " + std::to_string(f) +
                             ": the cage is not consistently oriented (or more than two faces share the edge)",
                         {"cage"});
    }
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (std::size_t i = 0; i < faces[f].size(); ++i) {
      const std::uint32_t a = faces[f][i], b = faces[f][(i + 1) % faces[f].size()];
      if (!directed.count({b, a}))
        throw InputError("cage edge " + edge_text(a, b) + " of face " + std::to_string(f) +
                             " has no face on its other side: the cage is not closed",
                         {"cage"});
    }
}

/// \throw InputError about "cage" when the cage encloses no volume (a flat, two-sided cage):
/// its triangles' contributions cancel, and the coordinates would divide by zero.
void check_volume(const MeanValueCage& cage) {
  double volume = 0;  // six times the signed volume
  for (const auto& t : cage.triangles)
    volume += cage.points.col(t[0]).dot(cage.points.col(t[1]).cross(cage.points.col(t[2])));
  const double d = cage.diagonal;
  if (!(std::abs(volume) > 1e-12 * d * d * d))
    throw InputError("the cage encloses no volume (its faces lie in one plane, or it folds onto itself)", {"cage"});
}

}  // namespace

CageDeformer::CageDeformer(std::vector<Eigen::Vector3d> rest, std::vector<std::vector<std::uint32_t>> faces)
    : ScatteredDeformer(std::move(rest), "cage vertices", "cage"), faces_(std::move(faces)) {
  check_faces(faces_);
  check_closed_and_oriented(faces_);
  const Eigen::Index m = static_cast<Eigen::Index>(rest_.size());
  Eigen::Matrix3Xd points(3, m);
  for (Eigen::Index j = 0; j < m; ++j) points.col(j) = rest_[static_cast<std::size_t>(j)];
  std::vector<std::array<std::uint32_t, 3>> triangles;
  for (const auto& face : faces_)  // a fan from the first corner
    for (std::size_t i = 1; i + 1 < face.size(); ++i) triangles.push_back({face[0], face[i], face[i + 1]});
  rest_cage_ = mean_value_cage(std::move(points), std::move(triangles));
  check_volume(rest_cage_);
  moves_ = Eigen::Matrix3Xd::Zero(3, m);
}

void CageDeformer::update_after_move() {
  moved_ids_.clear();
  for (Eigen::Index j = 0; j < moves_.cols(); ++j) {
    moves_.col(j) = current_[static_cast<std::size_t>(j)] - rest_[static_cast<std::size_t>(j)];
    if (!moves_.col(j).isZero(0.0)) moved_ids_.push_back(j);
  }
  moves_float_ = moves_.cast<float>();
}

CageDeformer::Binding CageDeformer::bind(const Eigen::Ref<const Eigen::Matrix3Xd>& positions, bool gradients,
                                         std::size_t max_bytes, std::size_t& outside) {
  const double pairs = static_cast<double>(positions.cols()) * static_cast<double>(rest_.size());
  gradients = gradients && 20 * pairs <= static_cast<double>(max_bytes);
  bound_positions_.resize(3, 0);
  bound_weights_.resize(0, 0);
  bound_gradients_.resize(0, 0);
  if (8 * pairs > static_cast<double>(max_bytes)) {
    outside = count_outside(positions);
    return Binding::None;
  }
  const Eigen::Index m = static_cast<Eigen::Index>(rest_.size()), n = positions.cols();
  bound_positions_ = positions;
  bound_weights_.resize(m, n);
  if (gradients) bound_gradients_.resize(3 * m, n);
  std::size_t out = 0;
#pragma omp parallel for schedule(dynamic, 64) reduction(+ : out)
  for (Eigen::Index v = 0; v < n; ++v) {
    Eigen::VectorXd w;
    Eigen::Matrix3Xd g;
    double winding = 0;
    mean_value_coordinates(rest_cage_, positions.col(v), w, gradients ? &g : nullptr, &winding);
    bound_weights_.col(v) = w;
    if (gradients) bound_gradients_.col(v) = Eigen::Map<const Eigen::VectorXd>(g.data(), 3 * m).cast<float>();
    out += std::abs(winding) < 0.5;
  }
  outside = out;
  return gradients ? Binding::WeightsAndGradients : Binding::Weights;
}

std::size_t CageDeformer::count_outside(const Eigen::Ref<const Eigen::Matrix3Xd>& positions) const {
  std::size_t outside = 0;
  const Eigen::Index n = positions.cols();
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : outside)
  for (Eigen::Index v = 0; v < n; ++v) outside += std::abs(winding_number(rest_cage_, positions.col(v))) < 0.5;
  return outside;
}

void CageDeformer::movable_weights(int, const Eigen::Vector3d& x, PointWeights& out) const {
  out.clear();
  Eigen::VectorXd w;
  mean_value_coordinates(rest_cage_, x, w);
  for (Eigen::Index j = 0; j < w.size(); ++j)
    if (w[j] != 0) out.emplace_back(static_cast<std::size_t>(j), w[j]);
}

std::vector<std::array<std::uint32_t, 2>> CageDeformer::net_edges(int) const {
  std::vector<std::array<std::uint32_t, 2>> edges;
  for (const auto& face : faces_)
    for (std::size_t i = 0; i < face.size(); ++i) {
      const std::uint32_t a = face[i], b = face[(i + 1) % face.size()];
      if (a < b) edges.push_back({a, b});  // the closed cage has each edge once each way
    }
  return edges;
}

template <class G>
Eigen::Vector3d CageDeformer::displaced(const Eigen::Vector3d& x, const Eigen::Ref<const Eigen::VectorXd>& w,
                                        const G* g, Eigen::Matrix3d* jacobian) const {
  // Few cage vertices moved: sum over those only (the others' moves are zero).
  const bool few = 4 * moved_ids_.size() < static_cast<std::size_t>(moves_.cols());
  if (jacobian && g) {
    const Eigen::Map<const Eigen::Matrix<G, 3, Eigen::Dynamic>> gradient(g, 3, moves_.cols());
    jacobian->setIdentity();
    if (few) {
      for (Eigen::Index j : moved_ids_) *jacobian += moves_.col(j) * gradient.col(j).template cast<double>().transpose();
    } else if constexpr (std::is_same_v<G, float>) {  // bound gradients: a single-precision product
      *jacobian += (moves_float_ * gradient.transpose()).template cast<double>();
    } else {
      *jacobian += moves_ * gradient.transpose();
    }
  }
  if (!few) return x + moves_ * w;
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  for (Eigen::Index j : moved_ids_) d += w[j] * moves_.col(j);
  return x + d;
}

Eigen::Vector3d CageDeformer::apply(const Eigen::Vector3d& x, Eigen::Matrix3d* jacobian) const {
  if (!moved()) {  // unmoved: the identity, bit for bit
    if (jacobian) jacobian->setIdentity();
    return x;
  }
  Eigen::VectorXd w;
  Eigen::Matrix3Xd g;
  mean_value_coordinates(rest_cage_, x, w, jacobian ? &g : nullptr);
  return displaced(x, w, g.data(), jacobian);
}

void CageDeformer::apply(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const Eigen::Ref<const Eigen::Matrix3Xd>& in_nrm,
                         const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
                         Eigen::Ref<Eigen::Matrix3Xd> out_nrm, WarpCounts& counts) const {
  std::size_t folded = 0;
  const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(ids.size());
  const bool gradients = bound_gradients_.size() > 0;
#pragma omp parallel for schedule(static) reduction(+ : folded)
  for (std::ptrdiff_t t = 0; t < count; ++t) {
    const std::uint32_t v = ids[static_cast<std::size_t>(t)];
    const Eigen::Vector3d x = in_pos.col(v), n = in_nrm.col(v);
    const bool bound = v < bound_positions_.cols() && bound_positions_.col(v) == x;
    const bool want_jacobian = !n.isZero(0.0) || !bound || gradients;
    Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
    if (!moved())
      out_pos.col(v) = x;
    else if (bound)
      out_pos.col(v) = displaced(x, bound_weights_.col(v), gradients ? bound_gradients_.col(v).data() : nullptr, &J);
    if (moved() && (!bound || (want_jacobian && !gradients))) out_pos.col(v) = apply(x, &J);
    out_nrm.col(v) = J.isIdentity(0.0) ? n : transformed_normal(J, n);
    // (J stays I where it was not computed: unmoved, or bound without gradients and no normal.)
    if (want_jacobian && J.determinant() <= 0) ++folded;
  }
  counts.folded += folded;
  counts.evaluated += ids.size();
}

}  // namespace ffd
