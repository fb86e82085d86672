// OctreeLattice as a Warp: parameterization in the subdivided rest lattices and
// relocation by the subdivided displacements (Ono et al. section 3.2).
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "common/ordered_select.h"
#include "multires/cell_coordinates.h"
#include "multires/octree_lattice.h"
#include "multires/trilinear_lanes.h"
#include "multires/volume_subdivision.h"

namespace ffd {
namespace {

constexpr double kInsideTolerance = 1e-9;
constexpr int kMaxWalk = 8;
// Vertices per block of the batch apply: the new tags of a block are located together.
constexpr std::ptrdiff_t kBlock = 64;
// The batch apply asks for the tags of the vertex this many places ahead: a later move
// reads each vertex's tags and Jacobian parts at every moved level, scattered over arrays
// larger than a core's caches, and one vertex's misses alone would be waited for in turn.
constexpr std::ptrdiff_t kPrefetchAhead = 2;
// Below this, a bound of the 2-norm of the sum A of a vertex's Jacobian parts decides that
// I + A has a positive determinant: for |A|_2 <= b < 1, every singular value of I + A is at
// least 1 - b, and I + tA is invertible for every t in [0, 1], so det(I + A) >= (1 - b)^3
// keeps det(I)'s sign; at 0.75 that is 1/64, far above the rounding of the determinant
// apply() computes.
constexpr double kFoldFreeBound = 0.75;
// A first locate's part whose cheap bound (squared_gradient_bound, about 2-3 times the
// norm) exceeds this is bounded by its own norm instead: the few vertices near a fine
// level's moved points, whose summed cheap bounds would otherwise send them to the parts.
constexpr double kTightenAbove = 0.1;

// A grid node (coordinates in [0, 2^20)) as a number that orders nodes by (k, j, i), the
// order of a GridComplex's points.
std::int64_t node_key(const GridIndex& n) {
  return (static_cast<std::int64_t>(n[2]) << 40) | (static_cast<std::int64_t>(n[1]) << 20) | n[0];
}
GridIndex key_node(std::int64_t key) {
  const std::int64_t mask = (1 << 20) - 1;
  return {static_cast<int>(key & mask), static_cast<int>((key >> 20) & mask), static_cast<int>(key >> 40)};
}

/// squared_gradient_bound, out of line: displacement() keeps the arithmetic it had before
/// the bound, so that gcc fuses its Jacobian's products into sums as it did (the bound's
/// code inlined beside them had moved normals by an ulp).
[[gnu::noinline]] double bound_of(const CellCorners& D, const Eigen::Matrix3d& dx_du) {
  return squared_gradient_bound(D, dx_du);
}

/// transformed_normal, out of line: inlined in the apply's loop, gcc kept two of its
/// products on the stack and reloaded them as one vector (a store-forwarding stall).
[[gnu::noinline]] Eigen::Vector3d normal_through(const Eigen::Matrix3d& J, const Eigen::Vector3d& n) {
  return transformed_normal(J, n);
}

/// Box coordinates of x, out of line, so that the batch apply and its prelocate() get the
/// same bits: inlined, GCC vectorizes and fuses Parallelepiped::to_local's product
/// differently from one caller to another, and a locate's guess (hence the last bits of
/// its result) starts from them.
[[gnu::noinline]] Eigen::Vector3d box_coordinates(const Parallelepiped& box, const Eigen::Vector3d& x) {
  return box.to_local(x);
}

/// Resizes v to n. Grown memory is fresh: its pages are faulted in at once, not one per
/// element written (on a 2-core VM each 4 KiB page's trap costs up to 10 us).
template <class Vector>
void grow_prefaulted(Vector& v, std::size_t n) {
  if (n > v.capacity()) {
    v.reserve(std::max(n, 2 * v.size()));
    prefault(v.data() + v.size(), (n - v.size()) * sizeof(*v.data()));
  }
  v.resize(n);
}

/// The slot, in a dense array over a grid with `res` cells per axis, of box coordinates t.
std::size_t grid_slot(const Eigen::Vector3d& t, int res) { return dense_cell(grid_cell_at(t, res), res); }

CellCorners corners_of(const StepGrid& g, const Eigen::Matrix3Xd& positions, std::int32_t cell) {
  std::int32_t corner[8];
  g.corners(cell, corner);
  CellCorners Q;
  for (int c = 0; c < 8; ++c) Q.col(c) = positions.col(corner[c]);
  return Q;
}

}  // namespace

bool OctreeLattice::locate(int l, const Eigen::Vector3d& x, Location& where) const {
  return locate(l, x, box_.to_local(x), where);
}

bool OctreeLattice::locate(int l, const Eigen::Vector3d& x, const Eigen::Vector3d& t, Location& where,
                           Eigen::Matrix3d* dx_du) const {
  const Level& level = levels_[l];
  if (!in_unit_cube(t, kInsideTolerance)) return false;
  // The minimal cell: the finest subdivision whose lattice holds x. A cell of C^k lies
  // near the grid cell of x at its resolution; from there, walk toward x by the sign of
  // the local coordinates outside [0, 1] (cells near cuts and shrunk points are bent).
  for (int k = static_cast<int>(level.fine.size()) - 1; k >= 0; --k) {
    const StepGrid g = level.step_grid(k);
    const int res = g.resolution();
    GridIndex c = grid_cell_at(t, res);
    for (int step = 0; step < kMaxWalk; ++step) {
      Eigen::Vector3d guess, u;
      const std::int32_t cell = ready_cell(l, k, c, t, guess);
      if (cell < 0) break;
      if (!inverse_trilinear(corners_of(g, level.fine[k], cell), x, u, guess, dx_du)) break;
      if (in_unit_cube(u, kInsideTolerance)) {
        where = {k, cell, u.cwiseMax(0.0).cwiseMin(1.0)};
        return true;
      }
      for (int a = 0; a < 3; ++a) c[a] += u[a] < -kInsideTolerance ? -1 : u[a] > 1 + kInsideTolerance ? 1 : 0;
    }
  }
  return false;
}

std::int32_t OctreeLattice::ready_cell(int l, int k, const GridIndex& c, const Eigen::Vector3d& t,
                                       Eigen::Vector3d& guess, bool subdivide) const {
  const StepGrid g = levels_[l].step_grid(k);
  const std::int32_t cell = g.cell(c[0], c[1], c[2]);
  if (cell < 0) return cell;
  const GridIndex coarse{c[0] >> k, c[1] >> k, c[2] >> k};  // the level's cell holding it
  if (k > 0 && !rest_ready(l, coarse)) {
    if (!subdivide) return kUnready;
    ensure_rest(l, {coarse});
  }
  guess = (t * g.resolution() - Eigen::Vector3d(c[0], c[1], c[2])).cwiseMax(0.0).cwiseMin(1.0);
  return cell;
}

void OctreeLattice::prelocate(int l, const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const std::uint32_t* ids,
                              const Eigen::Vector3d* t, std::ptrdiff_t n, std::size_t first_new, Located* out,
                              int stride, Parking* parking) const {
  const Level& level = levels_[l];
  const int k = static_cast<int>(level.fine.size()) - 1;  // locate()'s first try: the finest step
  const StepGrid g = level.step_grid(k);
  const Marks& m = marks(l);
  const std::vector<std::uint32_t>& index = tag_index_[static_cast<std::size_t>(l)];
  // locate()'s walk at step k, four vertices at a time: a vertex found outside its cell
  // tries the next cell toward it in a later round. Wherever locate() would leave step k
  // (no cell there, no convergence, too long a walk), the vertex is left not found, and
  // apply locates it from the start.
  struct Walk {
    std::ptrdiff_t i;  // the vertex, ids[i]
    GridIndex cell;    // the grid cell of C^k to try
    int steps;
  };
  std::vector<Walk> next, now;
  TrilinearLanes lanes;
  Walk lane_walk[TrilinearLanes::kLanes];
  std::int32_t lane_cell[TrilinearLanes::kLanes];
  std::int32_t lane_corners[TrilinearLanes::kLanes][8];
  int used = 0;
  const auto solve = [&] {
    for (int lane = used; lane < TrilinearLanes::kLanes; ++lane)  // a last batch's unused lanes: lane 0's cell
      std::copy(lane_corners[0], lane_corners[0] + 8, lane_corners[lane]);
    lanes.set_cells(level.fine[static_cast<std::size_t>(k)], lane_corners);
    lanes.pad_points(used);
    inverse_trilinear(lanes);
    for (int lane = 0; lane < used; ++lane) {
      if (!lanes.decided[lane]) continue;
      const Eigen::Vector3d u = lanes.u_of(lane);
      Walk walk = lane_walk[lane];
      if (!in_unit_cube(u, kInsideTolerance)) {
        for (int a = 0; a < 3; ++a) walk.cell[a] += u[a] < -kInsideTolerance ? -1 : u[a] > 1 + kInsideTolerance ? 1 : 0;
        if (++walk.steps < kMaxWalk) next.push_back(walk);
        continue;
      }
      Located& found = out[walk.i * stride];  // field by field: a copy of the whole is a slow rep movs
      found.found = true;
      found.where.step = k, found.where.cell = lane_cell[lane], found.where.u = u.cwiseMax(0.0).cwiseMin(1.0);
      lanes.get_dx_du(lane, found.dx_du);
      std::copy(lane_corners[lane], lane_corners[lane] + 8, found.corner);
    }
    used = 0;
  };
  const auto attempt = [&](const Walk& walk) {
    Eigen::Vector3d guess;
    const std::int32_t cell = ready_cell(l, k, walk.cell, t[walk.i], guess, parking == nullptr);
    if (cell == kUnready) {  // a level cell no move subdivided: the vertex waits for it
      const GridIndex& c = walk.cell;
      parking->parked[static_cast<std::size_t>(walk.i)] = 1;
      parking->cells.push_back({l, {c[0] >> k, c[1] >> k, c[2] >> k}});
      return;
    }
    if (cell < 0) return;
    g.corners(cell, lane_corners[used]);
    lanes.set_point(used, in_pos.col(ids[walk.i]), guess);
    lane_walk[used] = walk, lane_cell[used] = cell;
    if (++used == TrilinearLanes::kLanes) solve();
  };
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    out[i * stride].found = false;
    const std::uint32_t tag = index[ids[i]];
    if (tag == 0 || tag - 1 < first_new) continue;
    if (in_unit_cube(t[i], kInsideTolerance) && m.active[grid_slot(t[i], m.resolution)])
      attempt({i, grid_cell_at(t[i], g.resolution()), 0});
  }
  while (used > 0 || !next.empty()) {
    if (used > 0) solve();
    now.swap(next);
    next.clear();
    for (const Walk& walk : now) attempt(walk);
  }
}

