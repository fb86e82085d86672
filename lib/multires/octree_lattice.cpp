// OctreeLattice: building the levels (octree subdivision, cuts, shrink) and moving points.
#include "multires/octree_lattice.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "multires/volume_subdivision.h"

namespace ffd {
namespace {

constexpr double kInsideTolerance = 1e-9;

}  // namespace

OctreeLattice::Marks::Marks(int res)
    : resolution(res),
      changed(static_cast<std::size_t>(res) * res * res, 0),
      active(changed.size(), 0),
      epochs(changed.size(), 0) {}

void OctreeLattice::Marks::clear_changes() {
  if (any_changed) std::fill(changed.begin(), changed.end(), 0);
  any_changed = false;
}

OctreeLattice::OctreeLattice(const Parallelepiped& box, const Eigen::Matrix3Xd& region, const OctreeOptions& options)
    : box_(box), options_(options) {
  build_levels(region);
}

void OctreeLattice::build_levels(const Eigen::Matrix3Xd& region) {
  std::vector<Eigen::Vector3d> inside;  // box coordinates of the region points in the box
  // Reserved, not grown point by point: the growth copied it some 17 times on a 39k-vertex
  // mesh. (The same loop writing straight into `t` changed the last bits of shrunk levels:
  // GCC contracted to_local() into other FMAs in that shape.)
  inside.reserve(static_cast<std::size_t>(region.cols()));
  for (Eigen::Index v = 0; v < region.cols(); ++v) {
    const Eigen::Vector3d t = box_.to_local(region.col(v));
    if ((t.array() >= -kInsideTolerance).all() && (t.array() <= 1 + kInsideTolerance).all()) inside.push_back(t);
  }
  Eigen::Matrix3Xd t(3, static_cast<Eigen::Index>(inside.size()));
  for (std::size_t i = 0; i < inside.size(); ++i) t.col(static_cast<Eigen::Index>(i)) = inside[i];

  levels_.clear();
  levels_.resize(static_cast<std::size_t>(options_.levels) + 1);
  for (Level& level : levels_) {  // references to sub[k], fine[k] stay valid as they are built
    level.sub.reserve(static_cast<std::size_t>(options_.cc_steps) + 1);
    level.fine.reserve(static_cast<std::size_t>(options_.cc_steps) + 1);
    level.disp.reserve(static_cast<std::size_t>(options_.cc_steps) + 1);
  }
  levels_[0].sub.push_back(make_grid_complex(1, {{0, 0, 0}}));
  for (int l = 1; l <= options_.levels; ++l) {
    // Octree subdivision (reconnection rules (1)-(3)), then cut the cells holding no
    // region vertex (step 3 of section 2.1).
    const GridComplex refined = refine(levels_[l - 1].sub[0]);
    const int res = refined.resolution;
    std::vector<std::uint8_t> holds(static_cast<std::size_t>(res) * res * res, 0);
    for (Eigen::Index v = 0; v < t.cols(); ++v) holds[dense_cell(grid_cell_at(t.col(v), res), res)] = 1;
    levels_[l].sub.push_back(
        sub_complex(refined, [&](std::size_t c) { return holds[dense_cell(refined.cells[c], res)] != 0; }));
    levels_[l].cut = refined.num_cells() - levels_[l].sub[0].num_cells();
  }
  for (int l = 0; l <= options_.levels; ++l) {
    Level& level = levels_[l];
    const GridComplex& g = level.sub[0];
    level.rest.resize(3, static_cast<Eigen::Index>(g.num_points()));
    for (std::size_t p = 0; p < g.num_points(); ++p)
      level.rest.col(static_cast<Eigen::Index>(p)) =
          box_.to_world(Eigen::Vector3d(g.points[p][0], g.points[p][1], g.points[p][2]) / g.resolution);
    if (options_.shrink >= 0) shrink_level(l, t);
    level.delta = Eigen::Matrix3Xd::Zero(3, level.rest.cols());
    level.fine.push_back(level.rest);
    level.disp.emplace_back(level.rest.cols());  // zero: nothing moved yet
    level.marks = Marks(g.resolution);
  }
}

/// Section 2.2: each point on the boundary across an axis (cells on one side of it only)
/// moves along that axis toward the region, stopping `shrink` short of the farthest
/// region vertex in its cells. Moving only toward the cells' own vertices keeps every
/// vertex inside its cell. The paper leaves how far open; a point moves at most 0.45 of
/// a cell, so that a cell keeps at least a tenth of its width on every axis (at fine
/// levels a cell may hold one vertex, and an unbounded shrink would make it a sliver
/// whose trilinear map cannot be inverted reliably).
void OctreeLattice::shrink_level(int l, const Eigen::Matrix3Xd& t) {
  Level& level = levels_[l];
  const GridComplex& g = level.sub[0];
  const int res = g.resolution;
  const Eigen::Vector3d offset = options_.shrink * box_.extents().cwiseInverse();
  Eigen::Matrix3Xd lo = Eigen::Matrix3Xd::Constant(3, static_cast<Eigen::Index>(g.num_cells()), HUGE_VAL);
  Eigen::Matrix3Xd hi = -lo;
  for (Eigen::Index v = 0; v < t.cols(); ++v) {
    const GridIndex c = grid_cell_at(t.col(v), res);
    const std::int32_t cell = g.cell(c[0], c[1], c[2]);
    if (cell < 0) continue;
    lo.col(cell) = lo.col(cell).cwiseMin(t.col(v));
    hi.col(cell) = hi.col(cell).cwiseMax(t.col(v));
  }
  for (std::size_t p = 0; p < g.num_points(); ++p) {
    const GridIndex& n = g.points[p];
    Eigen::Vector3d u = Eigen::Vector3d(n[0], n[1], n[2]) / res;
    for (int a = 0; a < 3; ++a) {
      double below = -HUGE_VAL, above = HUGE_VAL;  // extents of the vertices on each side
      bool cells_below = false, cells_above = false;
      for (int k = 0; k < 8; ++k) {
        const GridIndex c{n[0] - (k & 1), n[1] - ((k >> 1) & 1), n[2] - ((k >> 2) & 1)};
        const std::int32_t cell = g.cell(c[0], c[1], c[2]);
        if (cell < 0) continue;
        const bool side_below = c[a] < n[a];
        (side_below ? cells_below : cells_above) = true;
        if (side_below) below = std::max(below, hi(a, cell));
        else above = std::min(above, lo(a, cell));
      }
      const double most = 0.45 / res;
      if (cells_below && !cells_above && below > -HUGE_VAL) u[a] = std::max(u[a] - most, std::min(u[a], below + offset[a]));
      if (cells_above && !cells_below && above < HUGE_VAL) u[a] = std::min(u[a] + most, std::max(u[a], above - offset[a]));
    }
    level.rest.col(static_cast<Eigen::Index>(p)) = box_.to_world(u);
  }
}

Eigen::Matrix3Xd OctreeLattice::points(int l) const {
  if (is_local(l)) {  // the octree rules from the source as shown, plus the level's own moves
    const SubdividedLevel& level = local(l);
    const Eigen::Matrix3Xd source = points(level.source_level()) - rest_points(level.source_level());
    return level.rest() + (level.from_source() * source.transpose()).transpose() + level.delta();
  }
  bool any = false;
  for (int i = 0; i <= l; ++i) any = any || levels_[i].moved;
  if (!any) return levels_[l].rest;
  return levels_[l].rest + deformation(l);
}

const Eigen::MatrixXd& OctreeLattice::deformation(int l) const {
  // Delta_0 = delta_0; Delta_l = O(Delta_{l-1}) + delta_l (octree rules: linear). Kept
  // until the next move, so that showing a level does not redo the coarser ones.
  if (deformation_.size() != levels_.size()) deformation_.assign(levels_.size(), Eigen::MatrixXd());
  Eigen::MatrixXd& delta = deformation_[static_cast<std::size_t>(l)];
  if (delta.size() == 0) {
    if (l == 0) {
      delta = levels_[0].delta;
    } else {
      // The coarser deformation is zero but near the points moved so far: only the new
      // points whose stencils reach those are computed (the same values).
      const Eigen::MatrixXd& coarser = deformation(l - 1);
      std::vector<std::uint8_t> nonzero(static_cast<std::size_t>(coarser.cols()));
      for (Eigen::Index p = 0; p < coarser.cols(); ++p) nonzero[static_cast<std::size_t>(p)] = !coarser.col(p).isZero(0.0);
      delta = subdivide_sparse_field(levels_[l - 1].sub[0], levels_[l].sub[0], coarser, nonzero, SubdivisionRule::Octree) +
              Eigen::MatrixXd(levels_[l].delta);
    }
  }
  return delta;
}

/// The grid cells mark_changed marks for the points `ids` (in the grid, existing or not).
static std::vector<GridIndex> marked_cells(const GridComplex& g, const std::vector<std::int32_t>& ids) {
  std::vector<GridIndex> out;
  const int res = g.resolution, below = 3, above = 2;
  for (std::int32_t id : ids) {
    const GridIndex& p = g.points[static_cast<std::size_t>(id)];
    for (int k = std::max(0, p[2] - below); k <= std::min(res - 1, p[2] + above); ++k)
      for (int j = std::max(0, p[1] - below); j <= std::min(res - 1, p[1] + above); ++j)
        for (int i = std::max(0, p[0] - below); i <= std::min(res - 1, p[0] + above); ++i) out.push_back({i, j, k});
  }
  return out;
}

OctreeMove OctreeLattice::move_level_points(int l, const std::vector<std::int32_t>& ids,
                                      const std::vector<Eigen::Vector3d>& targets) {
  const Eigen::Matrix3Xd shown = points(l);
  Eigen::Matrix3Xd change(3, static_cast<Eigen::Index>(ids.size()));
  for (std::size_t i = 0; i < ids.size(); ++i) change.col(static_cast<Eigen::Index>(i)) = targets[i] - shown.col(ids[i]);
  deformation_.clear();  // a level's moves show in the levels made from it
  if (is_local(l)) return move_local(l, ids, change);
  OctreeMove report;
  Level& level = levels_[l];
  for (std::size_t i = 0; i < ids.size(); ++i) level.delta.col(ids[i]) += change.col(static_cast<Eigen::Index>(i));
  report.points_moved = ids.size();
  ensure_subdivided(l);
  update_displacements(l, ids, change, report);
  mark_changed(l, ids, report);
  // The marked cells, where the apply locates vertices. A locate that walks out of them
  // (bent cells near cuts and shrunk points) needs the cell it walks into: the batch apply
  // subdivides those together once its other vertices are done (apply_points), a single
  // locate the one cell (ready_cell). Subdividing a ring more here in advance cost more
  // than those few cells (blob39k, level 4's first move: 134 cells in 7.1 ms, against 69
  // cells in 3.3 ms and eleven single cells walked into, 0.1-0.2 ms each).
  ensure_rest(l, marked_cells(level.sub[0], ids));
  level.moved = true;
  any_changed_ = any_changed_ || !ids.empty();
  return report;
}

void OctreeLattice::ensure_subdivided(int l) const {
  Level& level = levels_[l];
  if (level.stepped) return;
  level.stepped = true;
  // A level reads its C^k through StepGrid, which implies C^k from the level's grid; only
  // a level of at most kBuiltLevelCells builds C^k's topology, most of which its first
  // move needs (N_{S,3} spans 6 cells a side) and which the apply over most of the mesh
  // reads faster than slots (bunny00 and blob39k, levels 0 and 1: 1.4 ms a first move).
  // Building level 3's C^2 (up to 512 cells) took 3 ms of its first move. A small level
  // builds its step matrices row by row where moves reach (update_by_rows, each row
  // summing in the order of its nodes, over slots or points). Every level gets its rest
  // positions cell by cell (ensure_rest), where moves mark cells and locates walk, into
  // fields that no step touches until it needs them: the same values as subdividing the
  // whole level, bit for bit.
  const bool whole = level.sub[0].num_cells() <= options_.whole_level_cells;
  const bool build = level.sub[0].num_cells() <= kBuiltLevelCells;
  for (int k = 1; k <= options_.cc_steps; ++k) {
    if (build) level.sub.push_back(refine(level.sub[static_cast<std::size_t>(k - 1)]));
    const std::size_t slots = level.step_grid(k).num_points();  // or points of the built C^k
    if (whole) {
      level.rows.emplace_back();
      level.row_of.emplace_back(slots);
    }
    level.fine.emplace_back(3, static_cast<Eigen::Index>(slots));  // written by ensure_rest, slot by slot
    level.written.emplace_back(slots);
    // A level is subdivided before its first move: there is nothing to subdivide yet.
    level.disp.emplace_back(static_cast<Eigen::Index>(slots));
  }
  const std::size_t res = static_cast<std::size_t>(level.sub[0].resolution);
  level.ready.reset(new std::atomic<std::uint8_t>[res * res * res]());
}

bool OctreeLattice::rest_ready(int l, const GridIndex& cell) const {
  const Level& level = levels_[l];
  return !level.ready || level.ready[dense_cell(cell, level.sub[0].resolution)].load(std::memory_order_acquire) != 0;
}

std::size_t OctreeLattice::rest_cells_subdivided(int l) const {
  const Level& level = levels_[l];
  if (!level.stepped) return 0;
  std::size_t n = 0;
  for (const GridIndex& c : level.sub[0].cells) n += rest_ready(l, c);
  return n;
}

// ensure_rest's region. A new point of C^k reads the cells of C^(k-1) incident to the
// element (vertex, edge, face or cell) it is made for, and their corners, and its rule
// depends on those cells alone. Per axis, a cell q of C^k so reads its parent and the
// parent's neighbour on q's side. So C^k is exact within m cells of C^k of the pending
// cells when C^(k-1) is exact within floor(m / 2) + 1 cells of C^(k-1), and C^0, the
// level itself, is exact everywhere. Each step computes only what the next one reads:
// the same stencils over the same cells, so the same values bit for bit as subdividing
// the whole level. With cc_steps 2, around one pending cell: 3^3 cells of the level,
// 4^3 of C^1 and 4^3 of C^2 (in whole rings of the level's cells: 5^3, 6^3 and 4^3).

/// Per step k of `steps`, how many cells of C^k around the pending cells must be exact.
static std::vector<int> rest_margins(int steps) {
  std::vector<int> margin(static_cast<std::size_t>(steps) + 1, 0);
  for (std::size_t k = static_cast<std::size_t>(steps); k >= 1; --k) margin[k - 1] = margin[k] / 2 + 1;
  return margin;
}

/// The Chebyshev distance, in cells of C^k (k >= 1), from cell q of C^k to the pending
/// cells' subdivisions, or INT_MAX past one level cell from them (more than the margins of
/// C^k, at most 1). ring[c]: 1 + level cell c's Chebyshev distance in cells from the
/// nearest pending cell (1: pending).
static int pending_distance(const GridIndex& q, int k, const std::vector<std::uint8_t>& ring, int res) {
  const GridIndex at{q[0] >> k, q[1] >> k, q[2] >> k};
  const std::uint8_t r = ring[dense_cell(at, res)];
  if (r == 1) return 0;
  if (r != 2) return std::numeric_limits<int>::max();
  int best = std::numeric_limits<int>::max();
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const GridIndex p{at[0] + dx, at[1] + dy, at[2] + dz};
        const bool inside = std::min({p[0], p[1], p[2]}) >= 0 && std::max({p[0], p[1], p[2]}) < res;
        if (!inside || ring[dense_cell(p, res)] != 1) continue;
        int d = 0;
        for (int a = 0; a < 3; ++a) d = std::max({d, (p[a] << k) - q[a], q[a] - (((p[a] + 1) << k) - 1)});
        best = std::min(best, d);
      }
  return best;
}

