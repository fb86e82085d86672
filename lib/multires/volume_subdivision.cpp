#include "multires/volume_subdivision.h"

#include <omp.h>

#include <algorithm>
#include <functional>
#include <iterator>
#include <tuple>

#include "common/madd.h"

namespace ffd {
namespace {

GridIndex shifted(GridIndex n, int axis, int by) {
  n[axis] += by;
  return n;
}

/// A stencil's points lie within one node of the new point's coarse node `base` on every
/// axis: the 27 nodes of base + [-1, 1]^3, numbered in (k, j, i) order. kFar: outside them.
constexpr std::uint8_t kFar = 27;

/// Adds weighted points, centroids and midpoints of a coarse complex to a stencil, looking
/// up each of the 27 nodes near `base` once, and hands each entry to `sink(point, weight,
/// node number near base or kFar)`, in the rules' order.
/// Complex: a GridComplex, or a StepGrid (a large octree level's implied C^k).
template <class Complex, class Sink>
struct StencilBuilder {
  const Complex& g;
  Sink& sink;
  GridIndex base;
  std::int32_t ids[27];

  StencilBuilder(const Complex& complex, Sink& s, const GridIndex& b) : g(complex), sink(s), base(b) {
    std::fill(std::begin(ids), std::end(ids), kUnknown);
  }
  void point(const GridIndex& n, double w) {
    const int dx = n[0] - base[0] + 1, dy = n[1] - base[1] + 1, dz = n[2] - base[2] + 1;
    const bool far = static_cast<unsigned>(dx) > 2 || static_cast<unsigned>(dy) > 2 || static_cast<unsigned>(dz) > 2;
    const int slot = far ? kFar : (dz * 3 + dy) * 3 + dx;
    if (!far && ids[slot] == kUnknown) ids[slot] = g.point(n);
    sink(far ? g.point(n) : ids[slot], w, slot);
  }
  /// Centroid of the cell whose first corner is `c`.
  void cell(const GridIndex& c, double w) {
    for (int k = 0; k < 8; ++k) point({c[0] + (k & 1), c[1] + ((k >> 1) & 1), c[2] + ((k >> 2) & 1)}, w / 8);
  }
  /// Centroid of the face across `axis` whose first corner is `f`.
  void face(const GridIndex& f, int axis, double w) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int k = 0; k < 4; ++k) point(shifted(shifted(f, u, k & 1), v, k >> 1), w / 4);
  }
  /// Midpoint of the edge along `axis` from node `e`.
  void edge(const GridIndex& e, int axis, double w) {
    point(e, w / 2);
    point(shifted(e, axis, 1), w / 2);
  }

private:
  static constexpr std::int32_t kUnknown = -2;  // not looked up yet (-1: no point there)
};

/// A sink that keeps the entries: the stencil, and each entry's node number when asked.
struct KeptStencil {
  Stencil& out;
  std::vector<std::uint8_t>* near;
  void operator()(std::int32_t point, double w, int slot) {
    // Member by member: a pair built whole and copied in is a store-forwarding stall.
    auto& entry = out.emplace_back();
    entry.first = point;
    entry.second = w;
    if (near) near->push_back(static_cast<std::uint8_t>(slot));
  }
};

/// A sink that adds each entry's share of a field to a new point's value as it comes:
/// value += w X.col(point), entry by entry in the stencil's order, each a multiply-add
/// as `out.col(f) += w * X.col(p)` compiles to (madd), so the same bits as keeping the
/// stencil and then summing it, without storing it.
struct SummedField {
  const double* X;  // column-major, `rows` per column
  Eigen::Index rows;
  double* value;
  void operator()(std::int32_t point, double w, int) {
    const double* x = X + static_cast<Eigen::Index>(point) * rows;
    for (Eigen::Index r = 0; r < rows; ++r) value[r] = madd(w, x[r], value[r]);
  }
};

template <class Complex>
bool present(const Complex& g, const GridIndex& c) { return g.has_cell(c[0], c[1], c[2]); }

