// check_two_manifold (halfedge_view.h): plain arrays, no CGAL, so bcm can check without
// building a halfedge view.
#include <algorithm>
#include <unordered_map>

#include "common/errors.h"
#include "mesh/halfedge_view.h"

namespace ffd {
namespace {

// "face 12": the offending polygon, by its element index (the error's place gives its line).
std::string face_name(std::size_t e) { return "face " + std::to_string(e); }

// "face 12 (line 40)" or "face 12": another polygon the message names.
std::string face_name(const MeshElements& el, std::size_t e) {
  return face_name(e) + (el.line(e) ? " (line " + std::to_string(el.line(e)) + ")" : "");
}

// The error for element e, placed at its file line (or index) in `mesh`'s source.
[[noreturn]] void fail(const Mesh& mesh, std::size_t e, const std::string& what) {
  const std::string file = mesh.source().empty() ? "mesh" : mesh.source();
  throw TopologyError(At{element_place(file, mesh.elements(), e)},
                      what + "; this step needs an oriented 2-manifold mesh (boundaries are fine)");
}

// Degenerate: fewer than three corners, or a vertex twice.
void check_degenerate(const Mesh& mesh, std::size_t e, std::vector<std::uint32_t>& scratch) {
  const MeshElements& el = mesh.elements();
  if (el.degree(e) < 3)
    fail(mesh, e, "degenerate " + face_name(e) + ": it has " + std::to_string(el.degree(e)) + " vertices");
  scratch.assign(el.vertices(e), el.vertices(e) + el.degree(e));
  std::sort(scratch.begin(), scratch.end());
  const auto twice = std::adjacent_find(scratch.begin(), scratch.end());
  if (twice != scratch.end())
    fail(mesh, e, "degenerate " + face_name(e) + ": it uses vertex " + std::to_string(*twice) + " twice");
}

// True when polygons e and g have the same vertices (in any order).
bool same_vertices(const MeshElements& el, std::size_t e, std::size_t g) {
  if (el.degree(e) != el.degree(g)) return false;
  std::vector<std::uint32_t> a(el.vertices(e), el.vertices(e) + el.degree(e));
  std::vector<std::uint32_t> b(el.vertices(g), el.vertices(g) + el.degree(g));
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  return a == b;
}

// The faces on an undirected edge so far, and which way the first runs along it.
struct EdgeUse {
  std::uint32_t first = 0, second = 0;
  std::uint8_t count = 0;
  bool first_forward = false;  // the first face runs from the smaller vertex to the larger
};

// Edge checks for polygon e against the faces before it.
void check_edges(const Mesh& mesh, std::size_t e, std::unordered_map<std::uint64_t, EdgeUse>& uses) {
  const MeshElements& el = mesh.elements();
  const std::uint32_t* v = el.vertices(e);
  const std::uint32_t n = el.degree(e);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t a = v[i], b = v[(i + 1) % n];
    const bool forward = a < b;
    const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
    EdgeUse& use = uses[key];
    const std::string edge = std::to_string(a) + "–" + std::to_string(b);
    if (use.count == 0) {
      use = {static_cast<std::uint32_t>(e), 0, 1, forward};
      continue;
    }
    if (use.count >= 2)
      fail(mesh, e, "non-manifold edge " + edge + ": " + face_name(e) + " is its third face, after " +
                        face_name(el, use.first) + " and " + face_name(el, use.second));
    if (use.first_forward == forward) {
      if (same_vertices(el, e, use.first))
        fail(mesh, e, face_name(e) + " duplicates " + face_name(el, use.first));
      fail(mesh, e, face_name(e) + " is flipped against its neighbour " + face_name(el, use.first) +
                        ": both run " + std::to_string(a) + "→" + std::to_string(b));
    }
    use.second = static_cast<std::uint32_t>(e);
    use.count = 2;
  }
}

// A corner at a vertex: the vertices before and after it in its face.
struct Link {
  std::uint32_t prev, next, element;
};

// True when a vertex's corners chain into one fan. With every edge on at most two
// consistently oriented faces, each neighbour is some corner's `next` at most once and
// some corner's `prev` at most once, so the corners form paths and cycles
// (prev → next → the corner whose prev that is); one chain means one fan.
bool single_fan(std::vector<Link>::iterator first, std::vector<Link>::iterator last) {
  const auto k = static_cast<std::size_t>(last - first);
  std::vector<std::uint32_t> nexts;
  for (auto it = first; it != last; ++it) nexts.push_back(it->next);
  std::sort(nexts.begin(), nexts.end());
  std::sort(first, last, [](const Link& x, const Link& y) { return x.prev < y.prev; });
  auto start = first;  // a path's first corner (its prev is nobody's next), or any corner of a cycle
  for (auto it = first; it != last; ++it)
    if (!std::binary_search(nexts.begin(), nexts.end(), it->prev)) {
      start = it;
      break;
    }
  std::size_t reached = 1;
  for (auto at = start; reached <= k; ++reached) {
    const auto hit = std::lower_bound(first, last, at->next, [](const Link& x, std::uint32_t p) { return x.prev < p; });
    if (hit == last || hit->prev != at->next || hit == start) break;
    at = hit;
  }
  return reached == k;
}

// Non-manifold vertices: each vertex's corners must form one fan (single_fan).
void check_vertices(const Mesh& mesh) {
  const MeshElements& el = mesh.elements();
  const std::size_t nv = mesh.num_vertices();
  std::vector<std::uint32_t> start(nv + 1, 0);
  for (std::size_t e = 0; e < el.size(); ++e)
    if (el.kinds[e] == ElementKind::Polygon)
      for (std::uint32_t c = el.begin(e); c < el.end(e); ++c) ++start[el.corners[c] + 1];
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<Link> links(start[nv]);
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t e = 0; e < el.size(); ++e) {
    if (el.kinds[e] != ElementKind::Polygon) continue;
    const std::uint32_t* p = el.vertices(e);
    const std::uint32_t n = el.degree(e);
    for (std::uint32_t i = 0; i < n; ++i)
      links[fill[p[i]]++] = {p[(i + n - 1) % n], p[(i + 1) % n], static_cast<std::uint32_t>(e)};
  }
  for (std::size_t v = 0; v < nv; ++v) {
    const auto first = links.begin() + start[v], last = links.begin() + start[v + 1];
    if (last - first < 2 || single_fan(first, last)) continue;
    // Blame the last face to join the vertex: with it, the fans meet.
    const auto latest = std::max_element(first, last, [](const Link& x, const Link& y) { return x.element < y.element; });
    fail(mesh, latest->element, "non-manifold vertex " + std::to_string(v) + ": separate fans of faces meet there");
  }
}

}  // namespace

void check_two_manifold(const Mesh& mesh) {
  const MeshElements& el = mesh.elements();
  if (mesh.num_faces() == 0)
    throw TopologyError(At{mesh.source().empty() ? "mesh" : mesh.source()},
                        "the mesh has no faces (a point cloud); this step needs an oriented 2-manifold mesh");
  std::unordered_map<std::uint64_t, EdgeUse> uses;
  uses.reserve(el.corners.size());
  std::vector<std::uint32_t> scratch;
  for (std::size_t e = 0; e < el.size(); ++e) {
    if (el.kinds[e] != ElementKind::Polygon) continue;
    check_degenerate(mesh, e, scratch);
    check_edges(mesh, e, uses);
  }
  check_vertices(mesh);
}

}  // namespace ffd