Eigen::Vector3d OctreeLattice::displacement(int l, const Location& where, Eigen::Matrix3d* jacobian,
                                            const Eigen::Matrix3d* dx_du, double* bound2,
                                            const std::int32_t* given_corner) const {
  const Level& level = levels_[l];
  double w[8];
  Eigen::Matrix<double, 8, 3> dw;
  trilinear_weights(where.u, w, jacobian ? &dw : nullptr);
  std::int32_t looked_up[8];
  if (!given_corner) level.step_grid(where.step).corners(where.cell, looked_up);
  const std::int32_t* corner = given_corner ? given_corner : looked_up;
  const auto disp = level.disp[static_cast<std::size_t>(where.step)].map();
  CellCorners D;
  for (int c = 0; c < 8; ++c) D.col(c) = disp.col(corner[c]);
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  for (int c = 0; c < 8; ++c) d += w[c] * D.col(c);
  if (bound2) *bound2 = bound_of(D, *dx_du);
  if (jacobian) {
    // dF/dx = I + (dD/du) (dx/du)^-1, dx/du from the rest cell.
    CellCorners Q;
    for (int c = 0; c < 8; ++c) Q.col(c) = level.fine[where.step].col(corner[c]);
    const Eigen::Matrix3d dx_du_rest = Q * dw;
    *jacobian += (D * dw) * dx_du_rest.inverse();
  }
  return d;
}

