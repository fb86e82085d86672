#include "warp/lattice.h"

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/numbers.h"
#include "common/ordered_select.h"

namespace ffd {
namespace {

constexpr int kMaxOrder = 32;  // Bernstein degree is capped below this by the script schema

}  // namespace

Lattice::Lattice(const Parallelepiped& box, Index3 cells) : box_(box), cells_(cells) {}

void Lattice::init_points(Index3 first, Index3 count) {
  first_ = first;
  count_ = count;
  displacement_.assign(static_cast<std::size_t>(count[0]) * count[1] * count[2],
                       Eigen::Vector3d::Zero());
  const Index3 n = pieces();
  changed_piece_.assign(static_cast<std::size_t>(n[0]) * n[1] * n[2], 0);
}

bool Lattice::in_range(const Index3& ijk) const {
  for (int a = 0; a < 3; ++a)
    if (ijk[a] < first_[a] || ijk[a] > last_index(a)) return false;
  return true;
}

std::size_t Lattice::flat(const Index3& ijk) const {
  return (static_cast<std::size_t>(ijk[2] - first_[2]) * count_[1] + (ijk[1] - first_[1])) * count_[0] +
         (ijk[0] - first_[0]);
}

Index3 Lattice::index(std::size_t f) const {
  Index3 ijk;
  ijk[0] = static_cast<int>(f % count_[0]) + first_[0];
  f /= count_[0];
  ijk[1] = static_cast<int>(f % count_[1]) + first_[1];
  ijk[2] = static_cast<int>(f / count_[1]) + first_[2];
  return ijk;
}

std::string Lattice::movable_range() const {
  static const char* names = "ijk";
  std::string s;
  for (int a = 0; a < 3; ++a) {
    int lo, hi;
    movable_span(a, lo, hi);
    if (a) s += ", ";
    s += names[a];
    if (lo > hi)
      s += " has none";
    else
      s += " in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  }
  return s;
}

Eigen::Vector3d Lattice::rest_point(const Index3& ijk) const {
  return box_.to_world(Eigen::Vector3d(node(0, ijk[0]), node(1, ijk[1]), node(2, ijk[2])));
}

void Lattice::move_point(const Index3& ijk, const Eigen::Vector3d& position) {
  if (!in_range(ijk) || !movable(ijk)) throw std::logic_error("move_point: point is not movable");
  displacement_[flat(ijk)] = position - rest_point(ijk);
  Index3 lo, hi;
  for (int a = 0; a < 3; ++a) pieces_of_point(a, ijk[a], lo[a], hi[a]);
  for (int k = lo[2]; k <= hi[2]; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int i = lo[0]; i <= hi[0]; ++i) {
        const std::size_t p = flat_piece({i, j, k});
        changed_piece_[p] = 1;
        piece_changed(p);
      }
  any_changed_ = true;
}

bool Lattice::boundary_moved() const {
  for (std::size_t f = 0; f < displacement_.size(); ++f) {
    if (displacement_[f].isZero(0.0)) continue;
    const Index3 ijk = index(f);
    for (int a = 0; a < 3; ++a) {
      const double t = node(a, ijk[a]);
      if (t <= 0 || t >= 1) return true;
    }
  }
  return false;
}

void Lattice::locate(int axis, double u, int& piece, double& local) const {
  const int n = pieces()[axis];
  const double s = u * n;
  piece = piece_at(s, n);
  local = s - piece;
}

void Lattice::movable_weights(const Eigen::Vector3d& x,
                              std::vector<std::pair<std::size_t, double>>& out) const {
  out.clear();
  const Eigen::Vector3d u = box_.to_local(x);
  if (!inside(u)) return;
  int first[3];
  double w[3][kMaxOrder], dw[3][kMaxOrder];
  for (int a = 0; a < 3; ++a) axis_weights(a, u[a], first[a], w[a], dw[a]);
  for (int c = 0; c < order(2); ++c)
    for (int b = 0; b < order(1); ++b)
      for (int a = 0; a < order(0); ++a) {
        const Index3 ijk{first[0] + a, first[1] + b, first[2] + c};
        const double weight = w[0][a] * w[1][b] * w[2][c];
        if (weight != 0 && movable(ijk)) out.emplace_back(flat(ijk), weight);
      }
}

Eigen::Vector3d Lattice::apply(const Eigen::Vector3d& x, Eigen::Matrix3d* jacobian) const {
  if (jacobian) jacobian->setIdentity();
  const Eigen::Vector3d u = box_.to_local(x);
  if (!inside(u)) return x;
  int first[3];
  double w[3][kMaxOrder], dw[3][kMaxOrder];
  for (int a = 0; a < 3; ++a) axis_weights(a, u[a], first[a], w[a], dw[a]);
  // Factorized contraction: sum over k first, then j, then i. The orders and the flat
  // index's steps are read once (order() asks the virtual degree(); asked in every loop
  // test, it was a sixth of the point evaluation that file normals are written through).
  const Index3 deg = degree();
  const int order0 = deg[0] + 1, order1 = deg[1] + 1, order2 = deg[2] + 1;
  const auto step_j = static_cast<std::size_t>(count_[0]), step_k = step_j * static_cast<std::size_t>(count_[1]);
  const std::size_t base = flat({first[0], first[1], first[2]});
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  Eigen::Matrix3d g = Eigen::Matrix3d::Zero();  // columns: dD/du, dD/dv, dD/dw
  for (int a = 0; a < order0; ++a) {
    Eigen::Vector3d sa = Eigen::Vector3d::Zero(), sa_v = sa, sa_w = sa;
    for (int b = 0; b < order1; ++b) {
      Eigen::Vector3d sb = Eigen::Vector3d::Zero(), sb_w = sb;
      const Eigen::Vector3d* column = displacement_.data() + base + static_cast<std::size_t>(a) + static_cast<std::size_t>(b) * step_j;
      for (int c = 0; c < order2; ++c) {
        const Eigen::Vector3d& p = column[static_cast<std::size_t>(c) * step_k];
        sb += w[2][c] * p;
        sb_w += dw[2][c] * p;
      }
      sa += w[1][b] * sb;
      sa_v += dw[1][b] * sb;
      sa_w += w[1][b] * sb_w;
    }
    d += w[0][a] * sa;
    g.col(0) += dw[0][a] * sa;
    g.col(1) += w[0][a] * sa_v;
    g.col(2) += w[0][a] * sa_w;
  }
  if (jacobian) *jacobian += g * box_.inverse_axes();
  return x + d;
}

void Lattice::apply(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                    const Eigen::Ref<const Eigen::Matrix3Xd>& in_nrm,
                    const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
                    Eigen::Ref<Eigen::Matrix3Xd> out_nrm, WarpCounts& counts) const {
  std::size_t folded = 0, evaluated = 0;
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(ids.size());
#pragma omp parallel for schedule(static) reduction(+ : folded, evaluated)
  for (std::ptrdiff_t t = 0; t < n; ++t) {
    const std::uint32_t v = ids[t];
    const Eigen::Vector3d x = in_pos.col(v);
    if (!inside(box_.to_local(x))) {  // untouched, bit for bit
      out_pos.col(v) = x;
      out_nrm.col(v) = in_nrm.col(v);
      continue;
    }
    Eigen::Matrix3d J;
    out_pos.col(v) = apply(x, &J);
    out_nrm.col(v) = transformed_normal(J, in_nrm.col(v));
    if (J.determinant() <= 0) ++folded;
    ++evaluated;
  }
  counts.folded += folded;
  counts.evaluated += evaluated;
}

void Lattice::changed_points(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                             std::vector<std::uint32_t>& ids) const {
  if (!any_changed_) return;
  const Eigen::Matrix3d inv = box_.inverse_axes();
  const Eigen::Vector3d o = box_.origin();
  // Every piece changed (one point of a Bernstein lattice, or of a small B-spline one): the
  // points inside the box, without locating them. The predicate holds copies, not
  // references, so the scan keeps them in registers (with append_selected's private copy,
  // a million points took about 5 ms less).
  const bool all = all_pieces_changed();
  const auto box_coordinates = [pos = in_pos.data(), stride = in_pos.outerStride(), inv, o](Eigen::Index v) {
    return Eigen::Vector3d(inv * (Eigen::Map<const Eigen::Vector3d>(pos + v * stride) - o));
  };
  if (all) {
    append_selected(in_pos.cols(), [box_coordinates](Eigen::Index v) { return inside(box_coordinates(v)); },
                    ids);  // in parallel, in order
    return;
  }
  // The pieces as locate() finds them, flat as flat_piece() numbers them; the piece counts
  // are read once (pieces() is virtual: four calls a point cost about 3 ms of the 38 ms
  // step moving one point of an 8^3-cell lattice on a 1M cloud).
  const Index3 n = pieces();
  const std::uint8_t* const piece_changed = changed_piece_.data();
  const auto changed = [box_coordinates, n, piece_changed](Eigen::Index v) {
    const Eigen::Vector3d u = box_coordinates(v);
    if (!inside(u)) return false;
    const std::size_t flat =
        (static_cast<std::size_t>(piece_at(u[2] * n[2], n[2])) * n[1] + piece_at(u[1] * n[1], n[1])) * n[0] +
        piece_at(u[0] * n[0], n[0]);
    return piece_changed[flat] != 0;
  };
  append_selected(in_pos.cols(), changed, ids);  // in parallel, in order
}

void Lattice::clear_changes() {
  std::fill(changed_piece_.begin(), changed_piece_.end(), 0);
  any_changed_ = false;
}

// Slab test in box coordinates: clip the segment's parameter range t in [0, 1] against
// each axis's slab [-kBoxTolerance, 1 + kBoxTolerance].
bool Lattice::can_act_on_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
  return box_.segment_meets(a, b, kBoxTolerance);
}

namespace {

/// The largest value over [0, 1] (over the line, for a B-spline) of basis function i of
/// the given degree: Bernstein's B_i^n peaks at u = i / n; a uniform B-spline of degree
/// 0..3 at its centre (1, 1, 3/4, 2/3); 1 bounds any basis of a partition of unity.
double basis_peak(Lattice::Basis basis, int degree, int i) {
  if (basis == Lattice::Basis::Bernstein) {
    if (degree == 0) return 1;
    const double t = static_cast<double>(i) / degree;
    double binomial = 1;
    for (int k = 1; k <= i; ++k) binomial = binomial * (degree - i + k) / k;
    return binomial * std::pow(t, i) * std::pow(1 - t, degree - i);  // pow(0, 0) = 1
  }
  constexpr double kPeak[] = {1, 1, 0.75, 2.0 / 3.0};
  return degree < 4 ? kPeak[degree] : 1;
}

}  // namespace

// Along box axis a, both bases' derivative is a spline (polynomial) of one degree less
// whose coefficients are cells_[a] times the differences of neighbouring displacements
// (Bernstein: n (D_i+1 - D_i) with B_i^(n-1), n = cells_; uniform B-spline:
// (D_i+1 - D_i) / h, h = 1 / cells_). So |dD/du_a| <= cells_[a] times the smaller of the
// largest difference (convex hull) and the sum of each difference times the peak of its
// basis function (a few moved points: far tighter). Then J = I + G inv has
// det J >= (1 - r)^3 > 0 when r = |G|_F |inv|_2 < 1 (every eigenvalue lies within r of
// 1). With r < 0.99 the determinant is at least 1e-6, and the computed one is within
// ~1e-15 of it: it cannot come out non-positive.
bool Lattice::fold_free() const {
  const Index3 d = degree();
  double g2 = 0;
  for (int a = 0; a < 3; ++a) {
    double most = 0, sum = 0;
    for (int k = first_[2]; k < first_[2] + count_[2]; ++k)
      for (int j = first_[1]; j < first_[1] + count_[1]; ++j)
        for (int i = first_[0]; i < first_[0] + count_[0]; ++i) {
          const Index3 at{i, j, k};
          Index3 next = at;
          ++next[a];
          if (next[a] >= first_[a] + count_[a]) continue;
          const double step = (displacement_[flat(next)] - displacement_[flat(at)]).norm();
          if (step == 0) continue;
          double peak = 1;
          for (int b = 0; b < 3; ++b) peak *= basis_peak(basis(), b == a ? d[b] - 1 : d[b], at[b] - first_[b]);
          most = std::max(most, step);
          sum += step * peak;
        }
    const double column = cells_[a] * std::min(most, sum);
    g2 += column * column;
  }
  const double inv2 = Eigen::JacobiSVD<Eigen::Matrix3d>(box_.inverse_axes()).singularValues()(0);
  return std::sqrt(g2) * inv2 < 0.99;
}

double Lattice::feature_size() const {
  const Eigen::Vector3d extents = box_.extents();
  double smallest = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const double cell = extents[axis] / cells_[axis];
    if (axis == 0 || cell < smallest) smallest = cell;
  }
  return smallest;
}

}  // namespace ffd

