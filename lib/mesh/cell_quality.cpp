#include "mesh/cell_quality.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Geometry>

namespace ffd {
namespace {

using Vec = Eigen::Vector3d;

// A linear 3D kind: its corners, the three edges leaving each corner (in the reference
// shape's orientation), and its faces wound outward (VTK's parametric coordinates).
struct Shape {
  int corners = 0;
  std::vector<std::array<int, 4>> triples;  // corner, then the three far ends
  std::vector<std::vector<int>> faces;
  std::vector<double> ideal;  // each triple's value on the ideal cell
};

double corner_value(const Vec& o, const Vec& a, const Vec& b, const Vec& c) {
  const Vec e1 = a - o, e2 = b - o, e3 = c - o;
  const double lengths = e1.norm() * e2.norm() * e3.norm();
  return lengths > 0 ? e1.dot(e2.cross(e3)) / lengths : 0.0;
}

Shape make_shape(int corners, std::vector<std::array<int, 4>> triples, std::vector<std::vector<int>> faces,
                 const std::vector<Vec>& ideal) {
  Shape shape{corners, std::move(triples), std::move(faces), {}};
  for (const auto& t : shape.triples) shape.ideal.push_back(corner_value(ideal[t[0]], ideal[t[1]], ideal[t[2]], ideal[t[3]]));
  return shape;
}

const Shape& tetra_shape() {
  static const Shape shape = make_shape(
      4, {{0, 1, 2, 3}, {1, 2, 0, 3}, {2, 0, 1, 3}, {3, 0, 2, 1}}, {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}},
      {Vec(0, 0, 0), Vec(1, 0, 0), Vec(0.5, std::sqrt(3.0) / 2, 0), Vec(0.5, std::sqrt(3.0) / 6, std::sqrt(2.0 / 3))});
  return shape;
}

const Shape& hexahedron_shape() {
  static const Shape shape = make_shape(
      8,
      {{0, 1, 3, 4}, {1, 2, 0, 5}, {2, 3, 1, 6}, {3, 0, 2, 7}, {4, 7, 5, 0}, {5, 4, 6, 1}, {6, 5, 7, 2}, {7, 6, 4, 3}},
      {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}},
      {Vec(0, 0, 0), Vec(1, 0, 0), Vec(1, 1, 0), Vec(0, 1, 0), Vec(0, 0, 1), Vec(1, 0, 1), Vec(1, 1, 1), Vec(0, 1, 1)});
  return shape;
}

// VTK's wedge: the triangle (0, 1, 2) winds with its normal out of the wedge, away from
// (3, 4, 5) (vtkWedge's documentation).
const Shape& wedge_shape() {
  const double h = std::sqrt(3.0) / 2;
  static const Shape shape = make_shape(
      6, {{0, 2, 1, 3}, {1, 0, 2, 4}, {2, 1, 0, 5}, {3, 4, 5, 0}, {4, 5, 3, 1}, {5, 3, 4, 2}},
      {{0, 1, 2}, {3, 5, 4}, {0, 2, 5, 3}, {2, 1, 4, 5}, {1, 0, 3, 4}},
      {Vec(0, 0, 0), Vec(0.5, h, 0), Vec(1, 0, 0), Vec(0, 0, 1), Vec(0.5, h, 1), Vec(1, 0, 1)});
  return shape;
}

const Shape& pyramid_shape() {
  static const Shape shape = make_shape(
      5,
      {{0, 1, 3, 4}, {1, 2, 0, 4}, {2, 3, 1, 4}, {3, 0, 2, 4},  // the base corners
       {4, 2, 1, 0}, {4, 3, 2, 1}, {4, 0, 3, 2}, {4, 1, 0, 3}},  // the apex, by consecutive edges
      {{0, 3, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}},
      {Vec(0, 0, 0), Vec(1, 0, 0), Vec(1, 1, 0), Vec(0, 1, 0), Vec(0.5, 0.5, std::sqrt(0.5))});
  return shape;
}

// The linear shape whose corners lead cell kind `type`'s nodes, or null. Quadratic,
// Lagrange and Bezier kinds list their corners first in VTK's order.
const Shape* shape_of(std::uint8_t type) {
  switch (type) {
    case cell_type::kTetra: case cell_type::kQuadraticTetra: case 71: case 78: return &tetra_shape();
    case cell_type::kHexahedron: case cell_type::kQuadraticHexahedron: case cell_type::kTriquadraticHexahedron:
    case 33: case 72: case 79: return &hexahedron_shape();
    case cell_type::kWedge: case cell_type::kQuadraticWedge: case 31: case 32: case 73: case 80: return &wedge_shape();
    case cell_type::kPyramid: case cell_type::kQuadraticPyramid: case 37: case 74: case 81: return &pyramid_shape();
    default: return nullptr;
  }
}