/// The children of `coarse`'s cells (C^(k-1)) within `margin` cells of C^k of the pending cells.
static GridComplex children_near(const GridComplex& coarse, int k, int margin, const std::vector<std::uint8_t>& ring,
                                 int res) {
  std::vector<GridIndex> kept;
  for (const GridIndex& c : coarse.cells)
    for (int child = 0; child < 8; ++child) {
      const GridIndex q{2 * c[0] + (child & 1), 2 * c[1] + (child >> 1 & 1), 2 * c[2] + (child >> 2)};
      if (pending_distance(q, k, ring, res) <= margin) kept.push_back(q);
    }
  return make_grid_complex(coarse.resolution * 2, std::move(kept));
}

void OctreeLattice::ensure_rest(int l, const std::vector<GridIndex>& cells) const {
  std::lock_guard<std::mutex> lock(rest_mutex_);
  Level& level = levels_[l];
  const GridComplex& g = level.sub[0];
  const int res = g.resolution;
  std::vector<GridIndex> pending;
  for (const GridIndex& c : cells)
    if (g.has_cell(c[0], c[1], c[2]) && !rest_ready(l, c)) pending.push_back(c);
  if (pending.empty()) return;
  const std::vector<int> margin = rest_margins(options_.cc_steps);
  const int rings = margin[0];
  std::vector<std::uint8_t> ring(static_cast<std::size_t>(res) * res * res, 0);  // 0: outside the region
  std::vector<GridIndex> region;
  for (const GridIndex& c : pending)
    for (int k = std::max(0, c[2] - rings); k <= std::min(res - 1, c[2] + rings); ++k)
      for (int j = std::max(0, c[1] - rings); j <= std::min(res - 1, c[1] + rings); ++j)
        for (int i = std::max(0, c[0] - rings); i <= std::min(res - 1, c[0] + rings); ++i) {
          if (!g.has_cell(i, j, k)) continue;
          std::uint8_t& r = ring[dense_cell({i, j, k}, res)];
          const int d = 1 + std::max({std::abs(i - c[0]), std::abs(j - c[1]), std::abs(k - c[2])});
          if (r == 0) region.push_back({i, j, k});
          if (r == 0 || d < r) r = static_cast<std::uint8_t>(d);
        }
  GridComplex local = make_grid_complex(res, std::move(region));
  Eigen::MatrixXd field(3, static_cast<Eigen::Index>(local.num_points()));
  for (std::size_t p = 0; p < local.num_points(); ++p)
    field.col(static_cast<Eigen::Index>(p)) = level.rest.col(g.point(local.points[p]));
  for (int k = 1; k <= options_.cc_steps; ++k) {
    GridComplex finer = children_near(local, k, margin[static_cast<std::size_t>(k)], ring, res);
    field = subdivide_field(local, finer, field, SubdivisionRule::CatmullClark);
    const int span = 1 << k;  // nodes of C^k per cell of the level, per axis
    ZeroedArray<std::uint8_t>& written = level.written[static_cast<std::size_t>(k - 1)];
    const StepGrid fine = level.step_grid(k);
    for (const GridIndex& c : pending)
      for (int z = 0; z <= span; ++z)
        for (int y = 0; y <= span; ++y)
          for (int x = 0; x <= span; ++x) {
            const GridIndex node{c[0] * span + x, c[1] * span + y, c[2] * span + z};
            const std::int32_t p = fine.point(node);
            if (written[static_cast<std::size_t>(p)]) continue;
            level.fine[k].col(p) = field.col(finer.point(node));
            written[static_cast<std::size_t>(p)] = 1;
          }
    local = std::move(finer);
  }
  for (const GridIndex& c : pending) level.ready[dense_cell(c, res)].store(1, std::memory_order_release);
}

