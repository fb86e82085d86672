// catmull_clark_step: MacCracken & Joy's subdivision volumes on a CellComplex (Ono et al.'s
// appendix): the point rules with the boundary rules, and the reconnection rules (1)-(3).
#include <algorithm>
#include <stdexcept>

#include "multires/cell_complex.h"

namespace ffd {
namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

/// Who contains what, for the rules and the classification of boundary elements.
struct Incidence {
  std::vector<std::int32_t> face_cells;                      // 2 per face, -1 when absent
  std::vector<std::vector<std::int32_t>> edge_faces, edge_cells, point_faces, point_edges, point_cells;
  std::vector<std::vector<std::int32_t>> cell_points;
  std::vector<int> edge_boundary_faces;  // faces of the edge in one cell only

  bool boundary_face(std::int32_t f) const { return face_cells[2 * static_cast<std::size_t>(f) + 1] < 0; }
  bool sharp_edge(std::int32_t e) const {  // in one cell, or a non-manifold edge of the boundary
    const int b = edge_boundary_faces[static_cast<std::size_t>(e)];
    return edge_cells[static_cast<std::size_t>(e)].size() == 1 || (b > 0 && b != 2);
  }
};

void add_unique(std::vector<std::int32_t>& v, std::int32_t x) {
  if (std::find(v.begin(), v.end(), x) == v.end()) v.push_back(x);
}

Incidence incidence(const CellComplex& k) {
  Incidence in;
  const std::size_t P = static_cast<std::size_t>(k.num_points), E = k.edges.size(), F = k.num_faces(), C = k.num_cells();
  in.face_cells.assign(2 * F, -1);
  in.edge_faces.resize(E), in.edge_cells.resize(E), in.point_faces.resize(P), in.point_edges.resize(P),
      in.point_cells.resize(P), in.cell_points.resize(C);
  in.edge_boundary_faces.assign(E, 0);
  for (std::size_t c = 0; c < C; ++c)
    for (std::int32_t i = k.cell_offsets[c]; i < k.cell_offsets[c + 1]; ++i) {
      const std::size_t f = static_cast<std::size_t>(k.cell_faces[static_cast<std::size_t>(i)]);
      in.face_cells[2 * f + (in.face_cells[2 * f] < 0 ? 0 : 1)] = static_cast<std::int32_t>(c);
    }
  for (std::size_t f = 0; f < F; ++f)
    for (std::int32_t j = k.face_offsets[f]; j < k.face_offsets[f + 1]; ++j) {
      const std::int32_t e = k.face_edges[static_cast<std::size_t>(j)], p = k.face_points[static_cast<std::size_t>(j)];
      in.edge_faces[static_cast<std::size_t>(e)].push_back(static_cast<std::int32_t>(f));
      in.point_faces[static_cast<std::size_t>(p)].push_back(static_cast<std::int32_t>(f));
      for (int s = 0; s < 2; ++s)
        if (in.face_cells[2 * f + s] >= 0) add_unique(in.edge_cells[static_cast<std::size_t>(e)], in.face_cells[2 * f + s]);
      in.edge_boundary_faces[static_cast<std::size_t>(e)] += in.boundary_face(static_cast<std::int32_t>(f));
    }
  for (std::size_t e = 0; e < E; ++e)
    for (std::int32_t p : k.edges[e]) in.point_edges[static_cast<std::size_t>(p)].push_back(static_cast<std::int32_t>(e));
  for (std::size_t c = 0; c < C; ++c) {
    in.cell_points[c] = k.cell_points(c);
    for (std::int32_t p : in.cell_points[c]) in.point_cells[static_cast<std::size_t>(p)].push_back(static_cast<std::int32_t>(c));
  }
  return in;
}

/// Adds weighted points, centroids and midpoints of the coarse complex to one row.
struct Row {
  const CellComplex& k;
  const Incidence& in;
  Triplets& t;
  int row;
  void point(std::int32_t p, double w) { t.emplace_back(row, p, w); }
  void mid(std::int32_t e, double w) {
    point(k.edges[static_cast<std::size_t>(e)][0], w / 2);
    point(k.edges[static_cast<std::size_t>(e)][1], w / 2);
  }
  void face(std::int32_t f, double w) {
    const double n = k.face_offsets[f + 1] - k.face_offsets[f];
    for (std::int32_t j = k.face_offsets[f]; j < k.face_offsets[f + 1]; ++j) point(k.face_points[static_cast<std::size_t>(j)], w / n);
  }
  void cell(std::int32_t c, double w) {
    const auto& pts = in.cell_points[static_cast<std::size_t>(c)];
    for (std::int32_t p : pts) point(p, w / static_cast<double>(pts.size()));
  }
};

void edge_rule(Row& r, std::int32_t e) {
  const Incidence& in = r.in;
  const auto& faces = in.edge_faces[static_cast<std::size_t>(e)];
  const auto& cells = in.edge_cells[static_cast<std::size_t>(e)];
  if (in.edge_boundary_faces[static_cast<std::size_t>(e)] == 0) {  // E = (C_avg + 2 A_avg + (n - 3) M) / n
    const double n = static_cast<double>(faces.size());
    for (std::int32_t c : cells) r.cell(c, 1.0 / (n * static_cast<double>(cells.size())));
    for (std::int32_t f : faces) r.face(f, 2.0 / (n * n));
    return r.mid(e, (n - 3) / n);
  }
  if (in.sharp_edge(e)) return r.mid(e, 1.0);
  r.mid(e, 0.5);  // surface rule: (P0 + P1 + F0 + F1) / 4 over the two boundary faces
  for (std::int32_t f : faces)
    if (in.boundary_face(f)) r.face(f, 0.25);
}

void vertex_rule(Row& r, std::int32_t p) {
  const Incidence& in = r.in;
  const auto& faces = in.point_faces[static_cast<std::size_t>(p)];
  const auto& edges = in.point_edges[static_cast<std::size_t>(p)];
  const auto& cells = in.point_cells[static_cast<std::size_t>(p)];
  std::vector<std::int32_t> boundary_faces, boundary_edges, sharp;
  for (std::int32_t f : faces)
    if (in.boundary_face(f)) boundary_faces.push_back(f);
  for (std::int32_t e : edges) {
    if (in.edge_boundary_faces[static_cast<std::size_t>(e)] > 0) boundary_edges.push_back(e);
    if (in.sharp_edge(e)) sharp.push_back(e);
  }
  if (boundary_faces.empty()) {  // V = (C_avg + 3 A_avg + 3 M_avg + P) / 8
    for (std::int32_t c : cells) r.cell(c, 1.0 / (8.0 * static_cast<double>(cells.size())));
    for (std::int32_t f : faces) r.face(f, 3.0 / (8.0 * static_cast<double>(faces.size())));
    for (std::int32_t e : edges) r.mid(e, 3.0 / (8.0 * static_cast<double>(edges.size())));
    return r.point(p, 1.0 / 8);
  }
  const double n = static_cast<double>(boundary_edges.size());
  if (cells.size() == 1 || sharp.size() >= 3 || n < 3) return r.point(p, 1.0);  // corner point
  if (sharp.size() == 2) {  // sharp point: (M1 + 2P + M2) / 4
    r.point(p, 0.5);
    r.mid(sharp[0], 0.25);
    return r.mid(sharp[1], 0.25);
  }
  // Catmull-Clark surface rule: (Q + 2R + (n - 3) P) / n.
  for (std::int32_t f : boundary_faces) r.face(f, 1.0 / (n * static_cast<double>(boundary_faces.size())));
  for (std::int32_t e : boundary_edges) r.mid(e, 2.0 / (n * n));
  r.point(p, (n - 3) / n);
}

Triplets stencils(const CellComplex& k, const Incidence& in) {
  Triplets t;
  const int P = k.num_points, E = static_cast<int>(k.edges.size()), F = static_cast<int>(k.num_faces());
  for (int p = 0; p < P; ++p) {
    Row r{k, in, t, p};
    vertex_rule(r, p);
  }
  for (int e = 0; e < E; ++e) {
    Row r{k, in, t, P + e};
    edge_rule(r, e);
  }
  for (int f = 0; f < F; ++f) {
    Row r{k, in, t, P + E + f};
    if (in.boundary_face(f)) {
      r.face(f, 1.0);
    } else {  // F = (C0 + 2A + C1) / 4
      r.cell(in.face_cells[2 * static_cast<std::size_t>(f)], 0.25);
      r.cell(in.face_cells[2 * static_cast<std::size_t>(f) + 1], 0.25);
      r.face(f, 0.5);
    }
  }
  for (int c = 0; c < static_cast<int>(k.num_cells()); ++c) {
    Row r{k, in, t, P + E + F + c};
    r.cell(c, 1.0);
  }
  return t;
}

/// One use of an edge by a face of a cell: the edge, the face, the face slot holding the
/// edge, the cell slot holding the face.
struct EdgeUse {
  std::int32_t edge, face, face_slot, cell_slot;
  bool operator<(const EdgeUse& o) const { return edge < o.edge || (edge == o.edge && face < o.face); }
};

/// The edges of cell c, each with its two faces in the cell. \throw std::logic_error for
/// a cell that is not closed.
std::vector<std::pair<EdgeUse, EdgeUse>> cell_edges(const CellComplex& k, std::size_t c) {
  std::vector<EdgeUse> uses;
  for (std::int32_t t = k.cell_offsets[c]; t < k.cell_offsets[c + 1]; ++t) {
    const std::int32_t f = k.cell_faces[static_cast<std::size_t>(t)];
    for (std::int32_t j = k.face_offsets[f]; j < k.face_offsets[f + 1]; ++j)
      uses.push_back({k.face_edges[static_cast<std::size_t>(j)], f, j, t});
  }
  std::sort(uses.begin(), uses.end());
  std::vector<std::pair<EdgeUse, EdgeUse>> out;
  for (std::size_t i = 0; i < uses.size(); i += 2) {
    if (i + 1 >= uses.size() || uses[i + 1].edge != uses[i].edge || (i + 2 < uses.size() && uses[i + 2].edge == uses[i].edge))
      throw std::logic_error("catmull_clark_step: a cell of the lattice is not closed");
    out.push_back({uses[i], uses[i + 1]});
  }
  return out;
}

/// Reconnection: a quad per (face, corner) and per (cell, edge); a cell per (cell, point).
CellComplex refine_topology(const CellComplex& k, const Incidence& in) {
  const std::int32_t P = k.num_points, E = static_cast<std::int32_t>(k.edges.size()),
                     F = static_cast<std::int32_t>(k.num_faces()), L = static_cast<std::int32_t>(k.face_points.size());
  CellComplex out;
  out.num_points = P + E + F + static_cast<std::int32_t>(k.num_cells());
  for (const auto& e : k.edges) out.edges.push_back({e[0], P}), out.edges.push_back({P, e[1]});
  for (std::int32_t e = 0; e < E; ++e) out.edges[2 * e][1] = out.edges[2 * e + 1][0] = P + e;
  for (std::int32_t f = 0; f < F; ++f)
    for (std::int32_t j = k.face_offsets[f]; j < k.face_offsets[f + 1]; ++j)
      out.edges.push_back({P + k.face_edges[static_cast<std::size_t>(j)], P + E + f});
  for (std::size_t c = 0; c < k.num_cells(); ++c)
    for (std::int32_t t = k.cell_offsets[c]; t < k.cell_offsets[c + 1]; ++t)
      out.edges.push_back({P + E + k.cell_faces[static_cast<std::size_t>(t)], P + E + F + static_cast<std::int32_t>(c)});
  auto half = [&](std::int32_t v, std::int32_t e) { return k.edges[static_cast<std::size_t>(e)][0] == v ? 2 * e : 2 * e + 1; };
  auto quad = [&](std::array<std::int32_t, 4> p, std::array<std::int32_t, 4> e) {
    out.face_points.insert(out.face_points.end(), p.begin(), p.end());
    out.face_edges.insert(out.face_edges.end(), e.begin(), e.end());
    out.face_offsets.push_back(static_cast<std::int32_t>(out.face_points.size()));
  };
  for (std::int32_t f = 0; f < F; ++f) {  // (corner, edge point, face point, edge point)
    const std::int32_t o = k.face_offsets[f], n = k.face_offsets[f + 1] - o;
    for (std::int32_t i = 0; i < n; ++i) {
      const std::int32_t j = o + i, jp = o + (i + n - 1) % n, v = k.face_points[static_cast<std::size_t>(j)];
      const std::int32_t en = k.face_edges[static_cast<std::size_t>(j)], ep = k.face_edges[static_cast<std::size_t>(jp)];
      quad({v, P + en, P + E + f, P + ep}, {half(v, en), 2 * E + j, 2 * E + jp, half(v, ep)});
    }
  }
  std::vector<std::vector<std::pair<EdgeUse, EdgeUse>>> edges_of(k.num_cells());
  for (std::size_t c = 0; c < k.num_cells(); ++c) {  // (edge point, face point, cell point, face point)
    edges_of[c] = cell_edges(k, c);
    const std::int32_t cp = P + E + F + static_cast<std::int32_t>(c);
    for (const auto& [a, b] : edges_of[c])
      quad({P + a.edge, P + E + a.face, cp, P + E + b.face},
           {2 * E + a.face_slot, 2 * E + L + a.cell_slot, 2 * E + L + b.cell_slot, 2 * E + b.face_slot});
  }
  std::int32_t next_b = L;
  for (std::size_t c = 0; c < k.num_cells(); ++c) {  // the new cell at each point of each cell
    const std::int32_t first_b = next_b;
    for (std::int32_t p : in.cell_points[c]) {
      for (std::int32_t t = k.cell_offsets[c]; t < k.cell_offsets[c + 1]; ++t) {
        const std::int32_t f = k.cell_faces[static_cast<std::size_t>(t)];
        for (std::int32_t j = k.face_offsets[f]; j < k.face_offsets[f + 1]; ++j)
          if (k.face_points[static_cast<std::size_t>(j)] == p) out.cell_faces.push_back(j);
      }
      for (std::size_t i = 0; i < edges_of[c].size(); ++i) {
        const auto& e = k.edges[static_cast<std::size_t>(edges_of[c][i].first.edge)];
        if (e[0] == p || e[1] == p) out.cell_faces.push_back(first_b + static_cast<std::int32_t>(i));
      }
      out.cell_offsets.push_back(static_cast<std::int32_t>(out.cell_faces.size()));
    }
    next_b += static_cast<std::int32_t>(edges_of[c].size());
  }
  return out;
}

}  // namespace

CellComplex catmull_clark_step(const CellComplex& coarse, Eigen::SparseMatrix<double, Eigen::RowMajor>& stencil) {
  const Incidence in = incidence(coarse);
  const Triplets t = stencils(coarse, in);
  const int rows = coarse.num_points + static_cast<int>(coarse.edges.size() + coarse.num_faces() + coarse.num_cells());
  stencil.resize(rows, coarse.num_points);
  stencil.setFromTriplets(t.begin(), t.end());
  return refine_topology(coarse, in);
}

}  // namespace ffd