// Node k of a cell as the shape numbers it (a voxel's corners are numbered as a pixel's).
std::uint32_t corner(const VolumeCells& cells, std::size_t c, int k) {
  static constexpr int kVoxel[8] = {0, 1, 3, 2, 4, 5, 7, 6};
  return cells.nodes(c)[cells.type[c] == 11 ? kVoxel[k] : k];
}

// Adds the face fan's signed volume of the face `ids` (outward) about centroid `o` to
// `volume`, and gives each fan tetrahedron to `tet(o, p, q, f)`.
template <class Tet>
void face_fan(const Eigen::Matrix3Xd& x, const std::uint32_t* ids, std::size_t n, const Vec& o, double& volume, Tet tet) {
  Vec f = Vec::Zero();
  for (std::size_t k = 0; k < n; ++k) f += x.col(ids[k]);
  f /= static_cast<double>(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec p = x.col(ids[k]), q = x.col(ids[(k + 1) % n]);
    volume += (p - o).dot((q - o).cross(f - o)) / 6;
    tet(o, p, q, f);
  }
}

double tet_scaled_jacobian(const Vec& a, const Vec& b, const Vec& c, const Vec& d) {
  const Shape& s = tetra_shape();
  const Vec v[4] = {a, b, c, d};
  double lowest = 1e300;
  for (std::size_t t = 0; t < s.triples.size(); ++t) {
    const auto& i = s.triples[t];
    lowest = std::min(lowest, corner_value(v[i[0]], v[i[1]], v[i[2]], v[i[3]]) / s.ideal[t]);
  }
  return lowest;
}

}  // namespace

bool measured_cell(const VolumeCells& cells, std::size_t c) {
  const std::uint8_t type = cells.type[c];
  if (type == 11) return cells.degree(c) == 8;
  if (type == cell_type::kPolyhedron) return !cells.face_offset.empty();
  const Shape* shape = shape_of(type);
  return shape && cells.degree(c) >= static_cast<std::size_t>(shape->corners);
}