namespace ffd {

Eigen::Matrix3Xd Lattice::points(int) const {
  Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(num_points()));
  for (std::size_t f = 0; f < num_points(); ++f) out.col(static_cast<Eigen::Index>(f)) = point(index(f));
  return out;
}

Eigen::Matrix3Xd Lattice::points(int, const std::vector<std::size_t>& ids) const {
  Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(ids.size()));
  for (std::size_t i = 0; i < ids.size(); ++i) out.col(static_cast<Eigen::Index>(i)) = point(index(ids[i]));
  return out;
}

std::optional<std::size_t> Lattice::find_point(int, const PointIndex& index) const {
  if (!index.grid || !in_range(index.ijk) || !movable(index.ijk)) return std::nullopt;
  return flat(index.ijk);
}

std::string Lattice::missing_point(int, const PointIndex& index) const {
  if (const std::optional<std::string> form = index_form_problem(index, true, "points")) return *form;
  return "point " + index.text() + " is not movable (movable: " + movable_range() + ")";
}

MoveReport Lattice::move_points(int, const std::vector<std::size_t>& ids, const std::vector<Eigen::Vector3d>& targets) {
  for (std::size_t i = 0; i < ids.size(); ++i) move_point(index(ids[i]), targets[i]);
  MoveReport report;
  report.points_moved = ids.size();
  return report;
}

std::vector<std::array<std::uint32_t, 2>> Lattice::net_edges(int) const {
  std::vector<std::array<std::uint32_t, 2>> edges;
  for (std::size_t f = 0; f < num_points(); ++f) {
    const Index3 ijk = index(f);
    for (int axis = 0; axis < 3; ++axis) {
      Index3 next = ijk;
      ++next[axis];
      if (in_range(next)) edges.push_back({static_cast<std::uint32_t>(f), static_cast<std::uint32_t>(flat(next))});
    }
  }
  return edges;
}

std::string Lattice::tearing_warning(const std::string& name, std::size_t outside) const {
  return "lattice '" + name + "' moved points on its box's faces while " + format_count(outside) +
         " vertices lie outside the box: a Bernstein lattice tears the mesh there "
         "(use basis \"bspline\", or move only interior points)";
}

}  // namespace ffd