/// The cells of the level within `before`..`after` grid steps of the points' nodes.
static std::vector<std::uint8_t> cells_near(const GridComplex& g, const std::vector<std::int32_t>& ids, int before,
                                            int after) {
  std::vector<std::uint8_t> near(g.num_cells(), 0);
  for (std::int32_t id : ids) {
    const GridIndex& p = g.points[static_cast<std::size_t>(id)];
    for (int k = p[2] - before; k <= p[2] + after; ++k)
      for (int j = p[1] - before; j <= p[1] + after; ++j)
        for (int i = p[0] - before; i <= p[0] + after; ++i) {
          const std::int32_t c = g.cell(i, j, k);
          if (c >= 0) near[static_cast<std::size_t>(c)] = 1;
        }
  }
  return near;
}

void OctreeLattice::update_displacements(int l, const std::vector<std::int32_t>& ids, const Eigen::Matrix3Xd& change,
                                         OctreeMove& report) {
  Level& level = levels_[l];
  const GridComplex& g = level.sub[0];
  if (!level.rows.empty()) {  // a small level: its steps are matrices
    update_by_rows(l, ids);
    const std::vector<std::uint8_t> patch = cells_near(g, ids, 3, 2);  // where the rows lie
    report.cells_subdivided = static_cast<std::size_t>(std::count(patch.begin(), patch.end(), 1));
    return;
  }
  level.disp[0].map() = level.delta;
  // The paper subdivides N_{S,4}. The moves' image after any number of steps lies in the
  // cells of N_{S,2} (the limit's support: a B-spline's 4^3 cells); one more ring holds
  // every element the rules read there, so N_{S,3} gives the whole level's subdivision
  // (LocalSubdivisionAgreesWithSubdividingTheWholeLevel; N_{S,1} does not). Outside the
  // patch the image is zero.
  const std::vector<std::uint8_t> patch = cells_near(g, ids, 3, 2);
  const std::size_t patch_cells = static_cast<std::size_t>(std::count(patch.begin(), patch.end(), 1));
  GridComplex local = sub_complex(g, [&](std::size_t c) { return patch[c] != 0; });
  Eigen::MatrixXd field = Eigen::MatrixXd::Zero(3, static_cast<Eigen::Index>(local.num_points()));
  for (std::size_t i = 0; i < ids.size(); ++i)
    field.col(local.point(g.points[static_cast<std::size_t>(ids[i])])) += change.col(static_cast<Eigen::Index>(i));
  for (int k = 1; k <= options_.cc_steps; ++k) {
    GridComplex finer = refine(local);
    std::vector<std::uint8_t> nonzero(local.num_points());
    for (std::size_t q = 0; q < local.num_points(); ++q) nonzero[q] = !field.col(static_cast<Eigen::Index>(q)).isZero(0.0);
    field = subdivide_sparse_field(local, finer, field, nonzero, SubdivisionRule::CatmullClark);
    const StepGrid grid = level.step_grid(k);
    Eigen::Map<Eigen::Matrix3Xd> disp = level.disp[k].map();
    for (std::size_t q = 0; q < finer.num_points(); ++q) {
      if (field.col(static_cast<Eigen::Index>(q)).isZero(0.0)) continue;
      disp.col(grid.point(finer.points[q])) += field.col(static_cast<Eigen::Index>(q));
    }
    local = std::move(finer);
  }
  report.cells_subdivided = patch_cells;
}