namespace {

CellMeasure measure_shape(const VolumeCells& cells, std::size_t c, const Shape& shape, const Eigen::Matrix3Xd& x) {
  CellMeasure m;
  m.cell = c;
  std::uint32_t ids[8];
  for (int k = 0; k < shape.corners; ++k) {
    ids[k] = corner(cells, c, k);
    m.centroid += x.col(ids[k]);
  }
  m.centroid /= shape.corners;
  m.scaled_jacobian = 1e300;
  for (std::size_t t = 0; t < shape.triples.size(); ++t) {
    const auto& i = shape.triples[t];
    const double value = corner_value(x.col(ids[i[0]]), x.col(ids[i[1]]), x.col(ids[i[2]]), x.col(ids[i[3]]));
    m.scaled_jacobian = std::min(m.scaled_jacobian, value / shape.ideal[t]);
  }
  if (shape.corners == 4) {
    const Vec o = x.col(ids[0]);
    m.volume = (x.col(ids[1]) - o).dot((x.col(ids[2]) - o).cross(x.col(ids[3]) - o)) / 6;
    return m;
  }
  for (const std::vector<int>& face : shape.faces) {
    std::uint32_t f[4];
    for (std::size_t k = 0; k < face.size(); ++k) f[k] = ids[face[k]];
    face_fan(x, f, face.size(), m.centroid, m.volume, [](const Vec&, const Vec&, const Vec&, const Vec&) {});
  }
  return m;
}

// A polyhedron: volume and the lowest scaled Jacobian of its face pyramids' tetrahedra.
CellMeasure measure_polyhedron(const VolumeCells& cells, std::size_t c, const Eigen::Matrix3Xd& x) {
  CellMeasure m;
  m.cell = c;
  for (std::size_t k = 0; k < cells.degree(c); ++k) m.centroid += x.col(cells.nodes(c)[k]);
  if (cells.degree(c)) m.centroid /= static_cast<double>(cells.degree(c));
  m.scaled_jacobian = 1e300;
  const std::uint32_t* stream = cells.face.data() + cells.face_offset[c];
  const std::uint32_t faces = *stream++;
  for (std::uint32_t f = 0; f < faces; ++f) {
    const std::uint32_t n = *stream++;
    face_fan(x, stream, n, m.centroid, m.volume, [&m](const Vec& o, const Vec& p, const Vec& q, const Vec& g) {
      m.scaled_jacobian = std::min(m.scaled_jacobian, tet_scaled_jacobian(o, p, q, g));
    });
    stream += n;
  }
  if (faces == 0) m.scaled_jacobian = 0;
  return m;
}

// A tetrahedron without the general path's corner loop: every corner's determinant is
// the same 6V, so the lowest corner is the one whose three edges have the largest length
// product (the smallest, when 6V < 0). `by` is that product squared, so its scaled
// Jacobian is √2 det / √by (√2: the regular tetrahedron's 1/value): the same numbers as
// measure_shape's (up to rounding), at a fraction of the work.
struct TetraParts {
  double det = 0, by = 0;
};

TetraParts tetra_parts(const Eigen::Matrix3Xd& x, const std::uint32_t* n) {
  const Vec a = x.col(n[0]), e1 = x.col(n[1]) - a, e2 = x.col(n[2]) - a, e3 = x.col(n[3]) - a;
  const double det = e1.dot(e2.cross(e3));
  const double s01 = e1.squaredNorm(), s02 = e2.squaredNorm(), s03 = e3.squaredNorm();
  const double s12 = (e2 - e1).squaredNorm(), s13 = (e3 - e1).squaredNorm(), s23 = (e3 - e2).squaredNorm();
  const double p0 = s01 * s02 * s03, p1 = s01 * s12 * s13, p2 = s02 * s12 * s23, p3 = s03 * s13 * s23;
  return {det, det >= 0 ? std::max(std::max(p0, p1), std::max(p2, p3)) : std::min(std::min(p0, p1), std::min(p2, p3))};
}

double tetra_scaled(const TetraParts& t) { return t.by > 0 ? std::sqrt(2.0) * t.det / std::sqrt(t.by) : 0.0; }

// Whether a tetrahedron scores clearly above `bar` > 0, decided on squares without the
// root and the division: the margin is far above their rounding, so the computed score
// would compare the same way. A tiny determinant (whose score could underflow) is never
// passed.
bool clearly_above(const TetraParts& t, double bar) {
  return bar > 0 && t.det > 1e-150 && t.by > 0 && 2 * t.det * t.det > bar * bar * t.by * (1 + 1e-9);
}

// The order of the worst list: lowest scaled Jacobian first, then the lower cell.
bool worse(const CellMeasure& a, const CellMeasure& b) {
  if (a.scaled_jacobian != b.scaled_jacobian) return a.scaled_jacobian < b.scaled_jacobian;
  return a.cell < b.cell;
}

// Keeps the `keep` worst of `list` (sorted).
void trim_worst(std::vector<CellMeasure>& list, std::size_t keep) {
  std::sort(list.begin(), list.end(), worse);
  if (list.size() > keep) list.resize(keep);
}

// Merges one block's verdict into the total.
void merge(CellQuality& total, const CellQuality& part, std::size_t keep) {
  if (part.inverted && (!total.inverted || part.first_inverted < total.first_inverted))
    total.first_inverted = part.first_inverted;
  total.checked += part.checked;
  total.inverted += part.inverted;
  total.min_scaled_jacobian = std::min(total.min_scaled_jacobian, part.min_scaled_jacobian);
  total.worst.insert(total.worst.end(), part.worst.begin(), part.worst.end());
  trim_worst(total.worst, keep);
}

}  // namespace

CellMeasure measure_cell(const VolumeCells& cells, std::size_t c, const Eigen::Matrix3Xd& positions) {
  if (cells.type[c] == cell_type::kPolyhedron) return measure_polyhedron(cells, c, positions);
  if (cells.type[c] == cell_type::kTetra) {
    CellMeasure m;
    m.cell = c;
    const TetraParts t = tetra_parts(positions, cells.nodes(c));
    m.volume = t.det / 6;
    m.scaled_jacobian = tetra_scaled(t);
    for (int k = 0; k < 4; ++k) m.centroid += positions.col(cells.nodes(c)[k]);
    m.centroid /= 4;
    return m;
  }
  return measure_shape(cells, c, cells.type[c] == 11 ? hexahedron_shape() : *shape_of(cells.type[c]), positions);
}