/// The cells around the edge along `axis` from node `e`: c[0] = e, c[1] = e - u, c[2] = e - v,
/// c[3] = e - u - v (u, v the other axes).
struct EdgeRing {
  GridIndex cell[4];
  bool in[4];
  int count = 0;
  template <class Complex>
  EdgeRing(const Complex& g, const GridIndex& e, int axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    cell[0] = e;
    cell[1] = shifted(e, u, -1);
    cell[2] = shifted(e, v, -1);
    cell[3] = shifted(cell[1], v, -1);
    for (int k = 0; k < 4; ++k) count += in[k] = present(g, cell[k]);
  }
  bool exists() const { return count > 0; }
  bool interior() const { return count == 4; }
  /// A sharp edge: in one cell only, or shared by two cells that meet only along it
  /// (a non-manifold edge of the boundary, which we keep as a crease).
  bool sharp() const { return count == 1 || (count == 2 && ((in[0] && in[3]) || (in[1] && in[2]))); }
};

/// The four faces around an edge, each as (first corner, normal axis, its two cells in EdgeRing order).
struct EdgeFace {
  GridIndex corner;
  int axis, a, b;
};
void edge_faces(const GridIndex& e, int axis, EdgeFace out[4]) {
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  out[0] = {e, v, 0, 2};                  // spans axis and +u, across v
  out[1] = {shifted(e, u, -1), v, 1, 3};  // spans axis and -u
  out[2] = {e, u, 0, 1};                  // spans axis and +v, across u
  out[3] = {shifted(e, v, -1), u, 2, 3};  // spans axis and -v
}

template <class Complex, class Builder>
void edge_stencil(const Complex& g, const GridIndex& e, int axis, Builder& s) {
  const EdgeRing ring(g, e, axis);
  if (ring.interior()) {  // E = (C_avg + 2 A_avg + (n - 3) M) / n with n = 4 faces
    for (int k = 0; k < 4; ++k) s.cell(ring.cell[k], 1.0 / 16);
    EdgeFace faces[4];
    edge_faces(e, axis, faces);
    for (const EdgeFace& f : faces) s.face(f.corner, f.axis, 2.0 / 16);
    s.edge(e, axis, 1.0 / 4);
    return;
  }
  if (ring.sharp()) return s.edge(e, axis, 1.0);  // sharp edge: its midpoint
  // Catmull-Clark surface rule on the boundary: (P0 + P1 + F0 + F1) / 4, the F being the
  // face points (centroids) of the boundary faces at the edge.
  EdgeFace faces[4];
  edge_faces(e, axis, faces);
  int boundary = 0;
  for (const EdgeFace& f : faces) boundary += ring.in[f.a] != ring.in[f.b];
  s.edge(e, axis, 0.5);
  for (const EdgeFace& f : faces)
    if (ring.in[f.a] != ring.in[f.b]) s.face(f.corner, f.axis, 0.5 / boundary);
}

