#include "mesh/file_normals.h"

#include <algorithm>
#include <array>
#include <unordered_map>

namespace ffd {

namespace {

/// The distinct (entry, vertex) pairs of a mesh's corners, numbered in the order corners
/// first meet them. Most vertices meet one entry (smooth normals: one per vertex, or
/// shared), so the first entry met at a vertex is kept in flat arrays and only a vertex's
/// further entries go to a hash map (a std::map of every pair was 93% of writing a
/// 44k-vertex OBJ with one vn per vertex).
class CornerPairs {
public:
  explicit CornerPairs(std::size_t vertices) : first_entry_(vertices, -1), first_pair_(vertices, 0) {}
  /// The pair's number, a new one when the pair is new.
  std::size_t number(std::int32_t k, std::uint32_t v) {
    if (first_entry_[v] == k) return first_pair_[v];
    if (first_entry_[v] < 0) {
      first_entry_[v] = k, first_pair_[v] = pairs_.size();
      pairs_.push_back({k, v});
      return pairs_.size() - 1;
    }
    const auto [it, added] = more_.emplace(key(k, v), pairs_.size());
    if (added) pairs_.push_back({k, v});
    return it->second;
  }
  const std::vector<std::pair<std::int32_t, std::uint32_t>>& pairs() const { return pairs_; }

private:
  static std::uint64_t key(std::int32_t k, std::uint32_t v) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k)) << 32) | v;
  }
  std::vector<std::int32_t> first_entry_;
  std::vector<std::size_t> first_pair_;
  std::unordered_map<std::uint64_t, std::size_t> more_;
  std::vector<std::pair<std::int32_t, std::uint32_t>> pairs_;
};

/// transform(v, n) of every pair, in parallel: each is the stack's Jacobian at a vertex,
/// evaluated from rest space (the warps' point evaluation is safe on several threads).
std::vector<Eigen::Vector3d> transformed_pairs(const std::vector<std::pair<std::int32_t, std::uint32_t>>& pairs,
                                               const std::vector<Eigen::Vector3d>& file_normals,
                                               const NormalTransform& transform) {
  std::vector<Eigen::Vector3d> out(pairs.size());
  const auto n = static_cast<std::ptrdiff_t>(pairs.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const auto [k, v] = pairs[static_cast<std::size_t>(i)];
    out[static_cast<std::size_t>(i)] = transform ? transform(v, file_normals[static_cast<std::size_t>(k)])
                                                 : file_normals[static_cast<std::size_t>(k)];
  }
  return out;
}

/// Entry k's distinct results, in the order corners first meet them. A list longer than a
/// few (one vn shared by a curved region: every vertex bends it its own way) also gets a
/// hash of its values; a linear search made writing a 40k-vertex plane with one shared vn
/// take 0.6 s, and grows with the square of the vertices.
class EntryResults {
public:
  const std::vector<Eigen::Vector3d>& list() const { return list_; }
  /// The slot of a result equal to `n` (as `==` compares: -0 equals 0, NaN nothing), or a
  /// new one.
  std::size_t slot_of(const Eigen::Vector3d& n) {
    if (index_.empty()) {
      for (std::size_t slot = 0; slot < list_.size(); ++slot)
        if (list_[slot] == n) return slot;
      if (list_.size() < kScan) return append(n);
      for (std::size_t slot = 0; slot < list_.size(); ++slot) index_.emplace(key(list_[slot]), slot);
    }
    const auto [it, added] = index_.emplace(key(n), list_.size());  // a NaN equals no key: always added
    return added ? append(n) : it->second;
  }

private:
  static constexpr std::size_t kScan = 8;
  using Key = std::array<double, 3>;
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::size_t h = 0;
      for (const double x : k) h = h * 1000003u ^ std::hash<double>{}(x);  // std::hash<double>: -0 and 0 alike
      return h;
    }
  };
  static Key key(const Eigen::Vector3d& n) { return {n.x(), n.y(), n.z()}; }
  std::size_t append(const Eigen::Vector3d& n) {
    list_.push_back(n);
    return list_.size() - 1;
  }
  std::vector<Eigen::Vector3d> list_;
  std::unordered_map<Key, std::size_t, KeyHash> index_;
};

/// Every entry's distinct results, in the order the pairs meet them. An entry's first
/// result is one index in a flat array (most entries have one: a vn per vertex, or one
/// vn over a flat region); an entry with more gets an EntryResults of its own. (An
/// EntryResults per entry spent a third of writing a 1M-vertex OBJ with one vn per
/// vertex allocating, clearing and freeing them.)
class TableResults {
public:
  TableResults(std::size_t entries, const std::vector<Eigen::Vector3d>& moved) : first_(entries, -1), moved_(moved) {}
  /// The slot of pair i's result among entry k's.
  std::size_t slot_of(std::int32_t k, std::size_t i) {
    std::int64_t& first = first_[static_cast<std::size_t>(k)];
    if (first < 0) {
      first = static_cast<std::int64_t>(i);
      return 0;
    }
    auto it = more_.find(k);
    if (it == more_.end()) {
      if (moved_[static_cast<std::size_t>(first)] == moved_[i]) return 0;
      it = more_.emplace(k, EntryResults()).first;
      it->second.slot_of(moved_[static_cast<std::size_t>(first)]);
    }
    return it->second.slot_of(moved_[i]);
  }
  /// Appends entry k's results to `table` (its file normal, `rest`, when no pair has it).
  void append(std::int32_t k, const Eigen::Vector3d& rest, std::vector<Eigen::Vector3d>& table) const {
    const std::int64_t first = first_[static_cast<std::size_t>(k)];
    const auto it = first < 0 ? more_.end() : more_.find(k);
    if (it != more_.end())
      table.insert(table.end(), it->second.list().begin(), it->second.list().end());
    else
      table.push_back(first < 0 ? rest : moved_[static_cast<std::size_t>(first)]);
  }

private:
  std::vector<std::int64_t> first_;  // per entry: the pair whose result is its slot 0, -1 none yet
  std::unordered_map<std::int32_t, EntryResults> more_;
  const std::vector<Eigen::Vector3d>& moved_;
};