/// Whether grid node n is a corner of some cell of `grid` (a slot's node may be no cell's).
static bool is_corner(const StepGrid& grid, const GridIndex& n) {
  for (int c = 0; c < 8; ++c)
    if (grid.has_cell(n[0] - (c & 1), n[1] - (c >> 1 & 1), n[2] - (c >> 2))) return true;
  return false;
}

/// The points of C^k (fine) whose subdivision stencils read one of the points `changed`
/// of C^(k-1) (coarse), a small level's (built complexes or slots). A stencil reads the
/// corners of coarse cells at the new point's node / 2 and one step below it on each
/// axis, so coarse nodes within 1 of node / 2 on every axis (the 27 nodes
/// volume_subdivision.cpp's StencilBuilder looks up; no grid rule reads beyond them).
static std::vector<std::int32_t> points_reading(const StepGrid& coarse, const StepGrid& fine,
                                               const std::vector<std::int32_t>& changed) {
  constexpr int kReach = 1;
  std::vector<std::int32_t> out;
  if (changed.empty()) return out;
  GridIndex lo = coarse.node(changed[0]), hi = lo;
  for (const std::int32_t p : changed) {
    const GridIndex n = coarse.node(p);
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], n[a] - kReach), hi[a] = std::max(hi[a], n[a] + kReach);
  }
  const long long nx = hi[0] - lo[0] + 1, ny = hi[1] - lo[1] + 1, nz = hi[2] - lo[2] + 1;
  std::vector<std::uint8_t> reach(static_cast<std::size_t>(nx * ny * nz), 0);
  for (const std::int32_t p : changed) {
    const GridIndex n = coarse.node(p);
    for (long long z = n[2] - kReach - lo[2]; z <= n[2] + kReach - lo[2]; ++z)
      for (long long y = n[1] - kReach - lo[1]; y <= n[1] + kReach - lo[1]; ++y)
        for (long long x = n[0] - kReach - lo[0]; x <= n[0] + kReach - lo[0]; ++x)
          reach[static_cast<std::size_t>((z * ny + y) * nx + x)] = 1;
  }
  const int res = fine.resolution();
  for (int z = std::max(0, 2 * lo[2]); z <= std::min(res, 2 * hi[2] + 1); ++z)
    for (int y = std::max(0, 2 * lo[1]); y <= std::min(res, 2 * hi[1] + 1); ++y)
      for (int x = std::max(0, 2 * lo[0]); x <= std::min(res, 2 * hi[0] + 1); ++x) {
        const long long i = (x >> 1) - lo[0], j = (y >> 1) - lo[1], k = (z >> 1) - lo[2];
        if (!reach[static_cast<std::size_t>((k * ny + j) * nx + i)]) continue;
        const std::int32_t p = fine.point({x, y, z});  // a slot, or -1
        if (p >= 0 && is_corner(fine, {x, y, z})) out.push_back(p);
      }
  return out;
}