/// The vertex point of a boundary point p (fewer than 8 cells around it).
template <class Complex, class Builder>
void boundary_vertex_stencil(const Complex& g, const GridIndex& p, Builder& s) {
  int sharp = 0, boundary_edges = 0;
  GridIndex sharp_edge[6];
  int sharp_axis[6];
  for (int axis = 0; axis < 3; ++axis)
    for (int dir = 0; dir < 2; ++dir) {
      const GridIndex e = dir ? shifted(p, axis, -1) : p;
      const EdgeRing ring(g, e, axis);
      if (!ring.exists()) continue;
      if (ring.sharp()) sharp_edge[sharp] = e, sharp_axis[sharp++] = axis;
      boundary_edges += !ring.interior();
    }
  if (sharp >= 3 || boundary_edges < 3) return s.point(p, 1.0);  // a corner point: kept
  if (sharp == 2) {  // a sharp point: (M1 + 2P + M2) / 4
    s.point(p, 0.5);
    s.edge(sharp_edge[0], sharp_axis[0], 0.25);
    s.edge(sharp_edge[1], sharp_axis[1], 0.25);
    return;
  }
  // Catmull-Clark surface rule: (Q + 2R + (n - 3) P) / n over the boundary faces and edges.
  std::pair<GridIndex, int> faces[12];
  int count = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int k = 0; k < 4; ++k) {
      const GridIndex f = shifted(shifted(p, (axis + 1) % 3, -(k & 1)), (axis + 2) % 3, -(k >> 1));
      if (present(g, f) != present(g, shifted(f, axis, -1))) faces[count++] = {f, axis};
    }
  const double n = boundary_edges;
  for (int i = 0; i < count; ++i) s.face(faces[i].first, faces[i].second, 1.0 / (n * count));
  for (int axis = 0; axis < 3; ++axis)
    for (int dir = 0; dir < 2; ++dir) {
      const GridIndex e = dir ? shifted(p, axis, -1) : p;
      const EdgeRing ring(g, e, axis);
      if (ring.exists() && !ring.interior()) s.edge(e, axis, 2.0 / (n * n));
    }
  s.point(p, (n - 3) / n);
}

template <class Complex, class Builder>
void vertex_stencil(const Complex& g, const GridIndex& p, Builder& s) {
  int cells = 0;
  for (int k = 0; k < 8; ++k) cells += present(g, {p[0] - (k & 1), p[1] - ((k >> 1) & 1), p[2] - ((k >> 2) & 1)});
  if (cells == 1) return s.point(p, 1.0);  // a corner point stays where it is
  if (cells < 8) return boundary_vertex_stencil(g, p, s);
  // V = (C_avg + 3 A_avg + 3 M_avg + P) / 8: 8 cells, 12 faces, 6 edges.
  for (int k = 0; k < 8; ++k) s.cell({p[0] - (k & 1), p[1] - ((k >> 1) & 1), p[2] - ((k >> 2) & 1)}, 1.0 / 64);
  for (int axis = 0; axis < 3; ++axis)
    for (int k = 0; k < 4; ++k)
      s.face(shifted(shifted(p, (axis + 1) % 3, -(k & 1)), (axis + 2) % 3, -(k >> 1)), axis, 3.0 / 96);
  for (int axis = 0; axis < 3; ++axis) {
    s.edge(p, axis, 3.0 / 48);
    s.edge(shifted(p, axis, -1), axis, 3.0 / 48);
  }
  s.point(p, 1.0 / 8);
}

/// The new point at fine `node`'s stencil over the coarse points, entry by entry into
/// `sink` (StencilBuilder).
template <class Complex, class Sink>
void apply_rule(const Complex& coarse, const GridIndex& node, SubdivisionRule rule, Sink& sink) {
  const GridIndex base{node[0] >> 1, node[1] >> 1, node[2] >> 1};
  StencilBuilder<Complex, Sink> s(coarse, sink, base);
  const int odd = (node[0] & 1) + (node[1] & 1) + (node[2] & 1);
  const bool cc = rule == SubdivisionRule::CatmullClark;
  if (odd == 3) return s.cell(base, 1.0);
  if (odd == 2) {
    const int axis = (node[0] & 1) == 0 ? 0 : (node[1] & 1) == 0 ? 1 : 2;
    const bool two = present(coarse, base) && present(coarse, shifted(base, axis, -1));
    if (!cc || !two) return s.face(base, axis, 1.0);
    s.cell(base, 0.25);  // F = (C0 + 2A + C1) / 4
    s.cell(shifted(base, axis, -1), 0.25);
    return s.face(base, axis, 0.5);
  }
  if (odd == 1) {
    const int axis = (node[0] & 1) ? 0 : (node[1] & 1) ? 1 : 2;
    if (!cc) return s.edge(base, axis, 1.0);
    return edge_stencil(coarse, base, axis, s);
  }
  if (!cc) return s.point(base, 1.0);
  vertex_stencil(coarse, base, s);
}