/// Whether the file normals are one per vertex, entry v at vertex v (PLY, NOFF).
bool one_per_vertex(const Mesh& mesh) {
  return (mesh.file_normals_per_vertex || mesh.ply_source_as_read()) && mesh.file_normals().size() == mesh.num_vertices();
}

}  // namespace

CornerNormals transformed_file_normals(const Mesh& mesh, const NormalTransform& transform) {
  const MeshElements& el = mesh.elements();
  const std::vector<Eigen::Vector3d>& file_normals = mesh.file_normals();
  CornerNormals result;
  if (!mesh.has_file_normals() || el.corner_normals.empty()) {
    result.table = file_normals;  // no corner has one: `corner` stays empty
    return result;
  }
  // The pairs first (each corner's pair number in `corner` for now), then their
  // transforms, then each pair's slot among its entry's results in pair order: the order
  // corners first meet them, as one pass would give.
  CornerPairs memo(mesh.num_vertices());
  result.corner.assign(el.corners.size(), -1);
  for (std::size_t c = 0; c < el.corners.size(); ++c)
    if (el.corner_normals[c] >= 0)
      result.corner[c] = static_cast<std::int64_t>(memo.number(el.corner_normals[c], el.corners[c]));
  const std::vector<std::pair<std::int32_t, std::uint32_t>>& pairs = memo.pairs();
  const std::vector<Eigen::Vector3d> moved = transformed_pairs(pairs, file_normals, transform);
  TableResults values(file_normals.size(), moved);
  std::vector<std::size_t> slot(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) slot[i] = values.slot_of(pairs[i].first, i);
  std::vector<std::size_t> first(file_normals.size(), 0);
  for (std::size_t k = 0; k < file_normals.size(); ++k) {
    first[k] = result.table.size();
    values.append(static_cast<std::int32_t>(k), file_normals[k], result.table);
  }
  for (std::int64_t& c : result.corner) {
    if (c < 0) continue;
    const auto i = static_cast<std::size_t>(c);
    c = static_cast<std::int64_t>(first[static_cast<std::size_t>(pairs[i].first)] + slot[i]);
  }
  return result;
}

void bake_file_normals(Mesh& mesh, const NormalTransform& transform) {
  if (!mesh.has_file_normals()) return;
  CornerNormals baked = transformed_file_normals(mesh, transform);
  mesh.file_normals() = std::move(baked.table);
  mesh.file_normal_count = mesh.file_normals().size();
  std::vector<std::int32_t>& corner = mesh.corner_data().corner_normals;
  if (corner.empty()) return;
  for (std::size_t c = 0; c < corner.size(); ++c) corner[c] = static_cast<std::int32_t>(baked.corner[c]);
}

VertexFileNormals vertex_file_normals(const Mesh& mesh, const NormalTransform& transform) {
  const MeshElements& el = mesh.elements();
  VertexFileNormals out;
  out.value.assign(mesh.num_vertices(), Eigen::Vector3d::Zero());
  out.has.assign(mesh.num_vertices(), 0);
  out.moved.assign(mesh.num_vertices(), 0);
  const auto take = [&](std::uint32_t v, const Eigen::Vector3d& n) {
    out.value[v] = n;  // in rest space until transformed below
    out.has[v] = 1;
  };
  for (std::size_t c = 0; c < el.corners.size() && !el.corner_normals.empty(); ++c) {
    const std::uint32_t v = el.corners[c];
    if (!out.has[v] && el.corner_normals[c] >= 0) take(v, mesh.file_normals()[el.corner_normals[c]]);
  }
  // A PLY's or NOFF's normals are one per vertex (their readers make the table so): a
  // vertex in no element, a point of a cloud, has its own too.
  if (one_per_vertex(mesh))
    for (std::uint32_t v = 0; v < out.has.size(); ++v)
      if (!out.has[v]) take(v, mesh.file_normals()[v]);
  if (!transform) return out;
  const auto n = static_cast<std::ptrdiff_t>(out.value.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {  // in parallel, as transformed_pairs
    const auto v = static_cast<std::uint32_t>(i);
    if (!out.has[v]) continue;
    const Eigen::Vector3d rest = out.value[v];
    out.value[v] = transform(v, rest);
    out.moved[v] = out.value[v] != rest;
  }
  return out;
}

bool every_vertex_has_file_normal(const Mesh& mesh) {
  if (!mesh.has_file_normals()) return false;
  if (one_per_vertex(mesh)) return true;  // vertex_file_normals takes each vertex's own
  const MeshElements& el = mesh.elements();
  if (el.corner_normals.empty()) return false;
  std::vector<char> has(mesh.num_vertices(), 0);
  for (std::size_t c = 0; c < el.corners.size(); ++c)
    if (el.corner_normals[c] >= 0) has[el.corners[c]] = 1;
  return std::all_of(has.begin(), has.end(), [](char h) { return h != 0; });
}

}  // namespace ffd
