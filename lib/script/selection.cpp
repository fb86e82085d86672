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

PointIndex point_index_of(const SelectionPart::Entry& e) { return PointIndex{e.lattice, e.ijk, e.vertex}; }

const char* kLatticeIndexForVertex = "expected a vertex index, found a lattice index";
const char* kFileForPoints = "a selection file lists mesh vertices, not lattice points";
const char* kMarkerForPoints = "a marker names mesh nodes, not lattice points";

std::string point_not_movable(const std::string& text, const std::string& movable) {
  return "point " + text + " is not movable (movable: " + movable + ")";
}

// The cells of a grid level that subdivide can pick, for messages.
std::string kept_cells_text(int level, int resolution) {
  return "the kept cells of level " + std::to_string(level) + ", [i, j, k] in [0, " + std::to_string(resolution - 1) + "]";
}

std::string cell_not_kept(const std::string& text, const std::string& kept) { return "cell " + text + " is not one of " + kept; }

// Fails at the first index entry of `selection` that `problem` finds fault with, and at
// a file part unless `files` (a file lists vertices).
void check_entries(const Selection& selection, bool files,
                   const std::function<std::optional<std::string>(const SelectionPart::Entry&)>& problem) {
  for (const SelectionPart& part : selection.parts) {
    if (part.kind == SelectionPart::Kind::File && !files) throw InputError(At{part.place}, kFileForPoints);
    if (part.kind == SelectionPart::Kind::Marker && !files) throw InputError(At{part.place}, kMarkerForPoints);
    for (std::size_t i = 0; i < part.indices.size(); ++i)
      if (const std::optional<std::string> why = problem(part.indices[i])) throw InputError(At{index_place(part, i)}, *why);
  }
}

std::string out_of_range(long long v, std::size_t n) {
  return "vertex " + std::to_string(v) + " is out of range (the mesh has " + std::to_string(n) + " vertices)";
}

