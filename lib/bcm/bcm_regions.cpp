#include "bcm/bcm_regions.h"

#include <algorithm>

#include "common/errors.h"
#include "bcm/bcm_options.h"
#include "common/numbers.h"

namespace ffd {

VertexAdjacency vertex_adjacency(const Mesh& mesh) {
  const std::size_t n = mesh.num_vertices();
  // Each face edge (a, b) lists b under a and a under b; an interior edge comes twice
  // (once per face), removed after sorting each short row.
  std::vector<std::uint32_t> faces, sizes;
  faces.reserve(mesh.num_faces() * 3);
  std::vector<std::uint32_t> ids;
  std::vector<std::uint32_t> count(n + 1, 0);
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    mesh.face_vertices(f, ids);
    sizes.push_back(static_cast<std::uint32_t>(ids.size()));
    for (std::uint32_t v : ids) {
      faces.push_back(v);
      count[v + 1] += 2;
    }
  }
  for (std::size_t v = 0; v < n; ++v) count[v + 1] += count[v];
  std::vector<std::uint32_t> slots(count.back()), fill(count.begin(), count.end() - 1);
  std::size_t at = 0;
  for (std::uint32_t size : sizes) {
    for (std::uint32_t i = 0; i < size; ++i) {
      const std::uint32_t a = faces[at + i], b = faces[at + (i + 1) % size];
      slots[fill[a]++] = b;
      slots[fill[b]++] = a;
    }
    at += size;
  }
  VertexAdjacency adjacency;
  adjacency.offsets.assign(n + 1, 0);
  adjacency.neighbors.reserve(slots.size() / 2 + n);
  for (std::size_t v = 0; v < n; ++v) {
    auto first = slots.begin() + count[v], last = slots.begin() + count[v + 1];
    std::sort(first, last);
    adjacency.neighbors.insert(adjacency.neighbors.end(), first, std::unique(first, last));
    adjacency.offsets[v + 1] = static_cast<std::uint32_t>(adjacency.neighbors.size());
  }
  return adjacency;
}

BcmRegions bcm_regions(const std::vector<std::uint32_t>& support, const std::vector<std::vector<std::uint32_t>>& handles) {
  BcmRegions regions;
  std::vector<std::uint32_t> taken;  // union of the handles so far, ascending
  for (std::size_t h = 0; h < handles.size(); ++h) {
    const std::vector<std::uint32_t>& handle = handles[h];
    std::vector<std::uint32_t> outside;
    std::set_difference(handle.begin(), handle.end(), support.begin(), support.end(), std::back_inserter(outside));
    if (!outside.empty())
      throw InputError(format_count(outside.size()) + " of the handle's " + format_count(handle.size()) +
                           " vertices lie outside the support (first: vertex " + std::to_string(outside[0]) +
                           "); a handle must be inside its support",
                       {"handles", h});
    std::vector<std::uint32_t> shared;
    std::set_intersection(handle.begin(), handle.end(), taken.begin(), taken.end(), std::back_inserter(shared));
    if (!shared.empty())
      throw InputError("the handle shares " + format_count(shared.size()) + " vertices with an earlier handle (first: vertex " +
                           std::to_string(shared[0]) + "); handles must not overlap",
                       {"handles", h});
    std::vector<std::uint32_t> merged;
    std::merge(taken.begin(), taken.end(), handle.begin(), handle.end(), std::back_inserter(merged));
    taken.swap(merged);
    regions.handles.push_back(handle);
  }
  std::set_difference(support.begin(), support.end(), taken.begin(), taken.end(), std::back_inserter(regions.free));
  if (regions.free.empty())
    throw InputError("the handles cover the whole support (" + format_count(support.size()) +
                         " vertices): no vertex is left free to bend",
                     {"support"});
  return regions;
}

// Each connected part of the free vertices (ring 0) must touch a constrained vertex;
// otherwise Δ^k has no boundary condition there and the system is singular.
// \throw InputError about "support" naming the part's size and first vertex.
static void require_anchored(const BcmRegions& regions, const VertexAdjacency& adjacency, const std::vector<int>& ring) {
  std::vector<char> visited(ring.size(), 0);
  std::vector<std::uint32_t> queue;
  for (std::uint32_t seed : regions.free) {
    if (visited[seed]) continue;
    queue.assign(1, seed);
    visited[seed] = 1;
    bool anchored = false;
    for (std::size_t q = 0; q < queue.size(); ++q)
      for (const std::uint32_t* u = adjacency.begin(queue[q]); u != adjacency.end(queue[q]); ++u) {
        if (ring[*u] != 0) {
          anchored = true;
        } else if (!visited[*u]) {
          visited[*u] = 1;
          queue.push_back(*u);
        }
      }
    if (!anchored)
      throw InputError("a part of the support (" + format_count(queue.size()) + " free vertices, first: vertex " +
                           std::to_string(seed) +
                           ") touches no fixed or handle vertex, so nothing holds it (singular "
                           "system); put a handle in it or leave some of its surroundings fixed",
                       {"support"});
  }
}

BcmStencil bcm_stencil(const Mesh& mesh, const VertexAdjacency& adjacency, const BcmRegions& regions, int k) {
  const std::size_t n = mesh.num_vertices();
  constexpr int kFar = 1 << 20;
  std::vector<int> ring(n, kFar);
  std::vector<int> handle_of(n, -1);
  for (std::size_t h = 0; h < regions.handles.size(); ++h)
    for (std::uint32_t v : regions.handles[h]) handle_of[v] = static_cast<int>(h);

  for (std::uint32_t v : regions.free) ring[v] = 0;
  require_anchored(regions, adjacency, ring);

  // Rings 1..k around the free set (breadth first).
  std::vector<std::uint32_t> frontier = regions.free, next;
  std::vector<std::uint32_t> constrained;
  for (int r = 1; r <= k; ++r) {
    next.clear();
    for (std::uint32_t v : frontier)
      for (const std::uint32_t* u = adjacency.begin(v); u != adjacency.end(v); ++u)
        if (ring[*u] == kFar) {
          ring[*u] = r;
          next.push_back(*u);
        }
    constrained.insert(constrained.end(), next.begin(), next.end());
    frontier.swap(next);
  }
  std::sort(constrained.begin(), constrained.end());

  BcmStencil stencil;
  stencil.k = k;
  stencil.num_free = regions.free.size();
  stencil.vertices = regions.free;
  stencil.vertices.insert(stencil.vertices.end(), constrained.begin(), constrained.end());
  std::vector<std::uint32_t> local(n, UINT32_MAX);
  for (std::size_t i = 0; i < stencil.vertices.size(); ++i) {
    const std::uint32_t v = stencil.vertices[i];
    local[v] = static_cast<std::uint32_t>(i);
    stencil.ring.push_back(ring[v]);
    stencil.handle.push_back(handle_of[v]);
  }

  std::vector<std::uint32_t> ids;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    mesh.face_vertices(f, ids);
    bool inner = false;
    for (std::uint32_t v : ids) inner = inner || ring[v] <= k - 1;
    if (!inner) continue;
    if (ids.size() != 3)
      throw TopologyError("face " + std::to_string(f) + " has " + std::to_string(ids.size()) +
                             " sides and touches the free vertices or the " + std::to_string(k - 1) +
                             " rings around them that Δ^k reaches; boundary-constraint modeling needs "
                             "triangles there (triangulate the mesh first)",
                         {"support"});
    stencil.triangles.push_back({local[ids[0]], local[ids[1]], local[ids[2]]});
    stencil.faces.push_back(static_cast<std::uint32_t>(f));
  }
  return stencil;
}

}  // namespace ffd