template <class Complex>
void stencil_of(const Complex& coarse, const GridIndex& node, SubdivisionRule rule, Stencil& out,
                std::vector<std::uint8_t>* near = nullptr) {
  out.clear();
  if (near) near->clear();
  KeptStencil sink{out, near};
  apply_rule(coarse, node, rule, sink);
}

}  // namespace

void subdivision_stencil(const GridComplex& coarse, const GridIndex& node, SubdivisionRule rule, Stencil& out) {
  stencil_of(coarse, node, rule, out);
}

void subdivision_stencil(const StepGrid& coarse, const GridIndex& node, SubdivisionRule rule, Stencil& out) {
  stencil_of(coarse, node, rule, out);
}

namespace {

/// Whether the rule for the new point at `node` takes its fixed branch: a cell point;
/// a face point between two cells; an edge point inside four cells; a vertex point inside
/// eight (or any point under the octree rules). Its stencil's entries, as nodes near the
/// node's coarse node and weights, are then the same for every such point of its kind.
template <class Complex>
bool fixed_stencil(const Complex& g, const GridIndex& node, SubdivisionRule rule) {
  if (rule != SubdivisionRule::CatmullClark) return true;
  const GridIndex base{node[0] >> 1, node[1] >> 1, node[2] >> 1};
  const int odd = (node[0] & 1) + (node[1] & 1) + (node[2] & 1);
  if (odd == 3) return true;
  if (odd == 2) {
    const int axis = (node[0] & 1) == 0 ? 0 : (node[1] & 1) == 0 ? 1 : 2;
    return present(g, base) && present(g, shifted(base, axis, -1));
  }
  if (odd == 1) return EdgeRing(g, base, (node[0] & 1) ? 0 : (node[1] & 1) ? 1 : 2).interior();
  for (int k = 0; k < 8; ++k)
    if (!present(g, {base[0] - (k & 1), base[1] - ((k >> 1) & 1), base[2] - ((k >> 2) & 1)})) return false;
  return true;
}

/// A sink that records a stencil's entries as (node near base, weight).
struct NodeStencil {
  std::vector<std::pair<std::uint8_t, double>>& out;
  void operator()(std::int32_t, double w, int slot) { out.push_back({static_cast<std::uint8_t>(slot), w}); }
};

/// The fixed stencils of one rule by kind of new point (which node coordinates are odd),
/// recorded from the rules at the first point of the kind that takes the fixed branch.
/// A point with one is summed from it: its nodes looked up once, its entries run in the
/// rules' order with SummedField's arithmetic (the same bits as the rules), without the
/// rules' branches and per-entry node arithmetic. Most new points of a level take it.
struct FixedStencils {
  std::vector<std::pair<std::uint8_t, double>> entries[8];
  std::uint32_t used[8] = {};  // the nodes near base each reads; bit kFar: one beyond them
  bool recorded[8] = {};