bool OctreeLattice::tagged_part(int l, const Eigen::Vector3d& x, const Eigen::Vector3d& t, bool same, Tag& tag,
                                Eigen::Matrix3d* jacobian, const Located* located) const {
  if (!same) tag = Tag{};
  const Marks& m = marks(l);
  const std::size_t slot = grid_slot(t, m.resolution);
  const std::uint32_t epoch = m.epochs[slot] + 1;
  if (tag.epoch == epoch) {  // nothing moved near the vertex at this level since
    if (jacobian && tag.inside && !tag.jacobian) {  // an apply without normals left only the bound
      *jacobian = jacobian_part(l, tag);
      tag.jacobian = true;
    }
    return tag.inside;
  }
  tag.epoch = epoch;
  tag.d.setZero();
  tag.bound2 = 0;
  tag.jacobian = jacobian != nullptr;
  if (!m.active[slot]) {  // outside the cells any move marked, the level's displacement is zero
    tag.inside = false;
  } else {
    tag.inside = is_local(l) ? tagged_local_part(l, x, tag, jacobian) : tagged_grid_part(l, x, t, tag, jacobian, located);
  }
  return tag.inside;
}

bool OctreeLattice::tagged_local_part(int l, const Eigen::Vector3d& x, Tag& tag, Eigen::Matrix3d* jacobian) const {
  SubdividedLevel::Location where;
  if (tag.state == 0) {
    tag.state = local(l).locate(x, where) ? 1 : 2;
    located_.fetch_add(1, std::memory_order_relaxed);
    tag.u = where.lambda.tail<3>(), tag.cell = where.cell;
    tag.step = static_cast<std::int8_t>(where.step), tag.slot = static_cast<std::int8_t>(where.slot);
    if (tag.state == 1) tag.face = local(l).face_place(where.step, where.cell, where.face);
  }
  if (tag.state != 1) return false;
  exact_part(l, tag, jacobian);
  return true;
}

