#include "script/selection.h"

#include <algorithm>
#include <fstream>
#include <limits>
#include <sstream>

#include "common/errors.h"
#include "common/numbers.h"
#include "mesh/text_lines.h"
#include "script/transform.h"

namespace ffd {
namespace {

using json = nlohmann::json;

std::string where_text(const SelectionContext& w, const std::string& suffix = "") {
  return w.script + ": " + w.path + suffix;
}

template <typename Fn>
void for_each_part(const json& selection, const SelectionContext& where, Fn fn) {
  if (selection.is_array()) {
    for (std::size_t i = 0; i < selection.size(); ++i) {
      SelectionContext part = where;
      part.path += "/" + std::to_string(i);
      fn(selection[i], part);
    }
  } else {
    fn(selection, where);
  }
}

// Indices of the columns of `points` (restricted to `allowed` when non-null) inside the
// geometric part; `near` picks the single nearest (ties: lowest index).
template <typename Allowed>
void geometric_pick(const json& part, const Eigen::Ref<const Eigen::Matrix3Xd>& points, Allowed allowed,
                    std::vector<std::size_t>& out) {
  if (part.contains("sphere")) {
    const Eigen::Vector3d c = parse_vec3(part["sphere"]["center"]);
    const double r2 = std::pow(part["sphere"]["radius"].get<double>(), 2);
    for (Eigen::Index i = 0; i < points.cols(); ++i)
      if (allowed(i) && (points.col(i) - c).squaredNorm() <= r2) out.push_back(i);
  } else if (part.contains("box")) {
    const Eigen::Vector3d lo = parse_vec3(part["box"]["min"]), hi = parse_vec3(part["box"]["max"]);
    for (Eigen::Index i = 0; i < points.cols(); ++i)
      if (allowed(i) && (points.col(i).array() >= lo.array()).all() &&
          (points.col(i).array() <= hi.array()).all())
        out.push_back(i);
  } else if (part.contains("near")) {
    const Eigen::Vector3d q = parse_vec3(part["near"]);
    double best = std::numeric_limits<double>::infinity();
    Eigen::Index best_i = -1;
    for (Eigen::Index i = 0; i < points.cols(); ++i) {
      if (!allowed(i)) continue;
      const double d = (points.col(i) - q).squaredNorm();
      if (d < best) {
        best = d;
        best_i = i;
      }
    }
    if (best_i >= 0) out.push_back(best_i);
  }
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

std::vector<std::uint32_t> select_vertices(const json& selection,
                                           const Eigen::Ref<const Eigen::Matrix3Xd>& positions,
                                           const SelectionContext& where) {
  std::vector<std::size_t> picked;
  const std::size_t n = static_cast<std::size_t>(positions.cols());
  for_each_part(selection, where, [&](const json& part, const SelectionContext& w) {
    if (part.contains("indices")) {
      const json& list = part["indices"];
      for (std::size_t i = 0; i < list.size(); ++i) {
        if (!list[i].is_number_integer())
          throw InputError(where_text(w, "/indices/" + std::to_string(i)) +
                           ": expected a vertex index, found a lattice index");
        const auto v = list[i].get<long long>();
        if (v < 0 || static_cast<std::size_t>(v) >= n)
          throw InputError(where_text(w, "/indices/" + std::to_string(i)) + ": vertex " + std::to_string(v) +
                           " is out of range (the mesh has " + std::to_string(n) + " vertices)");
        picked.push_back(static_cast<std::size_t>(v));
      }
    } else if (part.contains("file")) {
      std::string file = part["file"].get<std::string>();
      if (!file.empty() && file[0] != '/' && !w.folder.empty()) file = w.folder + "/" + file;
      for (std::uint32_t v : read_index_file(file)) {
        if (v >= n)
          throw InputError(file + ": vertex " + std::to_string(v) + " is out of range (the mesh has " +
                           std::to_string(n) + " vertices)");
        picked.push_back(v);
      }
    } else {
      geometric_pick(part, positions, [](Eigen::Index) { return true; }, picked);
    }
  });
  std::sort(picked.begin(), picked.end());
  picked.erase(std::unique(picked.begin(), picked.end()), picked.end());
  if (picked.empty()) throw InputError(where_text(where) + ": the selection picks no mesh vertex");
  return {picked.begin(), picked.end()};
}

std::vector<std::size_t> select_lattice_points(const json& selection, const Lattice& lattice,
                                               const SelectionContext& where) {
  std::vector<std::size_t> picked;
  Eigen::Matrix3Xd points(3, static_cast<Eigen::Index>(lattice.num_points()));
  std::vector<bool> movable(lattice.num_points());
  for (std::size_t f = 0; f < lattice.num_points(); ++f) {
    const Index3 ijk = lattice.index(f);
    points.col(static_cast<Eigen::Index>(f)) = lattice.point(ijk);
    movable[f] = lattice.movable(ijk);
  }
  for_each_part(selection, where, [&](const json& part, const SelectionContext& w) {
    if (part.contains("indices")) {
      const json& list = part["indices"];
      for (std::size_t i = 0; i < list.size(); ++i) {
        const std::string at = where_text(w, "/indices/" + std::to_string(i));
        if (!list[i].is_array()) throw InputError(at + ": expected a lattice index [i, j, k]");
        const Index3 ijk{list[i][0].get<int>(), list[i][1].get<int>(), list[i][2].get<int>()};
        if (!lattice.in_range(ijk) || !lattice.movable(ijk))
          throw InputError(at + ": point " + list[i].dump() + " is not movable (movable: " +
                           lattice.movable_range() + ")");
        picked.push_back(lattice.flat(ijk));
      }
    } else if (part.contains("file")) {
      throw InputError(where_text(w) + ": a selection file lists mesh vertices, not lattice points");
    } else {
      geometric_pick(part, points, [&](Eigen::Index i) { return movable[static_cast<std::size_t>(i)]; }, picked);
    }
  });
  std::sort(picked.begin(), picked.end());
  picked.erase(std::unique(picked.begin(), picked.end()), picked.end());
  if (picked.empty())
    throw InputError(where_text(where) + ": the selection picks no movable lattice point (movable: " +
                     lattice.movable_range() + ")");
  return picked;
}

}  // namespace ffd