namespace {

// The verdict on cells [first, end). The worst list is trimmed to `worst` whenever it
// holds twice that; after a trim it holds cells no worse than its last, so a cell that
// is not worse than that one cannot enter (nor lower the minimum, which is no higher).
CellQuality measure_block(const VolumeCells& cells, const Eigen::Matrix3Xd& positions, std::size_t worst,
                          std::size_t first, std::size_t end) {
  // The nodes of the tetrahedron kAhead cells on are fetched ahead: the cells' nodes are
  // scattered over the positions, and waiting for them was half the guard's time.
  constexpr std::size_t kAhead = 8;
  CellQuality part;
  CellMeasure bar;
  bool trimmed = false;
  for (std::size_t cell = first; cell < end; ++cell) {
    CellMeasure m;
    m.cell = cell;
    if (cells.type[cell] == cell_type::kTetra && cells.degree(cell) >= 4) {  // most cells of most meshes
      if (cell + kAhead < end && cells.offset[cell + kAhead] + 4 <= cells.node.size())
        for (int k = 0; k < 4; ++k) __builtin_prefetch(positions.data() + 3 * cells.node[cells.offset[cell + kAhead] + k]);
      const TetraParts t = tetra_parts(positions, cells.nodes(cell));
      const double pass = trimmed ? bar.scaled_jacobian : worst == 0 ? part.min_scaled_jacobian : 0;
      if (clearly_above(t, pass)) {  // neither inverted nor among the worst
        ++part.checked;
        continue;
      }
      m.volume = t.det / 6;
      m.scaled_jacobian = tetra_scaled(t);
    } else if (measured_cell(cells, cell)) {
      m = measure_cell(cells, cell, positions);
    } else {
      continue;
    }
    ++part.checked;
    if (inverted(m) && !part.inverted++) part.first_inverted = cell;
    part.min_scaled_jacobian = std::min(part.min_scaled_jacobian, m.scaled_jacobian);
    if (worst && (!trimmed || worse(m, bar))) {
      part.worst.push_back(m);
      if (part.worst.size() < 2 * worst) continue;
      trim_worst(part.worst, worst);
      bar = part.worst.back();
      trimmed = true;
    }
  }
  trim_worst(part.worst, worst);
  return part;
}

constexpr std::size_t kBlock = 1 << 14;  // cells; fixed blocks: the same result for any thread count

// Whether a cell of [first, end) has a node marked in `moved`.
bool block_moved(const VolumeCells& cells, const std::vector<char>& moved, std::size_t first, std::size_t end) {
  for (std::uint64_t k = cells.offset[first]; k < cells.offset[end]; ++k)
    if (moved[cells.node[k]]) return true;
  for (std::size_t c = first; c < end && !cells.face_offset.empty(); ++c)  // a polyhedron's faces name nodes too
    if (cells.type[c] == cell_type::kPolyhedron)
      for (std::uint64_t k = cells.face_offset[c]; k < (c + 1 < cells.size() ? cells.face_offset[c + 1] : cells.face.size()); ++k)
        if (moved[cells.face[k]]) return true;
  return false;
}

// Which nodes are not where they were (a node's flag, for a cheap look-up per cell node).
std::vector<char> moved_nodes(const Eigen::Matrix3Xd& now, const Eigen::Matrix3Xd& before) {
  std::vector<char> moved(static_cast<std::size_t>(now.cols()));
  for (Eigen::Index i = 0; i < now.cols(); ++i) moved[static_cast<std::size_t>(i)] = now.col(i) != before.col(i);
  return moved;
}

// Measures the blocks of cells (all, or those with a node marked in `moved`) into `parts`
// and merges them.
CellQuality measure_blocks(const VolumeCells& cells, const Eigen::Matrix3Xd& positions, std::size_t worst,
                           const std::vector<char>* moved, std::vector<CellQuality>& parts) {
  const std::size_t n = cells.size();
  parts.resize((n + kBlock - 1) / kBlock);
#pragma omp parallel for schedule(dynamic, 1)
  for (std::int64_t b = 0; b < static_cast<std::int64_t>(parts.size()); ++b) {
    const std::size_t first = static_cast<std::size_t>(b) * kBlock, end = std::min(n, first + kBlock);
    if (moved && !block_moved(cells, *moved, first, end)) continue;  // its verdict stands
    parts[static_cast<std::size_t>(b)] = measure_block(cells, positions, worst, first, end);
  }
  CellQuality total;
  for (const CellQuality& part : parts) merge(total, part, worst);
  for (CellMeasure& m : total.worst) m = measure_cell(cells, m.cell, positions);  // with its centroid
  return total;
}

}  // namespace

CellQuality cell_quality(const VolumeCells& cells, const Eigen::Matrix3Xd& positions, std::size_t worst) {
  std::vector<CellQuality> parts;
  return measure_blocks(cells, positions, worst, nullptr, parts);
}

CellQuality cell_quality(const VolumeCells& cells, const Eigen::Matrix3Xd& positions, CellQualityCache& cache,
                         std::size_t worst) {
  const bool reuse = cache.blocks.size() == (cells.size() + kBlock - 1) / kBlock && cache.worst == worst &&
                     cache.positions.cols() == positions.cols();
  const std::vector<char> moved = reuse ? moved_nodes(positions, cache.positions) : std::vector<char>();
  CellQuality total = measure_blocks(cells, positions, worst, reuse ? &moved : nullptr, cache.blocks);
  cache.positions = positions;
  cache.worst = worst;
  return total;
}

}  // namespace ffd
