#include "script/selection.h"

#include <algorithm>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>

#include "common/errors.h"
#include "common/numbers.h"
#include "common/text_file.h"
#include "mesh/text_lines.h"

namespace ffd {
namespace {

// Indices of the columns of `points` (restricted to `allowed`) inside a geometric part;
// `near` picks the single nearest (ties: lowest index).
template <typename Allowed>
void geometric_pick(const SelectionPart& part, const Eigen::Ref<const Eigen::Matrix3Xd>& points, Allowed allowed,
                    std::vector<std::size_t>& out) {
  using Kind = SelectionPart::Kind;
  if (part.kind == Kind::Sphere) {
    const double r2 = part.radius * part.radius;
    for (Eigen::Index i = 0; i < points.cols(); ++i)
      if (allowed(i) && (points.col(i) - part.center).squaredNorm() <= r2) out.push_back(i);
  } else if (part.kind == Kind::Box) {
    for (Eigen::Index i = 0; i < points.cols(); ++i)
      if (allowed(i) && (points.col(i).array() >= part.min.array()).all() &&
          (points.col(i).array() <= part.max.array()).all())
        out.push_back(i);
  } else if (part.kind == Kind::Near) {
    double best = std::numeric_limits<double>::infinity();
    Eigen::Index best_i = -1;
    for (Eigen::Index i = 0; i < points.cols(); ++i) {
      if (!allowed(i)) continue;
      const double d = (points.col(i) - part.center).squaredNorm();
      if (d < best) {
        best = d;
        best_i = i;
      }
    }
    if (best_i >= 0) out.push_back(best_i);
  }
}

std::string index_place(const SelectionPart& part, std::size_t i) {
  return part.place + "/indices/" + std::to_string(i);
}

std::string out_of_range(long long v, std::size_t n) {
  return "vertex " + std::to_string(v) + " is out of range (the mesh has " + std::to_string(n) + " vertices)";
}

template <typename T>
void sort_unique(std::vector<T>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

}  // namespace

std::vector<std::uint32_t> read_index_file(const std::string& path) {
  const std::optional<std::string> text = read_text_file(path);
  if (!text) throw InputError(path + ": cannot read the selection file");
  LineScanner lines(*text);
  std::string_view line;
  std::vector<std::string_view> tokens;
  std::vector<std::uint32_t> out;
  while (lines.next(line)) {
    split_tokens(line, tokens);
    if (tokens.empty()) continue;
    long long v;
    if (tokens.size() != 1 || !parse_integer(tokens[0], v) || v < 0 || v > UINT32_MAX)
      throw InputError(place(path, lines.number()) + ": expected one vertex index (a non-negative integer)");
    out.push_back(static_cast<std::uint32_t>(v));
  }
  return out;
}

std::vector<std::uint32_t> select_vertices(const Selection& selection,
                                           const Eigen::Ref<const Eigen::Matrix3Xd>& positions) {
  std::vector<std::size_t> picked;
  const std::size_t n = static_cast<std::size_t>(positions.cols());
  for (const SelectionPart& part : selection.parts) {
    if (part.kind == SelectionPart::Kind::Indices) {
      for (std::size_t i = 0; i < part.indices.size(); ++i) {
        const SelectionPart::Entry& e = part.indices[i];
        if (e.lattice) throw InputError(At{index_place(part, i)}, "expected a vertex index, found a lattice index");
        if (e.vertex < 0 || static_cast<std::size_t>(e.vertex) >= n)
          throw InputError(At{index_place(part, i)}, out_of_range(e.vertex, n));
        picked.push_back(static_cast<std::size_t>(e.vertex));
      }
    } else if (part.kind == SelectionPart::Kind::File) {
      for (std::uint32_t v : part.file_vertices) {
        if (v >= n) throw InputError(At{part.file}, out_of_range(v, n));
        picked.push_back(v);
      }
    } else {
      geometric_pick(part, positions, [](Eigen::Index) { return true; }, picked);
    }
  }
  sort_unique(picked);
  if (picked.empty()) throw InputError(At{selection.place}, "the selection picks no mesh vertex");
  return {picked.begin(), picked.end()};
}

namespace {

/// Control points a selection can pick: their positions, the flat index of a grid index
/// (none when out of range or not movable), which are movable, and a text of which are.
/// Entries are points' script indices: [i, j, k] on grids, plain integers for scattered
/// points (`grid` false).
struct PickablePoints {
  Eigen::Matrix3Xd points;
  bool grid = true;
  std::function<std::optional<std::size_t>(const PointIndex&)> flat;
  std::function<bool(std::size_t)> movable;
  std::string movable_text;
};

std::vector<std::size_t> pick_points(const Selection& selection, const PickablePoints& pick) {
  std::vector<std::size_t> picked;
  for (const SelectionPart& part : selection.parts) {
    if (part.kind == SelectionPart::Kind::Indices) {
      for (std::size_t i = 0; i < part.indices.size(); ++i) {
        const SelectionPart::Entry& e = part.indices[i];
        if (pick.grid && !e.lattice) throw InputError(At{index_place(part, i)}, "expected a lattice index [i, j, k]");
        const std::optional<std::size_t> flat = pick.flat(PointIndex{e.lattice, e.ijk, e.vertex});
        if (!flat)
          throw InputError(At{index_place(part, i)}, "point " + e.text + " is not movable (movable: " + pick.movable_text + ")");
        picked.push_back(*flat);
      }
    } else if (part.kind == SelectionPart::Kind::File) {
      throw InputError(At{part.place}, "a selection file lists mesh vertices, not lattice points");
    } else {
      geometric_pick(part, pick.points, [&](Eigen::Index i) { return pick.movable(static_cast<std::size_t>(i)); }, picked);
    }
  }
  sort_unique(picked);
  if (picked.empty())
    throw InputError(At{selection.place}, "the selection picks no movable lattice point (movable: " + pick.movable_text + ")");
  return picked;
}

}  // namespace

std::vector<std::size_t> select_points(const Selection& selection, const Deformer& deformer, int level) {
  PickablePoints pick;
  pick.points = deformer.points(level);
  pick.grid = deformer.grid_indexed();
  pick.flat = [&](const PointIndex& index) -> std::optional<std::size_t> {
    const std::optional<std::size_t> id = deformer.find_point(level, index);
    if (!id || !deformer.point_movable(level, *id)) return std::nullopt;
    return id;
  };
  pick.movable = [&](std::size_t id) { return deformer.point_movable(level, id); };
  pick.movable_text = deformer.movable_text(level);
  return pick_points(selection, pick);
}

std::vector<std::size_t> select_octree_cells(const Selection& selection, const OctreeLattice& lattice, int level) {
  const GridComplex& g = lattice.complex(level);
  const Eigen::Matrix3Xd shown = lattice.points(level);
  PickablePoints pick;
  pick.points = Eigen::Matrix3Xd::Zero(3, static_cast<Eigen::Index>(g.num_cells()));
  for (std::size_t c = 0; c < g.num_cells(); ++c)
    for (int k = 0; k < 8; ++k) pick.points.col(static_cast<Eigen::Index>(c)) += shown.col(g.corner(c, k)) / 8;
  pick.flat = [&](const PointIndex& index) -> std::optional<std::size_t> {
    const std::int32_t c = g.cell(index.ijk[0], index.ijk[1], index.ijk[2]);
    if (c < 0) return std::nullopt;
    return static_cast<std::size_t>(c);
  };
  pick.movable = [](std::size_t) { return true; };
  pick.movable_text = "the kept cells of level " + std::to_string(level) + ", [i, j, k] in [0, " +
                      std::to_string(g.resolution - 1) + "]";
  return pick_points(selection, pick);
}

}  // namespace ffd