  /// Sums the new point at `node`, for which fixed_stencil holds, into `field`.
  template <class Complex>
  void sum(const Complex& g, const GridIndex& node, SubdivisionRule rule, const SummedField& field) {
    const int kind = (node[0] & 1) | (node[1] & 1) << 1 | (node[2] & 1) << 2;
    if (!recorded[kind]) {
      NodeStencil sink{entries[kind]};
      apply_rule(g, node, rule, sink);
      for (const auto& [slot, w] : entries[kind]) used[kind] |= 1u << slot;
      recorded[kind] = true;
    }
    if (used[kind] >> kFar) {  // reaches past the nodes near base: the rules' way
      SummedField sink = field;
      return apply_rule(g, node, rule, sink);
    }
    const GridIndex base{node[0] >> 1, node[1] >> 1, node[2] >> 1};
    std::int32_t ids[27];
    for (int slot = 0; slot < 27; ++slot)
      if (used[kind] >> slot & 1) ids[slot] = g.point(base[0] + slot % 3 - 1, base[1] + slot / 3 % 3 - 1, base[2] + slot / 9 - 1);
    if (field.rows != 3) {
      for (const auto& [slot, w] : entries[kind]) {
        const double* x = field.X + static_cast<Eigen::Index>(ids[slot]) * field.rows;
        for (Eigen::Index r = 0; r < field.rows; ++r) field.value[r] = madd(w, x[r], field.value[r]);
      }
      return;
    }
    double v[3] = {field.value[0], field.value[1], field.value[2]};  // in registers, not through memory
    for (const auto& [slot, w] : entries[kind]) {
      const double* x = field.X + 3 * static_cast<Eigen::Index>(ids[slot]);
      v[0] = madd(w, x[0], v[0]), v[1] = madd(w, x[1], v[1]), v[2] = madd(w, x[2], v[2]);
    }
    std::copy(v, v + 3, field.value);
  }
};

// The field at the new points for which computed(node) holds (the others stay zero).
template <class Computed>
Eigen::MatrixXd subdivide_where(const GridComplex& coarse, const GridComplex& fine, const Eigen::MatrixXd& X,
                                SubdivisionRule rule, Computed computed) {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(X.rows(), static_cast<Eigen::Index>(fine.num_points()));
  const long long n = static_cast<long long>(fine.num_points());
#pragma omp parallel
  {
    FixedStencils fixed;
#pragma omp for schedule(static)
    for (long long f = 0; f < n; ++f) {
      const GridIndex& node = fine.points[static_cast<std::size_t>(f)];
      if (!computed(node)) continue;
      SummedField sink{X.data(), X.rows(), out.col(f).data()};  // out.col(f) starts at zero
      if (fixed_stencil(coarse, node, rule))
        fixed.sum(coarse, node, rule, sink);
      else
        apply_rule(coarse, node, rule, sink);
    }
  }
  return out;
}

}  // namespace

Eigen::MatrixXd subdivide_field(const GridComplex& coarse, const GridComplex& fine, const Eigen::MatrixXd& X,
                                SubdivisionRule rule) {
  return subdivide_where(coarse, fine, X, rule, [](const GridIndex&) { return true; });
}

Eigen::MatrixXd subdivide_sparse_field(const GridComplex& coarse, const GridComplex& fine, const Eigen::MatrixXd& X,
                                       const std::vector<std::uint8_t>& nonzero, SubdivisionRule rule) {
  // A stencil reads coarse points within 1 node of the new point's coarse node `base`
  // (node / 2) on every axis but the ones it spans (cells, faces, edges: up to base + 1):
  // a Chebyshev ball of 2 around base holds them all. `reach` marks, over the coarse
  // nodes' bounding range, the nodes within 2 of a non-zero point.
  const GridIndex lo = coarse.lo, hi = coarse.hi;
  const long long nx = hi[0] - lo[0] + 1, ny = hi[1] - lo[1] + 1, nz = hi[2] - lo[2] + 1;
  std::vector<std::uint8_t> reach(static_cast<std::size_t>(nx * ny * nz), 0);
  for (std::size_t p = 0; p < coarse.num_points(); ++p) {
    if (!nonzero[p]) continue;
    const GridIndex& c = coarse.points[p];
    for (long long k = std::max<long long>(0, c[2] - lo[2] - 2); k <= std::min(nz - 1, c[2] - lo[2] + 2LL); ++k)
      for (long long j = std::max<long long>(0, c[1] - lo[1] - 2); j <= std::min(ny - 1, c[1] - lo[1] + 2LL); ++j)
        for (long long i = std::max<long long>(0, c[0] - lo[0] - 2); i <= std::min(nx - 1, c[0] - lo[0] + 2LL); ++i)
          reach[static_cast<std::size_t>((k * ny + j) * nx + i)] = 1;
  }
  const auto reached = [&](const GridIndex& node) {
    const long long i = (node[0] >> 1) - lo[0], j = (node[1] >> 1) - lo[1], k = (node[2] >> 1) - lo[2];
    return i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz && reach[static_cast<std::size_t>((k * ny + j) * nx + i)];
  };
  return subdivide_where(coarse, fine, X, rule, reached);
}