void OctreeLattice::update_by_rows(int l, const std::vector<std::int32_t>& ids) {
  // disp[k] = S_k disp[k-1] for every k, as a product of the whole matrices: a row whose
  // inputs did not change keeps its value, so only the rows reading a changed value are
  // multiplied again, by the same Eigen product (each row sums its terms in its column
  // order, whatever rows come with it), and only values that changed propagate.
  Level& level = levels_[l];
  std::vector<std::int32_t> changed;
  Eigen::Map<Eigen::Matrix3Xd> first = level.disp[0].map();
  for (const std::int32_t p : ids) {
    if (std::memcmp(first.col(p).data(), level.delta.col(p).data(), 3 * sizeof(double)) == 0) continue;
    first.col(p) = level.delta.col(p);
    changed.push_back(p);
  }
  for (int k = 1; k <= options_.cc_steps && !changed.empty(); ++k) {
    const StepGrid coarse = level.step_grid(k - 1), fine = level.step_grid(k);
    const std::vector<std::int32_t> points = points_reading(coarse, fine, changed);
    SubdivisionRows& rows = level.rows[static_cast<std::size_t>(k - 1)];
    ZeroedArray<std::int32_t>& row_of = level.row_of[static_cast<std::size_t>(k - 1)];
    std::vector<std::int32_t> listed(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      std::int32_t& row = row_of[static_cast<std::size_t>(points[i])];
      if (row == 0) row = 1 + rows.append(coarse, fine.node(points[i]), SubdivisionRule::CatmullClark);
      listed[i] = row - 1;
    }
    const Eigen::SparseMatrix<double, Eigen::RowMajor> S = rows.matrix(listed, level.disp[k - 1].cols);
    const Eigen::Matrix3Xd values = (S * level.disp[k - 1].map().transpose()).transpose();
    Eigen::Map<Eigen::Matrix3Xd> disp = level.disp[k].map();
    changed.clear();
    for (std::size_t i = 0; i < points.size(); ++i) {
      const auto now = values.col(static_cast<Eigen::Index>(i));
      if (std::memcmp(disp.col(points[i]).data(), now.data(), 3 * sizeof(double)) == 0) continue;
      disp.col(points[i]) = now;
      changed.push_back(points[i]);
    }
  }
}

