#include "multires/subdivided_level.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "common/errors.h"
#include "multires/volume_subdivision.h"

namespace ffd {
namespace {

constexpr double kTetTolerance = 1e-9;

}  // namespace

SubdividedLevel::SubdividedLevel(const Parallelepiped& box, int source_level, const GridComplex& grid,
                                 const Eigen::Matrix3Xd& grid_rest, const std::vector<std::uint8_t>& cells, int cc_steps)
    : box_(box), source_(source_level), resolution_(2 * grid.resolution) {
  subdivided_ = static_cast<std::size_t>(std::count(cells.begin(), cells.end(), 1));
  sub_.push_back(locally_subdivided(grid, cells, nodes_));
  // The new points by the octree rules of the source level (cell, face and edge points).
  from_source_ = subdivision_matrix(grid, nodes_, SubdivisionRule::Octree);
  fine_.push_back((from_source_ * grid_rest.transpose()).transpose());
  delta_ = Eigen::Matrix3Xd::Zero(3, fine_[0].cols());
  disp_.push_back(delta_);
  for (int k = 1; k <= cc_steps; ++k) {
    steps_.emplace_back();
    sub_.push_back(catmull_clark_step(sub_[k - 1], steps_.back()));
    fine_.push_back((steps_.back() * fine_[k - 1].transpose()).transpose());
    disp_.push_back(Eigen::Matrix3Xd::Zero(3, fine_[k].cols()));
  }
  for (int k = 0; k <= cc_steps; ++k) {
    const CellComplex& g = sub_[k];
    cell_points_.emplace_back();
    cell_centroids_.emplace_back(3, static_cast<Eigen::Index>(g.num_cells()));
    face_centroids_.emplace_back(3, static_cast<Eigen::Index>(g.num_faces()));
    for (std::size_t c = 0; c < g.num_cells(); ++c) {
      // face_place() keeps a face's place among its cell's faces in a byte; a cell here has
      // at most 24 (six, each split in four), so this is a check of the complex, made
      // here rather than in the apply's parallel loop.
      if (g.cell_offsets[c + 1] - g.cell_offsets[c] > 256)
        throw Error("octree: cell " + std::to_string(c) + " of a subdivided level has more than 256 faces");
      cell_points_[k].push_back(g.cell_points(c));
      Eigen::Vector3d C = Eigen::Vector3d::Zero();
      for (std::int32_t p : cell_points_[k][c]) C += fine_[k].col(p);
      cell_centroids_[k].col(static_cast<Eigen::Index>(c)) = C / static_cast<double>(cell_points_[k][c].size());
    }
    for (std::size_t f = 0; f < g.num_faces(); ++f) {
      Eigen::Vector3d F = Eigen::Vector3d::Zero();
      for (std::int32_t j = g.face_offsets[f]; j < g.face_offsets[f + 1]; ++j) F += fine_[k].col(g.face_points[static_cast<std::size_t>(j)]);
      face_centroids_[k].col(static_cast<Eigen::Index>(f)) = F / (g.face_offsets[f + 1] - g.face_offsets[f]);
    }
    build_buckets(k);
  }
}

std::int32_t SubdividedLevel::point_index(const GridIndex& n) const {
  auto less = [](const GridIndex& a, const GridIndex& b) {
    return std::make_tuple(a[2], a[1], a[0]) < std::make_tuple(b[2], b[1], b[0]);
  };
  auto it = std::lower_bound(nodes_.begin(), nodes_.end(), n, less);
  return it != nodes_.end() && *it == n ? static_cast<std::int32_t>(it - nodes_.begin()) : -1;
}

SubdividedLevel::Bounds SubdividedLevel::cell_bounds(int k, std::size_t c) const {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(HUGE_VAL), hi = -lo;
  for (std::int32_t p : cell_points_[k][c]) {
    const Eigen::Vector3d t = box_.to_local(fine_[k].col(p));
    lo = lo.cwiseMin(t), hi = hi.cwiseMax(t);
  }
  return {lo, hi};
}

/// A uniform grid of buckets over the box, each listing the cells whose points' bounds
/// (in box coordinates) meet it.
void SubdividedLevel::build_buckets(int k) {
  Buckets b;
  b.n = std::clamp(resolution_ << k, 1, 128);
  const std::size_t cells = sub_[k].num_cells();
  std::vector<std::vector<std::int32_t>> lists(static_cast<std::size_t>(b.n) * b.n * b.n);
  for (std::size_t c = 0; c < cells; ++c) {
    const auto [lo, hi] = cell_bounds(k, c);
    int a[3], z[3];
    for (int i = 0; i < 3; ++i) {
      a[i] = std::clamp(static_cast<int>(std::floor((lo[i] - kTetTolerance) * b.n)), 0, b.n - 1);
      z[i] = std::clamp(static_cast<int>(std::floor((hi[i] + kTetTolerance) * b.n)), 0, b.n - 1);
    }
    for (int kz = a[2]; kz <= z[2]; ++kz)
      for (int ky = a[1]; ky <= z[1]; ++ky)
        for (int kx = a[0]; kx <= z[0]; ++kx)
          lists[(static_cast<std::size_t>(kz) * b.n + ky) * b.n + kx].push_back(static_cast<std::int32_t>(c));
  }
  b.offsets.push_back(0);
  for (const auto& list : lists) {
    b.cells.insert(b.cells.end(), list.begin(), list.end());
    b.offsets.push_back(static_cast<std::int32_t>(b.cells.size()));
  }
  buckets_.push_back(std::move(b));
}

bool SubdividedLevel::in_tet(int k, std::int32_t c, std::int32_t f, std::int32_t slot, const Eigen::Vector3d& x,
                             Tet& where) const {
  const CellComplex& g = sub_[k];
  const Eigen::Matrix3Xd& X = fine_[k];
  const Eigen::Vector3d C = cell_centroids_[k].col(c), F = face_centroids_[k].col(f);
  const std::int32_t o = g.face_offsets[f], n = g.face_offsets[f + 1] - o;
  const Eigen::Vector3d a = X.col(g.face_points[static_cast<std::size_t>(o + slot)]);
  const Eigen::Vector3d b = X.col(g.face_points[static_cast<std::size_t>(o + (slot + 1) % n)]);
  Eigen::Matrix3d M;
  M << F - C, a - C, b - C;
  const double det = M.determinant();
  if (!(std::abs(det) > 1e-300)) return false;
  const Eigen::Vector3d l = M.inverse() * (x - C);
  const double l0 = 1 - l.sum();
  if (l0 < -kTetTolerance || (l.array() < -kTetTolerance).any()) return false;
  where = {k, c, f, slot, Eigen::Vector4d(l0, l[0], l[1], l[2])};
  return true;
}

bool SubdividedLevel::locate(const Eigen::Vector3d& x, Tet& where) const {
  const Eigen::Vector3d t = box_.to_local(x);
  for (int k = static_cast<int>(sub_.size()) - 1; k >= 0; --k) {  // the minimal cell: the finest step
    const Buckets& b = buckets_[static_cast<std::size_t>(k)];
    const std::size_t bucket = dense_cell(grid_cell_at(t, b.n), b.n);
    const CellComplex& g = sub_[k];
    for (std::int32_t q = b.offsets[bucket]; q < b.offsets[bucket + 1]; ++q) {
      const std::int32_t c = b.cells[static_cast<std::size_t>(q)];
      for (std::int32_t s = g.cell_offsets[c]; s < g.cell_offsets[c + 1]; ++s) {
        const std::int32_t f = g.cell_faces[static_cast<std::size_t>(s)];
        for (std::int32_t slot = 0; slot < g.face_offsets[f + 1] - g.face_offsets[f]; ++slot)
          if (in_tet(k, c, f, slot, x, where)) return true;
      }
    }
  }
  return false;
}

std::uint8_t SubdividedLevel::face_place(int k, std::int32_t c, std::int32_t f) const {
  const CellComplex& g = sub_[static_cast<std::size_t>(k)];
  const auto begin = g.cell_faces.begin() + g.cell_offsets[static_cast<std::size_t>(c)];
  const auto end = g.cell_faces.begin() + g.cell_offsets[static_cast<std::size_t>(c) + 1];
  // f is one of c's faces (locate() found it there), and c has at most 256 (checked when
  // the level was built).
  return static_cast<std::uint8_t>(std::find(begin, end, f) - begin);
}

std::int32_t SubdividedLevel::face_at(int k, std::int32_t c, std::uint8_t place) const {
  const CellComplex& g = sub_[static_cast<std::size_t>(k)];
  return g.cell_faces[static_cast<std::size_t>(g.cell_offsets[static_cast<std::size_t>(c)] + place)];
}

void SubdividedLevel::tet_weights(const Tet& w, std::vector<std::pair<std::int32_t, double>>& out) const {
  out.clear();
  const CellComplex& g = sub_[w.step];
  const auto& cell = cell_points_[w.step][static_cast<std::size_t>(w.cell)];
  for (std::int32_t p : cell) out.push_back({p, w.lambda[0] / static_cast<double>(cell.size())});
  const std::int32_t o = g.face_offsets[w.face], n = g.face_offsets[w.face + 1] - o;
  for (std::int32_t j = o; j < o + n; ++j) out.push_back({g.face_points[static_cast<std::size_t>(j)], w.lambda[1] / n});
  out.push_back({g.face_points[static_cast<std::size_t>(o + w.slot)], w.lambda[2]});
  out.push_back({g.face_points[static_cast<std::size_t>(o + (w.slot + 1) % n)], w.lambda[3]});
}

Eigen::Vector3d SubdividedLevel::displacement(const Location& where, Eigen::Matrix3d* jacobian) const {
  std::vector<std::pair<std::int32_t, double>> w;
  tet_weights(where, w);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& [p, wp] : w) sum += wp * disp_[static_cast<std::size_t>(where.step)].col(p);
  if (jacobian) {  // affine in the tetrahedron: I + [dF - dC, da - dC, db - dC] [F - C, a - C, b - C]^-1
    Eigen::Matrix<double, 3, 4> rest = Eigen::Matrix<double, 3, 4>::Zero(), moved = rest;
    for (int corner = 0; corner < 4; ++corner) {
      Tet unit = where;
      unit.lambda = Eigen::Vector4d::Unit(corner);
      tet_weights(unit, w);
      for (const auto& [p, wp] : w) {
        rest.col(corner) += wp * fine_[static_cast<std::size_t>(where.step)].col(p);
        moved.col(corner) += wp * disp_[static_cast<std::size_t>(where.step)].col(p);
      }
    }
    Eigen::Matrix3d R, D;
    for (int i = 0; i < 3; ++i) R.col(i) = rest.col(i + 1) - rest.col(0), D.col(i) = moved.col(i + 1) - moved.col(0);
    *jacobian += D * R.inverse();
  }
  return sum;
}