namespace {

/// Appends the row of `stencil` with its weights merged per coarse point, summed in the
/// stencil's order (as setFromTriplets sums duplicates), in the order of the points' nodes.
/// `near`: each entry's node number near the new point (stencil_of), so merged by number,
/// in number order. `node_order(a, b)`: whether coarse point a's node comes before b's,
/// for a stencil reaching beyond the 27 nodes (none of the grid rules do).
template <class NodeOrder>
void append_merged(const Stencil& stencil, const std::vector<std::uint8_t>& near, std::vector<std::int32_t>& columns,
                   std::vector<double>& values, NodeOrder node_order) {
  if (std::find(near.begin(), near.end(), kFar) != near.end()) {
    Stencil merged;
    for (const auto& [p, w] : stencil) {
      auto at = std::find_if(merged.begin(), merged.end(), [p = p](const auto& e) { return e.first == p; });
      if (at == merged.end())
        merged.push_back({p, w});
      else
        at->second += w;
    }
    std::sort(merged.begin(), merged.end(), [&](const auto& a, const auto& b) { return node_order(a.first, b.first); });
    for (const auto& [p, w] : merged) columns.push_back(p), values.push_back(w);
    return;
  }
  std::uint32_t seen = 0;
  double sum[27];
  std::int32_t id[27];
  for (std::size_t i = 0; i < stencil.size(); ++i) {
    const std::uint8_t n = near[i];
    if (seen >> n & 1) {
      sum[n] += stencil[i].second;
    } else {
      seen |= 1u << n;
      sum[n] = stencil[i].second;
      id[n] = stencil[i].first;
    }
  }
  for (int n = 0; n < 27; ++n)
    if (seen >> n & 1) columns.push_back(id[n]), values.push_back(sum[n]);
}

/// A row-major sparse matrix built a row at a time, in row order.
struct CsrRows {
  std::vector<int> starts{0}, columns;
  std::vector<double> values;

  /// Room for `rows` rows of at most 27 entries: one allocation, of which only what is
  /// written gets memory.
  void reserve(std::size_t rows) {
    starts.reserve(rows + 1);
    columns.reserve(27 * rows);
    values.reserve(27 * rows);
  }
  /// Appends the row of `stencil` over a GridComplex (append_merged), whose points are
  /// numbered in node order: columns ascending.
  void append(const Stencil& stencil, const std::vector<std::uint8_t>& near) {
    append_merged(stencil, near, columns, values, std::less<std::int32_t>());
    starts.push_back(static_cast<int>(columns.size()));
  }
};

/// The matrix of rows made in parts, each part's rows following the previous part's.
Eigen::SparseMatrix<double, Eigen::RowMajor> csr_matrix(const std::vector<CsrRows>& parts, Eigen::Index rows,
                                                        Eigen::Index cols) {
  Eigen::SparseMatrix<double, Eigen::RowMajor> S(rows, cols);
  std::size_t nonzeros = 0;
  for (const CsrRows& part : parts) nonzeros += part.columns.size();
  S.resizeNonZeros(static_cast<Eigen::Index>(nonzeros));
  int* outer = S.outerIndexPtr();
  Eigen::Index row = 0;
  int offset = 0;
  for (const CsrRows& part : parts) {
    for (std::size_t r = 0; r + 1 < part.starts.size(); ++r) outer[row++] = offset + part.starts[r];
    std::copy(part.columns.begin(), part.columns.end(), S.innerIndexPtr() + offset);
    std::copy(part.values.begin(), part.values.end(), S.valuePtr() + offset);
    offset += static_cast<int>(part.columns.size());
  }
  outer[row] = offset;
  return S;
}

}  // namespace