bool OctreeLattice::tagged_grid_part(int l, const Eigen::Vector3d& x, const Eigen::Vector3d& t, Tag& tag,
                                     Eigen::Matrix3d* jacobian, const Located* located) const {
  Eigen::Matrix3d dx_du;  // the rest cell's Jacobian, when located here
  bool located_here = false;
  const std::int32_t* corner = nullptr;  // the cell's corners, when prelocated
  if (tag.state == 0) {
    Location where;
    if (located && located->found)
      where = located->where, dx_du = located->dx_du, tag.state = 1, corner = located->corner;
    else
      tag.state = locate(l, x, t, where, &dx_du) ? 1 : 2;
    located_.fetch_add(1, std::memory_order_relaxed);
    tag.u = where.u, tag.cell = where.cell, tag.step = static_cast<std::int8_t>(where.step);
    located_here = true;
  }
  if (tag.state != 1) return false;
  const Location where{tag.step, tag.cell, tag.u};
  if (located_here && !jacobian) {
    // A first move without normals: the locate's Jacobian bounds the part, and the part
    // itself is computed only if the bounds cannot decide the vertex's fold.
    double bound2;
    tag.d = displacement(l, where, nullptr, &dx_du, &bound2, corner);
    tag.bound2 = static_cast<float>(bound2);
    if (bound2 > kTightenAbove * kTightenAbove) tag.bound2 = static_cast<float>(jacobian_part(l, tag).squaredNorm());
    return true;
  }
  exact_part(l, tag, jacobian, corner);  // the prelocated cell's corners, when located here
  return true;
}

[[gnu::always_inline]] inline Eigen::Vector3d OctreeLattice::part_at(int l, const Tag& tag, Eigen::Matrix3d* jacobian,
                                                                      const std::int32_t* corner) const {
  if (!is_local(l)) return displacement(l, Location{tag.step, tag.cell, tag.u}, jacobian, nullptr, nullptr, corner);
  const Eigen::Vector4d lambda(1 - tag.u.sum(), tag.u[0], tag.u[1], tag.u[2]);
  const std::int32_t face = local(l).face_at(tag.step, tag.cell, tag.face);
  return local(l).displacement({tag.step, tag.cell, face, tag.slot, lambda}, jacobian);
}

[[gnu::always_inline]] inline void OctreeLattice::exact_part(int l, Tag& tag, Eigen::Matrix3d* jacobian,
                                                              const std::int32_t* corner) const {
  Eigen::Matrix3d part;  // where the part goes: the caller's, or here to bound it
  Eigen::Matrix3d& J = jacobian ? *jacobian : part;
  J.setZero();
  tag.d = part_at(l, tag, &J, corner);
  tag.bound2 = static_cast<float>(J.squaredNorm());
}

Eigen::Matrix3d OctreeLattice::jacobian_part(int l, const Tag& tag) const {
  Eigen::Matrix3d part = Eigen::Matrix3d::Zero();
  part_at(l, tag, &part);
  return part;
}