std::vector<SubdividedLevel::Bounds> SubdividedLevel::move(const std::vector<std::int32_t>& ids,
                                                            const Eigen::Matrix3Xd& change) {
  std::vector<std::uint8_t> reach(static_cast<std::size_t>(delta_.cols()), 0);  // points the change reaches
  for (std::size_t i = 0; i < ids.size(); ++i) {
    delta_.col(ids[i]) += change.col(static_cast<Eigen::Index>(i));
    reach[static_cast<std::size_t>(ids[i])] = 1;
  }
  disp_[0] = delta_;
  for (std::size_t k = 1; k < disp_.size(); ++k) disp_[k] = (steps_[k - 1] * disp_[k - 1].transpose()).transpose();
  moved_ = true;
  std::vector<Bounds> reached;
  for (std::size_t k = 0; k < sub_.size(); ++k) {
    if (k > 0) {  // a new point is reached when its stencil holds a reached point
      const auto& S = steps_[k - 1];
      std::vector<std::uint8_t> next(static_cast<std::size_t>(S.rows()), 0);
      for (Eigen::Index r = 0; r < S.rows(); ++r)
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(S, r); it && !next[static_cast<std::size_t>(r)]; ++it)
          next[static_cast<std::size_t>(r)] = reach[static_cast<std::size_t>(it.col())];
      reach = std::move(next);
    }
    for (std::size_t c = 0; c < sub_[k].num_cells(); ++c)
      for (std::int32_t p : cell_points_[k][c])
        if (reach[static_cast<std::size_t>(p)]) {
          reached.push_back(cell_bounds(static_cast<int>(k), c));
          break;
        }
  }
  return reached;
}