void OctreeLattice::mark_changed(int l, const std::vector<std::int32_t>& ids, OctreeMove& report) {
  Level& level = levels_[l];
  const GridComplex& g = level.sub[0];
  const int res = g.resolution;
  // N_{S,3}: the cells within 2 cells of the cells around S (grid cells, cut or not, so
  // that a vertex a subdivided cell reaches over a cut is not missed).
  for (const GridIndex& c : marked_cells(g, ids)) level.marks.mark(dense_cell(c, res));
  report.cells_marked = 0;
  for (std::size_t c = 0; c < g.num_cells(); ++c) report.cells_marked += level.marks.changed[dense_cell(g.cells[c], res)];
}

OctreeMove OctreeLattice::move_local(int l, const std::vector<std::int32_t>& ids, const Eigen::Matrix3Xd& change) {
  Local& entry = local_[static_cast<std::size_t>(l - num_grid_levels())];
  SubdividedLevel& level = *entry.level;
  // The whole level is subdivided again; the vertices to relocate are those in the rest
  // cells the change reaches (at most N_{S,3}), marked on the level's node grid.
  const std::vector<SubdividedLevel::Bounds> reached = level.move(ids, change);
  OctreeMove report;
  report.points_moved = ids.size();
  report.cells_subdivided = level.complex().num_cells();
  const int res = level.resolution();
  for (const auto& [lo, hi] : reached) {
    int a[3], z[3];
    for (int i = 0; i < 3; ++i) {
      a[i] = std::clamp(static_cast<int>(std::floor((lo[i] - kInsideTolerance) * res)), 0, res - 1);
      z[i] = std::clamp(static_cast<int>(std::floor((hi[i] + kInsideTolerance) * res)), 0, res - 1);
    }
    for (int k = a[2]; k <= z[2]; ++k)
      for (int j = a[1]; j <= z[1]; ++j)
        for (int i = a[0]; i <= z[0]; ++i) {
          const std::size_t c = dense_cell({i, j, k}, res);
          report.cells_marked += !entry.marks.changed[c];
          entry.marks.mark(c);  // every mark counts, so that no vertex keeps a part from before it
        }
  }
  any_changed_ = any_changed_ || !ids.empty();
  return report;
}