bool OctreeLattice::jacobian_folded(std::uint32_t v, double bound2) const {
  if (bound2 < kFoldFreeBound * kFoldFreeBound) return false;
  // Cauchy-Schwarz could not decide: the plain sum of the parts' bounds, then the parts.
  const auto each_part = [&](const auto& visit) {
    for (int l = 0; l < num_levels(); ++l) {
      if (!moved(l)) continue;
      const std::uint32_t index = tag_index_[static_cast<std::size_t>(l)][v];
      if (index == 0) continue;
      const Tag& tag = cache_[static_cast<std::size_t>(l)][index - 1];
      if (tag.inside) visit(l, tag);
    }
  };
  double bound = 0;
  each_part([&](int, const Tag& tag) { bound += std::sqrt(static_cast<double>(tag.bound2)); });
  if (bound < kFoldFreeBound) return false;
  Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
  each_part([&](int l, const Tag& tag) { J += jacobian_part(l, tag); });
  return J.determinant() <= 0;
}

bool OctreeLattice::displacement(const Eigen::Vector3d& x, Eigen::Vector3d& d, Eigen::Matrix3d* jacobian) const {
  d.setZero();
  if (jacobian) jacobian->setIdentity();
  const Eigen::Vector3d t = box_coordinates(box_, x);
  if (!in_unit_cube(t, kInsideTolerance)) return false;
  bool inside = false;
  for (int l = 0; l < num_levels(); ++l) {
    Tag fresh;  // the same computation as the batch apply's, without keeping it
    Eigen::Matrix3d part;
    if (!moved(l) || !tagged_part(l, x, t, false, fresh, jacobian ? &part : nullptr)) continue;
    d += fresh.d;
    if (jacobian) *jacobian += part;
    inside = true;
  }
  return inside;
}

Eigen::Vector3d OctreeLattice::apply(const Eigen::Vector3d& x, Eigen::Matrix3d* jacobian) const {
  Eigen::Vector3d d;
  if (!displacement(x, d, jacobian)) return x;
  return x + d;
}

void OctreeLattice::size_cache(Eigen::Index vertices) const {
  if (cache_key_.cols() < vertices) {
    const Eigen::Index old = cache_key_.cols();
    cache_key_.conservativeResize(3, vertices);
    cache_key_.rightCols(vertices - old).setConstant(std::numeric_limits<double>::quiet_NaN());  // matches nothing
  }
  const auto levels = static_cast<std::size_t>(num_levels());
  cache_.resize(levels);
  jacobians_.resize(levels);
  tag_index_.resize(levels);
  for (std::size_t l = 0; l < levels; ++l)
    if (moved(static_cast<int>(l)) && tag_index_[l].size() < static_cast<std::size_t>(vertices))
      tag_index_[l].resize(static_cast<std::size_t>(vertices), 0);
}

std::vector<std::size_t> OctreeLattice::assign_tags(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                                                    const std::vector<std::uint32_t>& ids, bool with_jacobians) const {
  std::vector<std::size_t> first_new(static_cast<std::size_t>(num_levels()));
  for (int l = 0; l < num_levels(); ++l) {
    auto& tags = cache_[static_cast<std::size_t>(l)];
    first_new[static_cast<std::size_t>(l)] = tags.size();
    if (!moved(l)) continue;
    std::vector<std::uint32_t>& index = tag_index_[static_cast<std::size_t>(l)];
    const Marks& m = marks(l);
    std::size_t count = tags.size();
    if (m.all_active()) {  // coarse levels: every vertex (one outside the box keeps an unused tag)
      for (const std::uint32_t v : ids)
        if (index[v] == 0) index[v] = static_cast<std::uint32_t>(++count);
    } else {
      for (const std::uint32_t v : ids) {
        if (index[v] != 0) continue;
        const Eigen::Vector3d t = box_.to_local(in_pos.col(v));
        if (in_unit_cube(t, kInsideTolerance) && m.active[grid_slot(t, m.resolution)])
          index[v] = static_cast<std::uint32_t>(++count);
      }
    }
    grow_prefaulted(tags, count);  // the new tags, not yet located
    if (with_jacobians) grow_prefaulted(jacobians_[static_cast<std::size_t>(l)], count);
  }
  return first_new;
}