Eigen::MatrixXd subdivide_field_and_matrix(const GridComplex& coarse, const GridComplex& fine, const Eigen::MatrixXd& X,
                                           SubdivisionRule rule, Eigen::SparseMatrix<double, Eigen::RowMajor>& matrix) {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(X.rows(), static_cast<Eigen::Index>(fine.num_points()));
  const long long n = static_cast<long long>(fine.num_points());
  std::vector<CsrRows> parts;  // per thread: its static chunk of rows, in order
#pragma omp parallel
  {
#pragma omp single
    parts.resize(static_cast<std::size_t>(omp_get_num_threads()));
    CsrRows& mine = parts[static_cast<std::size_t>(omp_get_thread_num())];
    mine.reserve(static_cast<std::size_t>(n / omp_get_num_threads() + 1));
    Stencil stencil;
    std::vector<std::uint8_t> near;
#pragma omp for schedule(static)
    for (long long f = 0; f < n; ++f) {
      stencil_of(coarse, fine.points[static_cast<std::size_t>(f)], rule, stencil, &near);
      for (const auto& [p, w] : stencil) out.col(f) += w * X.col(p);
      mine.append(stencil, near);
    }
  }
  matrix = csr_matrix(parts, static_cast<Eigen::Index>(fine.num_points()), static_cast<Eigen::Index>(coarse.num_points()));
  return out;
}

Eigen::SparseMatrix<double, Eigen::RowMajor> subdivision_matrix(const GridComplex& coarse,
                                                               const std::vector<GridIndex>& nodes, SubdivisionRule rule) {
  std::vector<CsrRows> rows(1);
  Stencil stencil;
  std::vector<std::uint8_t> near;
  for (const GridIndex& node : nodes) {
    stencil_of(coarse, node, rule, stencil, &near);
    rows[0].append(stencil, near);
  }
  return csr_matrix(rows, static_cast<Eigen::Index>(nodes.size()), static_cast<Eigen::Index>(coarse.num_points()));
}

std::int32_t SubdivisionRows::append(const StepGrid& coarse, const GridIndex& node, SubdivisionRule rule) {
  stencil_of(coarse, node, rule, stencil_, &near_);
  const auto node_order = [&](std::int32_t a, std::int32_t b) {
    const GridIndex na = coarse.node(a), nb = coarse.node(b);
    return std::make_tuple(na[2], na[1], na[0]) < std::make_tuple(nb[2], nb[1], nb[0]);
  };
  append_merged(stencil_, near_, columns_, values_, node_order);
  starts_.push_back(static_cast<int>(columns_.size()));
  return static_cast<std::int32_t>(starts_.size() - 2);
}

Eigen::SparseMatrix<double, Eigen::RowMajor> SubdivisionRows::matrix(const std::vector<std::int32_t>& rows,
                                                                     Eigen::Index cols) const {
  Eigen::SparseMatrix<double, Eigen::RowMajor> S(static_cast<Eigen::Index>(rows.size()), cols);
  std::size_t nonzeros = 0;
  for (const std::int32_t r : rows) nonzeros += static_cast<std::size_t>(starts_[r + 1] - starts_[r]);
  S.resizeNonZeros(static_cast<Eigen::Index>(nonzeros));
  int* outer = S.outerIndexPtr();
  int offset = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const int begin = starts_[rows[i]], end = starts_[rows[i] + 1];
    outer[i] = offset;
    std::copy(columns_.begin() + begin, columns_.begin() + end, S.innerIndexPtr() + offset);
    std::copy(values_.begin() + begin, values_.begin() + end, S.valuePtr() + offset);
    offset += end - begin;
  }
  outer[rows.size()] = offset;
  return S;
}

std::size_t SubdivisionRows::bytes() const {
  return starts_.capacity() * sizeof(int) + columns_.capacity() * sizeof(std::int32_t) + values_.capacity() * sizeof(double);
}

}  // namespace ffd
