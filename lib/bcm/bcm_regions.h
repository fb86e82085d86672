// The vertex sets of boundary-constraint modeling (Botsch & Kobbelt eq. 5, Figure 1):
// free vertices p (support minus handles, blue), handle vertices h (green) and fixed
// vertices f (everything else, grey), and the stencil the k-harmonic system needs: the
// free vertices and the k rings of constrained vertices around them (k rings prescribe
// C^(k−1) boundary conditions, "k+1 rings for C^k" in the paper's words).
#pragma once

#include <cstdint>
#include <vector>

#include "bcm/cotan_laplacian.h"
#include "mesh/mesh.h"

namespace ffd {

/// Vertex neighbours from the mesh's faces, in compressed rows, each row ascending.
struct VertexAdjacency {
  std::vector<std::uint32_t> offsets;  // num_vertices + 1
  std::vector<std::uint32_t> neighbors;
  std::size_t degree(std::uint32_t v) const { return offsets[v + 1] - offsets[v]; }
  const std::uint32_t* begin(std::uint32_t v) const { return neighbors.data() + offsets[v]; }
  const std::uint32_t* end(std::uint32_t v) const { return neighbors.data() + offsets[v + 1]; }
};

/// Vertex adjacency of every face's edges.
VertexAdjacency vertex_adjacency(const Mesh& mesh);

struct BcmRegions {
  std::vector<std::uint32_t> free;                  // support minus the handles, ascending
  std::vector<std::vector<std::uint32_t>> handles;  // each ascending
};

/// Splits a support and its handles (sorted, unique vertex lists) into free and handle
/// sets. \throw InputError about element j of "handles" when handle j has vertices outside
/// the support or shares vertices with an earlier handle; about "support" when the handles
/// cover the whole support, leaving nothing free.
BcmRegions bcm_regions(const std::vector<std::uint32_t>& support,
                       const std::vector<std::vector<std::uint32_t>>& handles);

/// What the k-harmonic system of a region acts on, in local indices.
struct BcmStencil {
  int k = 0;
  /// Local vertex -> mesh vertex: the free vertices first (as in BcmRegions::free), then
  /// the constrained vertices within k rings of them, ascending.
  std::vector<std::uint32_t> vertices;
  std::size_t num_free = 0;
  /// Per local vertex: graph distance to the free set (0 for free vertices, 1..k).
  std::vector<int> ring;
  /// Per local vertex: the handle it belongs to, or -1 (free or fixed).
  std::vector<int> handle;
  /// Every face around a vertex within k−1 rings (so the Laplacian rows that Δ^k needs
  /// are complete), with local indices; `faces` holds each one's mesh face index.
  std::vector<Triangle> triangles;
  std::vector<std::uint32_t> faces;

  std::size_t num_constrained() const { return vertices.size() - num_free; }
};

/// The stencil of `regions` for Δ^k. \throw InputError about "support" when a connected
/// part of the free vertices touches no fixed or handle vertex (nothing would determine
/// it: the system is singular); TopologyError about "support" when a face within k−1
/// rings is not a triangle.
BcmStencil bcm_stencil(const Mesh& mesh, const VertexAdjacency& adjacency, const BcmRegions& regions, int k);

}  // namespace ffd