void OctreeLattice::apply(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, const Eigen::Ref<const Eigen::Matrix3Xd>& in_nrm,
                          const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
                          Eigen::Ref<Eigen::Matrix3Xd> out_nrm, WarpCounts& counts) const {
  apply_points(in_pos, &in_nrm, ids, out_pos, &out_nrm, counts);
}

bool OctreeLattice::apply_without_normals(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                                          const std::vector<std::uint32_t>& ids, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
                                          WarpCounts& counts) const {
  // The folds apply() would count are still counted: by the Jacobian parts' bounds, and
  // by the parts themselves where the bounds cannot decide.
  apply_points(in_pos, nullptr, ids, out_pos, nullptr, counts);
  return true;
}

std::vector<OctreeLattice::TagStream> OctreeLattice::tag_streams(bool with_jacobians) const {
  std::vector<TagStream> streams;
  for (int l = 0; l < num_levels(); ++l) {
    if (!moved(l)) continue;
    const auto i = static_cast<std::size_t>(l);
    streams.push_back({l, tag_index_[i].data(), cache_[i].data(), with_jacobians ? jacobians_[i].data() : nullptr});
  }
  return streams;
}

void OctreeLattice::prefetch_tags(const std::vector<TagStream>& streams, std::uint32_t v) {
  // The empty volatile asm keeps the calls: GCC's interprocedural analysis counts a
  // prefetch as no side effect, and without it found this function pure and deleted them.
  asm volatile("");
  const auto lines = [](const void* p, std::size_t bytes) {  // the cache lines of an entry
    const char* c = static_cast<const char*>(p);
    __builtin_prefetch(c);
    __builtin_prefetch(c + bytes - 1);
  };
  for (const TagStream& s : streams) {
    const std::uint32_t index = s.index[v];
    if (index == 0) continue;
    lines(s.tags + (index - 1), sizeof(Tag));
    if (s.jacobians) lines(s.jacobians + (index - 1), sizeof(Eigen::Matrix3d));
  }
}

bool OctreeLattice::apply_vertex(std::uint32_t v, const Eigen::Vector3d& t, const std::vector<TagStream>& streams,
                                 const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos, Eigen::Ref<Eigen::Matrix3Xd>& out_pos,
                                 Eigen::Matrix3d* jacobian, const Located* located, bool& folded) const {
  const Eigen::Vector3d x = in_pos.col(v);
  // Sums the levels' parts as displacement() does, locating the vertex in a grid level
  // only when its tag is not for this position.
  const bool same = (cache_key_.col(v).array() == x.array()).all();
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
  double bound2 = 0;  // without normals: the sum of the parts' squared bounds
  int parts = 0;
  if (in_unit_cube(t, kInsideTolerance))
    for (const TagStream& s : streams) {  // the moved levels, in level order
      const std::uint32_t index = s.index[v];
      if (index == 0) continue;  // not in a cell the level marked active: its part is zero
      Tag& tag = s.tags[index - 1];
      Eigen::Matrix3d* part = jacobian ? s.jacobians + (index - 1) : nullptr;
      if (!tagged_part(s.level, x, t, same, tag, part, located ? located + s.level : nullptr)) continue;
      d += tag.d;
      if (jacobian)
        J += *part;
      else
        bound2 += tag.bound2;
      ++parts;
    }
  cache_key_.col(v) = x;
  if (parts == 0) {  // in no cell where a level moved: untouched, bit for bit
    out_pos.col(v) = x;
    return false;
  }
  out_pos.col(v) = x + d;
  if (jacobian) {
    *jacobian = J;
    folded = J.determinant() <= 0;
  } else {
    folded = jacobian_folded(v, parts * bound2);  // (sum of bounds)^2 <= parts * sum of squares
  }
  return true;
}