void SubdividedLevel::point_weights(const Eigen::Vector3d& x, std::vector<std::pair<std::int32_t, double>>& out) const {
  out.clear();
  Tet where;
  if (!locate(x, where)) return;
  std::vector<std::pair<std::int32_t, double>> w;
  tet_weights(where, w);
  std::map<std::int32_t, double> weights;
  for (const auto& [p, wp] : w) weights[p] += wp;
  for (int k = where.step; k >= 1; --k) {  // back through the steps' stencils
    std::map<std::int32_t, double> coarser;
    const auto& S = steps_[static_cast<std::size_t>(k - 1)];
    for (const auto& [p, wp] : weights)
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(S, p); it; ++it)
        coarser[static_cast<std::int32_t>(it.col())] += wp * it.value();
    weights = std::move(coarser);
  }
  for (const auto& [p, wp] : weights)
    if (wp != 0) out.push_back({p, wp});
}

std::size_t SubdividedLevel::bytes() const {
  std::size_t total = nodes_.size() * sizeof(GridIndex);
  for (const CellComplex& g : sub_) total += g.bytes();
  for (const auto& m : fine_) total += static_cast<std::size_t>(m.size()) * sizeof(double);
  for (const auto& m : disp_) total += static_cast<std::size_t>(m.size()) * sizeof(double);
  for (const auto& s : steps_) total += static_cast<std::size_t>(s.nonZeros()) * (sizeof(double) + sizeof(int));
  for (const auto& b : buckets_) total += (b.offsets.size() + b.cells.size()) * sizeof(std::int32_t);
  for (const auto& m : cell_centroids_) total += static_cast<std::size_t>(m.size()) * sizeof(double);
  for (const auto& m : face_centroids_) total += static_cast<std::size_t>(m.size()) * sizeof(double);
  return total;
}

}  // namespace ffd