int OctreeLattice::subdivide(int l, const std::vector<std::int32_t>& cells) {
  if (is_local(l)) throw std::invalid_argument("a locally subdivided level cannot be subdivided again");
  std::vector<std::uint8_t> flags(complex(l).num_cells(), 0);
  for (std::int32_t c : cells) flags.at(static_cast<std::size_t>(c)) = 1;
  Local entry;
  entry.level = std::make_unique<SubdividedLevel>(box_, l, complex(l), rest_points(l), flags, options_.cc_steps);
  entry.marks = Marks(entry.level->resolution());
  local_.push_back(std::move(entry));
  return num_levels() - 1;
}

std::size_t OctreeLattice::num_points(int l) const {
  return is_local(l) ? local(l).nodes().size() : complex(l).num_points();
}

std::size_t OctreeLattice::num_cells(int l) const {
  return is_local(l) ? local(l).complex().num_cells() : complex(l).num_cells();
}

int OctreeLattice::resolution(int l) const { return is_local(l) ? local(l).resolution() : complex(l).resolution; }

std::vector<std::array<std::int32_t, 2>> OctreeLattice::edges(int l) const {
  if (is_local(l)) return local(l).edges();
  std::vector<std::array<std::int32_t, 2>> out;
  const GridComplex& g = complex(l);
  // The edge from node n along `axis` belongs to a cell when one of the 4 cells around it is kept.
  for (std::size_t p = 0; p < g.num_points(); ++p)
    for (int axis = 0; axis < 3; ++axis) {
      GridIndex m = g.points[p];
      ++m[axis];
      const std::int32_t q = g.point(m);
      if (q < 0) continue;
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      bool used = false;
      for (int k = 0; k < 4 && !used; ++k) {
        GridIndex c = g.points[p];
        c[u] -= k & 1;
        c[v] -= k >> 1;
        used = g.has_cell(c[0], c[1], c[2]);
      }
      if (used) out.push_back({static_cast<std::int32_t>(p), q});
    }
  return out;
}