void OctreeLattice::apply_points(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                                 const Eigen::Ref<const Eigen::Matrix3Xd>* in_nrm, const std::vector<std::uint32_t>& ids,
                                 Eigen::Ref<Eigen::Matrix3Xd> out_pos, Eigen::Ref<Eigen::Matrix3Xd>* out_nrm,
                                 WarpCounts& counts) const {
  size_cache(in_pos.cols());
  BatchApply batch;
  batch.first_new = assign_tags(in_pos, ids, out_nrm != nullptr);
  // The grid levels with new tags (a level's first move, or vertices newly in its marked
  // cells): each block of vertices locates them there four at a time before applying. A
  // whole grid without shrinking too, where a locate is mostly one evaluation: since the
  // lanes' cells are gathered four at once (set_cells), its first moves are 11-12% faster
  // through the lanes than one vertex at a time (elephant, levels 0 and 1).
  for (int l = 0; l < num_grid_levels(); ++l)
    if (moved(l) && cache_[static_cast<std::size_t>(l)].size() > batch.first_new[static_cast<std::size_t>(l)])
      batch.locating.push_back(l);
  batch.streams = tag_streams(out_nrm != nullptr);
  // A walk that reaches a level cell whose rest lattice no move subdivided parks its
  // vertex: those cells are subdivided together, in one ensure_rest per level, and the
  // parked vertices applied after the others, as they would have been (blob39k's level 2:
  // 12 calls of one cell each, 10% of its first move, became one).
  Parking parked;
  apply_blocks(in_pos, in_nrm, ids, batch, out_pos, out_nrm, counts, &parked);
  if (parked.vertices.empty()) return;
  std::vector<std::pair<int, GridIndex>>& cells = parked.cells;
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  for (std::size_t from = 0, to = 0; from < cells.size(); from = to) {
    std::vector<GridIndex> level_cells;
    for (to = from; to < cells.size() && cells[to].first == cells[from].first; ++to) level_cells.push_back(cells[to].second);
    ensure_rest(cells[from].first, level_cells);
  }
  std::sort(parked.vertices.begin(), parked.vertices.end());
  apply_blocks(in_pos, in_nrm, parked.vertices, batch, out_pos, out_nrm, counts, nullptr);
}

void OctreeLattice::apply_blocks(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                                 const Eigen::Ref<const Eigen::Matrix3Xd>* in_nrm, const std::vector<std::uint32_t>& ids,
                                 const BatchApply& batch, Eigen::Ref<Eigen::Matrix3Xd> out_pos,
                                 Eigen::Ref<Eigen::Matrix3Xd>* out_nrm, WarpCounts& counts, Parking* parked) const {
  const int stride = num_levels();
  std::size_t folded = 0, evaluated = 0;
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(ids.size()), blocks = (n + kBlock - 1) / kBlock;
#pragma omp parallel reduction(+ : folded, evaluated)
  {
    // By vertex of the block and level, empty when no level locates. Only the levels in
    // `locating` write their entries; the others' stay not found, so a tag of theirs that
    // needs a locate (its vertex moved) gets the scalar one.
    std::vector<Located> located(batch.locating.empty() ? 0 : static_cast<std::size_t>(kBlock * stride));
    std::vector<Eigen::Vector3d> t(static_cast<std::size_t>(kBlock));  // box coordinates, computed once
    // With normals, each vertex's Jacobian, and whether a level moved it (else its normal
    // is copied): the normals are transformed after the block's vertices, when the stores
    // of a Jacobian are long done (read straight after them, two of normal_through's loads
    // waited for the stores to reach the cache).
    std::vector<Eigen::Matrix3d> jacobian(out_nrm ? static_cast<std::size_t>(kBlock) : 0);
    std::vector<std::uint8_t> applied(static_cast<std::size_t>(kBlock));
    Parking parking;  // this thread's
    parking.parked.resize(static_cast<std::size_t>(kBlock));
#pragma omp for schedule(static)
    for (std::ptrdiff_t b = 0; b < blocks; ++b) {
      const std::ptrdiff_t begin = b * kBlock, end = std::min(n, begin + kBlock);
      for (std::ptrdiff_t i = begin; i < end; ++i)
        t[static_cast<std::size_t>(i - begin)] = box_coordinates(box_, in_pos.col(ids[static_cast<std::size_t>(i)]));
      std::fill(parking.parked.begin(), parking.parked.end(), 0);
      for (const int l : batch.locating)
        prelocate(l, in_pos, ids.data() + begin, t.data(), end - begin, batch.first_new[static_cast<std::size_t>(l)],
                  located.data() + l, stride, parked ? &parking : nullptr);
      for (std::ptrdiff_t i = begin; i < end; ++i) {
        if (i + kPrefetchAhead < n) prefetch_tags(batch.streams, ids[static_cast<std::size_t>(i + kPrefetchAhead)]);
        const auto slot = static_cast<std::size_t>(i - begin);
        if (parking.parked[slot]) {
          parking.vertices.push_back(ids[static_cast<std::size_t>(i)]);
          continue;
        }
        bool fold = false;
        const Located* found = located.empty() ? nullptr : located.data() + slot * static_cast<std::size_t>(stride);
        applied[slot] = apply_vertex(ids[static_cast<std::size_t>(i)], t[slot], batch.streams, in_pos, out_pos,
                                     out_nrm ? &jacobian[slot] : nullptr, found, fold);
        evaluated += applied[slot];
        folded += fold;
      }
      for (std::ptrdiff_t i = begin; out_nrm && i < end; ++i) {
        const auto slot = static_cast<std::size_t>(i - begin);
        if (parking.parked[slot]) continue;
        const std::uint32_t v = ids[static_cast<std::size_t>(i)];
        out_nrm->col(v) = applied[slot] ? normal_through(jacobian[slot], in_nrm->col(v)) : Eigen::Vector3d(in_nrm->col(v));
      }
    }
    if (parked && !parking.vertices.empty()) {
#pragma omp critical(ffd_octree_parked)
      {
        parked->vertices.insert(parked->vertices.end(), parking.vertices.begin(), parking.vertices.end());
        parked->cells.insert(parked->cells.end(), parking.cells.begin(), parking.cells.end());
      }
    }
  }
  counts.folded += folded;
  counts.evaluated += evaluated;
}

