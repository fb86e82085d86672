#include "multires/cell_complex.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace ffd {

std::vector<std::int32_t> CellComplex::cell_points(std::size_t c) const {
  std::vector<std::int32_t> out;
  for (std::int32_t i = cell_offsets[c]; i < cell_offsets[c + 1]; ++i) {
    const std::int32_t f = cell_faces[static_cast<std::size_t>(i)];
    for (std::int32_t j = face_offsets[f]; j < face_offsets[f + 1]; ++j) {
      const std::int32_t p = face_points[static_cast<std::size_t>(j)];
      if (std::find(out.begin(), out.end(), p) == out.end()) out.push_back(p);
    }
  }
  return out;
}

std::size_t CellComplex::bytes() const {
  return edges.capacity() * sizeof(edges[0]) +
         (face_offsets.capacity() + face_points.capacity() + face_edges.capacity() + cell_offsets.capacity() +
          cell_faces.capacity()) *
             sizeof(std::int32_t);
}

namespace {

std::uint64_t node_key(const GridIndex& n) {
  return static_cast<std::uint64_t>(n[0]) | static_cast<std::uint64_t>(n[1]) << 21 |
         static_cast<std::uint64_t>(n[2]) << 42;
}

/// Builds a CellComplex face by face, sharing faces by key and edges by their points.
struct ComplexBuilder {
  CellComplex& out;
  std::unordered_map<std::uint64_t, std::int32_t> edge_of;
  std::map<std::array<int, 5>, std::int32_t> face_of;

  std::int32_t edge(std::int32_t a, std::int32_t b) {
    const std::uint64_t key = static_cast<std::uint64_t>(std::min(a, b)) << 32 | static_cast<std::uint32_t>(std::max(a, b));
    auto [it, fresh] = edge_of.emplace(key, static_cast<std::int32_t>(out.edges.size()));
    if (fresh) out.edges.push_back({a, b});
    return it->second;
  }
  std::int32_t face(const std::array<int, 5>& key, const std::vector<std::int32_t>& loop) {
    auto [it, fresh] = face_of.emplace(key, static_cast<std::int32_t>(out.num_faces()));
    if (!fresh) return it->second;
    for (std::size_t i = 0; i < loop.size(); ++i) {
      out.face_points.push_back(loop[i]);
      out.face_edges.push_back(edge(loop[i], loop[(i + 1) % loop.size()]));
    }
    out.face_offsets.push_back(static_cast<std::int32_t>(out.face_points.size()));
    return it->second;
  }
};

GridIndex step(GridIndex n, int axis, int by) {
  n[axis] += by;
  return n;
}

}  // namespace

CellComplex locally_subdivided(const GridComplex& grid, const std::vector<std::uint8_t>& subdivide,
                               std::vector<GridIndex>& nodes) {
  struct Box {
    GridIndex lo;
    int size;
  };
  std::vector<Box> boxes;
  for (std::size_t c = 0; c < grid.num_cells(); ++c) {
    const GridIndex g{2 * grid.cells[c][0], 2 * grid.cells[c][1], 2 * grid.cells[c][2]};
    if (!subdivide[c]) boxes.push_back({g, 2});
    else
      for (int d = 0; d < 8; ++d) boxes.push_back({{g[0] + (d & 1), g[1] + ((d >> 1) & 1), g[2] + ((d >> 2) & 1)}, 1});
  }
  nodes.clear();
  for (const Box& b : boxes)
    for (int d = 0; d < 8; ++d)
      nodes.push_back({b.lo[0] + b.size * (d & 1), b.lo[1] + b.size * ((d >> 1) & 1), b.lo[2] + b.size * ((d >> 2) & 1)});
  std::sort(nodes.begin(), nodes.end(), [](const GridIndex& a, const GridIndex& b) { return node_key(a) < node_key(b); });
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  std::unordered_map<std::uint64_t, std::int32_t> point_of;
  for (std::size_t p = 0; p < nodes.size(); ++p) point_of[node_key(nodes[p])] = static_cast<std::int32_t>(p);
  auto point = [&](const GridIndex& n) {
    auto it = point_of.find(node_key(n));
    return it == point_of.end() ? -1 : it->second;
  };

  CellComplex out;
  out.num_points = static_cast<std::int32_t>(nodes.size());
  ComplexBuilder builder{out, {}, {}};
  auto unit_face = [&](const GridIndex& m, int axis, int u, int v) {
    return builder.face({m[0], m[1], m[2], axis, 1},
                        {point(m), point(step(m, u, 1)), point(step(step(m, u, 1), v, 1)), point(step(m, v, 1))});
  };
  for (const Box& b : boxes) {
    for (int axis = 0; axis < 3; ++axis)
      for (int side = 0; side < 2; ++side) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        const GridIndex m = step(b.lo, axis, side * b.size);
        if (b.size == 1) {
          out.cell_faces.push_back(unit_face(m, axis, u, v));
        } else if (point(step(step(m, u, 1), v, 1)) >= 0) {  // split by a subdivided neighbour
          for (int k = 0; k < 4; ++k) out.cell_faces.push_back(unit_face(step(step(m, u, k & 1), v, k >> 1), axis, u, v));
        } else {
          const int ring[8][2] = {{0, 0}, {1, 0}, {2, 0}, {2, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}};
          std::vector<std::int32_t> loop;
          for (const auto& r : ring) {
            const std::int32_t p = point(step(step(m, u, r[0]), v, r[1]));
            if (p >= 0) loop.push_back(p);
          }
          out.cell_faces.push_back(builder.face({m[0], m[1], m[2], axis, 2}, loop));
        }
      }
    out.cell_offsets.push_back(static_cast<std::int32_t>(out.cell_faces.size()));
  }
  return out;
}

std::string lattice_defect(const CellComplex& complex) {
  std::vector<int> cells_of_face(complex.num_faces(), 0);
  for (std::int32_t f : complex.cell_faces) ++cells_of_face[static_cast<std::size_t>(f)];
  for (std::size_t f = 0; f < cells_of_face.size(); ++f)
    if (cells_of_face[f] > 2) return "face " + std::to_string(f) + " is in " + std::to_string(cells_of_face[f]) + " cells";
  for (std::size_t c = 0; c < complex.num_cells(); ++c) {
    std::map<std::int32_t, int> uses;
    for (std::int32_t i = complex.cell_offsets[c]; i < complex.cell_offsets[c + 1]; ++i) {
      const std::int32_t f = complex.cell_faces[static_cast<std::size_t>(i)];
      for (std::int32_t j = complex.face_offsets[f]; j < complex.face_offsets[f + 1]; ++j)
        ++uses[complex.face_edges[static_cast<std::size_t>(j)]];
    }
    for (const auto& [e, n] : uses)
      if (n != 2) return "cell " + std::to_string(c) + " is not closed: its edge " + std::to_string(e) + " is in " +
                         std::to_string(n) + " of its faces";
  }
  return {};
}

}  // namespace ffd