void OctreeLattice::clear_changes() {
  for (Local& entry : local_) entry.marks.clear_changes();
  for (Level& level : levels_) level.marks.clear_changes();
  any_changed_ = false;
}

std::size_t OctreeLattice::bytes() const {
  std::size_t total = 0;
  for (const Local& entry : local_)
    total += entry.level->bytes() + entry.marks.bytes();
  total += static_cast<std::size_t>(cache_key_.size()) * sizeof(double);
  for (const auto& tags : cache_) total += tags.capacity() * sizeof(Tag);
  for (const auto& parts : jacobians_) total += parts.capacity() * sizeof(Eigen::Matrix3d);
  for (const auto& index : tag_index_) total += index.capacity() * sizeof(std::uint32_t);
  for (const Level& level : levels_) {
    for (const GridComplex& g : level.sub) total += g.bytes();
    for (const Eigen::Matrix3Xd& m : level.fine) total += static_cast<std::size_t>(m.size()) * sizeof(double);
    for (const Field& m : level.disp) total += m.values.size() * sizeof(double);
    for (const SubdivisionRows& rows : level.rows) total += rows.bytes();
    for (const auto& index : level.row_of) total += index.size() * sizeof(std::int32_t);
    for (const auto& flags : level.written) total += flags.size();
    if (level.ready) total += static_cast<std::size_t>(level.marks.changed.size());  // one flag per grid cell
    total += static_cast<std::size_t>(level.rest.size() + level.delta.size()) * sizeof(double) +
             level.marks.bytes();
  }
  return total;
}

const GridComplex& OctreeLattice::subdivided(int l, int k) const {
  ensure_subdivided(l);
  const Level& level = levels_[l];
  if (static_cast<std::size_t>(k) < level.sub.size()) return level.sub[static_cast<std::size_t>(k)];
  Inspected& seen = inspected_[{l, k}];  // the level's C^k, built for the caller only
  if (seen.complex.cells.empty()) {
    seen.complex = level.sub[0];
    for (int step = 1; step <= k; ++step) seen.complex = refine(seen.complex);
  }
  return seen.complex;
}

const Eigen::Matrix3Xd& OctreeLattice::subdivided_rest(int l, int k) const {
  ensure_subdivided(l);
  const Level& level = levels_[l];
  ensure_rest(l, level.sub[0].cells);
  if (static_cast<std::size_t>(k) < level.sub.size()) return level.fine[static_cast<std::size_t>(k)];
  const GridComplex& g = subdivided(l, k);
  Inspected& seen = inspected_[{l, k}];
  const StepGrid grid = level.step_grid(k);
  seen.rest.resize(3, static_cast<Eigen::Index>(g.num_points()));
  for (std::size_t p = 0; p < g.num_points(); ++p)
    seen.rest.col(static_cast<Eigen::Index>(p)) = level.fine[static_cast<std::size_t>(k)].col(grid.point(g.points[p]));
  return seen.rest;
}

Eigen::Matrix3Xd OctreeLattice::subdivided_moves(int l, int k) const {
  ensure_subdivided(l);
  const GridComplex& g = subdivided(l, k);
  const Level& level = levels_[l];
  const StepGrid grid = level.step_grid(k);
  const auto disp = level.disp[static_cast<std::size_t>(k)].map();
  Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(g.num_points()));
  for (std::size_t p = 0; p < g.num_points(); ++p) out.col(static_cast<Eigen::Index>(p)) = disp.col(grid.point(g.points[p]));
  return out;
}

}  // namespace ffd