void OctreeLattice::changed_points(const Eigen::Ref<const Eigen::Matrix3Xd>& in_pos,
                                   std::vector<std::uint32_t>& ids) const {
  if (!any_changed_) return;
  std::vector<const Marks*> marked;  // the levels a move marked since clear_changes (usually one)
  for (int l = 0; l < num_levels(); ++l)
    if (marks(l).any_changed) marked.push_back(&marks(l));
  const auto changed = [&](Eigen::Index v) {
    const Eigen::Vector3d t = box_.to_local(in_pos.col(v));
    if (!in_unit_cube(t, kInsideTolerance)) return false;
    for (const Marks* m : marked)
      if (m->changed[grid_slot(t, m->resolution)]) return true;
    return false;
  };
  append_selected(in_pos.cols(), changed, ids);  // in parallel, in order
}

bool OctreeLattice::can_act_on_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
  const bool moved = std::any_of(levels_.begin(), levels_.end(), [](const Level& l) { return l.moved; }) ||
                     std::any_of(local_.begin(), local_.end(), [](const Local& l) { return l.level->moved(); });
  return moved && box_.segment_meets(a, b, kInsideTolerance);
}

double OctreeLattice::feature_size() const {
  int res = levels_.back().sub[0].resolution;
  for (const Local& entry : local_) res = std::max(res, entry.level->resolution());
  return box_.extents().minCoeff() / res;
}

void OctreeLattice::point_weights(int l, const Eigen::Vector3d& x,
                                  std::vector<std::pair<std::int32_t, double>>& out) const {
  out.clear();
  if (is_local(l)) return local(l).point_weights(x, out);
  ensure_subdivided(l);
  Location where;
  if (!locate(l, x, where)) return;
  const Level& level = levels_[l];
  double w[8];
  trilinear_weights(where.u, w, nullptr);
  // Keyed by grid node in (k, j, i) order: a built complex's point order, so the sums
  // below run in the same order for small levels and for a large level's slots.
  using Weights = std::map<std::int64_t, double>;  // by node_key
  Weights weights;
  const StepGrid cell_grid = level.step_grid(where.step);
  for (int c = 0; c < 8; ++c) weights[node_key(cell_grid.node(cell_grid.corner(where.cell, c)))] += w[c];
  // Back through the Catmull-Clark steps: each subdivided point is a stencil of the
  // points one step coarser.
  Stencil stencil;
  for (int k = where.step; k >= 1; --k) {
    const StepGrid coarse = level.step_grid(k - 1);
    Weights coarser;
    for (const auto& [key, wp] : weights) {
      subdivision_stencil(coarse, key_node(key), SubdivisionRule::CatmullClark, stencil);
      for (const auto& [q, wq] : stencil) coarser[node_key(coarse.node(q))] += wp * wq;
    }
    weights = std::move(coarser);
  }
  for (const auto& [key, wp] : weights)  // in point order, as the level's points are sorted
    if (wp != 0) out.push_back({level.sub[0].point(key_node(key)), wp});
}

}  // namespace ffd