template <typename T>
void sort_unique(std::vector<T>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

// The nodes of the elements of `volume`'s marker `part.marker`, appended to `picked`.
void pick_marker(const SelectionPart& part, const VolumeSource* volume, std::vector<std::size_t>& picked) {
  if (!volume)
    throw InputError(At{part.place + "/marker"}, "a marker selects the nodes of a volume mesh's boundary marker or "
                                                 "physical group, and this mesh is not a volume mesh");
  std::string names;
  for (const VolumeMarker& marker : volume->markers) {
    names += (names.empty() ? "" : ", ") + marker.name;
    if (marker.name != part.marker) continue;
    for (const std::uint64_t c : marker.cells)
      picked.insert(picked.end(), volume->cells.nodes(c), volume->cells.nodes(c) + volume->cells.degree(c));
    return;
  }
  throw InputError(At{part.place + "/marker"}, "the mesh has no marker '" + part.marker + "' (" +
                                                   (names.empty() ? "it has none" : "it has " + names) + ")");
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
                                           const Eigen::Ref<const Eigen::Matrix3Xd>& positions,
                                           const VolumeSource* volume) {
  std::vector<std::size_t> picked;
  const std::size_t n = static_cast<std::size_t>(positions.cols());
  for (const SelectionPart& part : selection.parts) {
    if (part.kind == SelectionPart::Kind::Indices) {
      for (std::size_t i = 0; i < part.indices.size(); ++i) {
        const SelectionPart::Entry& e = part.indices[i];
        if (e.lattice) throw InputError(At{index_place(part, i)}, kLatticeIndexForVertex);
        if (e.vertex < 0 || static_cast<std::size_t>(e.vertex) >= n)
          throw InputError(At{index_place(part, i)}, out_of_range(e.vertex, n));
        picked.push_back(static_cast<std::size_t>(e.vertex));
      }
    } else if (part.kind == SelectionPart::Kind::File) {
      for (std::uint32_t v : part.file_vertices) {
        if (v >= n) throw InputError(At{part.file}, out_of_range(v, n));
        picked.push_back(v);
      }
    } else if (part.kind == SelectionPart::Kind::Marker) {
      pick_marker(part, volume, picked);
    } else {
      geometric_pick(part, positions, [](Eigen::Index) { return true; }, picked);
    }
  }
  sort_unique(picked);
  if (picked.empty()) throw InputError(At{selection.place}, "the selection picks no mesh vertex");
  return {picked.begin(), picked.end()};
}

namespace {

/// Control points a selection can pick: their positions, why an index has the wrong form
/// ([i, j, k] on grids, plain integers for scattered points), the flat index of an index
/// (none when out of range or not movable), which are movable, a text of which are, and
/// why an index names none of them.
struct PickablePoints {
  Eigen::Matrix3Xd points;
  std::function<std::optional<std::string>(const PointIndex&)> misformed;
  std::function<std::optional<std::size_t>(const PointIndex&)> flat;
  std::function<bool(std::size_t)> movable;
  std::string movable_text;
  std::function<std::string(const std::string&)> unknown;
};

std::vector<std::size_t> pick_points(const Selection& selection, const PickablePoints& pick) {
  std::vector<std::size_t> picked;
  for (const SelectionPart& part : selection.parts) {
    if (part.kind == SelectionPart::Kind::Indices) {
      for (std::size_t i = 0; i < part.indices.size(); ++i) {
        const SelectionPart::Entry& e = part.indices[i];
        if (const std::optional<std::string> why = pick.misformed(point_index_of(e)))
          throw InputError(At{index_place(part, i)}, *why);
        const std::optional<std::size_t> flat = pick.flat(point_index_of(e));
        if (!flat) throw InputError(At{index_place(part, i)}, pick.unknown(e.text));
        picked.push_back(*flat);
      }
    } else if (part.kind == SelectionPart::Kind::File) {
      throw InputError(At{part.place}, kFileForPoints);
    } else if (part.kind == SelectionPart::Kind::Marker) {
      throw InputError(At{part.place}, kMarkerForPoints);
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
  pick.misformed = [&](const PointIndex& index) -> std::optional<std::string> {
    if (index.grid == deformer.grid_indexed()) return std::nullopt;
    return deformer.missing_point(level, index);  // which says what form it expects
  };
  pick.flat = [&](const PointIndex& index) -> std::optional<std::size_t> {
    const std::optional<std::size_t> id = deformer.find_point(level, index);
    if (!id || !deformer.point_movable(level, *id)) return std::nullopt;
    return id;
  };
  pick.movable = [&](std::size_t id) { return deformer.point_movable(level, id); };
  pick.movable_text = deformer.movable_text(level);
  pick.unknown = [&](const std::string& text) { return point_not_movable(text, pick.movable_text); };
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
  pick.misformed = [](const PointIndex& index) { return index_form_problem(index, true, "cells"); };
  pick.movable = [](std::size_t) { return true; };
  pick.movable_text = kept_cells_text(level, g.resolution);
  pick.unknown = [&](const std::string& text) { return cell_not_kept(text, pick.movable_text); };
  return pick_points(selection, pick);
}

void check_point_selection(const Selection& selection, const DeformerShape& shape, int level) {
  check_entries(selection, false, [&](const SelectionPart::Entry& e) -> std::optional<std::string> {
    const PointIndex index = point_index_of(e);
    if (const std::optional<std::string> form = index_form_problem(index, shape.grid, shape.noun)) return form;
    if (const std::optional<std::string> movable = shape.unmovable(level, index)) return point_not_movable(e.text, *movable);
    return std::nullopt;
  });
}

void check_cell_selection(const Selection& selection, int level) {
  const int resolution = 1 << level;
  check_entries(selection, false, [&](const SelectionPart::Entry& e) -> std::optional<std::string> {
    if (const std::optional<std::string> form = index_form_problem(point_index_of(e), true, "cells")) return form;
    for (int a = 0; a < 3; ++a)
      if (e.ijk[a] < 0 || e.ijk[a] >= resolution) return cell_not_kept(e.text, kept_cells_text(level, resolution));
    return std::nullopt;
  });
}

void check_vertex_selection(const Selection& selection) {
  check_entries(selection, true, [](const SelectionPart::Entry& e) -> std::optional<std::string> {
    if (e.lattice) return std::string(kLatticeIndexForVertex);
    return std::nullopt;
  });
}

}  // namespace ffd
