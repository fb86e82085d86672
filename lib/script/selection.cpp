#include "script/selection.h"

#include <algorithm>
#include <fstream>
#include <limits>
#include <sstream>

#include "common/errors.h"
#include "common/numbers.h"
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
  std::ifstream is(path, std::ios::binary);
  if (!is) throw InputError(path + ": cannot read the selection file");
  std::stringstream ss;
  ss << is.rdbuf();
  const std::string text = ss.str();
  LineScanner lines(text);
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

std::vector<std::size_t> select_lattice_points(const Selection& selection, const Lattice& lattice) {
  std::vector<std::size_t> picked;
  Eigen::Matrix3Xd points(3, static_cast<Eigen::Index>(lattice.num_points()));
  std::vector<bool> movable(lattice.num_points());
  for (std::size_t f = 0; f < lattice.num_points(); ++f) {
    const Index3 ijk = lattice.index(f);
    points.col(static_cast<Eigen::Index>(f)) = lattice.point(ijk);
    movable[f] = lattice.movable(ijk);
  }
  for (const SelectionPart& part : selection.parts) {
    if (part.kind == SelectionPart::Kind::Indices) {
      for (std::size_t i = 0; i < part.indices.size(); ++i) {
        const SelectionPart::Entry& e = part.indices[i];
        if (!e.lattice) throw InputError(At{index_place(part, i)}, "expected a lattice index [i, j, k]");
        if (!lattice.in_range(e.ijk) || !lattice.movable(e.ijk))
          throw InputError(At{index_place(part, i)},
                           "point " + e.text + " is not movable (movable: " + lattice.movable_range() + ")");
        picked.push_back(lattice.flat(e.ijk));
      }
    } else if (part.kind == SelectionPart::Kind::File) {
      throw InputError(At{part.place}, "a selection file lists mesh vertices, not lattice points");
    } else {
      geometric_pick(part, points, [&](Eigen::Index i) { return movable[static_cast<std::size_t>(i)]; }, picked);
    }
  }
  sort_unique(picked);
  if (picked.empty())
    throw InputError(At{selection.place},
                     "the selection picks no movable lattice point (movable: " + lattice.movable_range() + ")");
  return picked;
}

}  // namespace ffd
