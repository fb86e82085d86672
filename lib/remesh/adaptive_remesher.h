// Adaptive refinement and reversible decimation under FFD (Gain & Dodgson, section 4).
//
// Promises:
// - Levels: input vertices and edges are level 0. Splitting edge bc (faces abc, bcd)
//   creates m at bc's rest-space midpoint, evaluated through the whole warp stack
//   (position; normal = covariant transform of the interpolated rest normal; UVs, file
//   normals and colours interpolated per corner). level(m) = max(level a, b, c, d) + 1;
//   edges am, dm get level(m); bm, cm keep bc's level. A boundary edge splits with its one
//   face.
// - Refinement (figure 3): an edge is refined if (a) an endpoint was deformed since the
//   last remesh and its deformed endpoint normals diverge by more than θmax
//   (ε = 1 − n̄1·n̄2), or (b) it is longer than Lmax. Longest edge first; the four new
//   edges are tested and pushed. Condition (b) applies where the warps can act
//   (Warp::can_act_on_segment: for a lattice, edges that meet its box; the paper's
//   sampling argument, point 1); elsewhere the mesh is never deformed and splitting would
//   only add vertices.
// - Decimation: candidates are the endpoints of edges whose normals diverge by less than
//   θmin and that are shorter than Lmax; by level, highest first; a vertex goes only if it
//   has exactly four incident edges (three on a boundary) that all pass, all neighbours are
//   at its level or lower, and its edges are exactly those its split made; removal is the
//   exact reverse of the split (figure 3 backwards), so a refinement stack unwinds to the
//   original faces. Level-0 vertices are never removed. One guard beyond the paper: a
//   decimation whose restored edge would be refined again at once (longer than Lmax, or
//   deformed and diverging by more than θmax) is skipped, so a step never leaves an edge
//   its own trigger would split and remeshing does not oscillate.
// - Polygon faces are triangulated first (counted in the stats).
// - Levels and face starts are the mesh's declared attributes (mesh.h: mesh_attribute)
//   and stay on the mesh for the next remesh step; scratch data is removed before
//   adaptive_remesh returns.
// - Deterministic: ties in edge length break by edge index, candidates by vertex index.
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "mesh/halfedge_view.h"
#include "mesh/mesh.h"
#include "remesh/remesh_options.h"
#include "warp/warp_stack.h"

namespace ffd {

/// Refines and decimates `mesh` after a deformation by `stack`'s warps, on the halfedge
/// view that `cache` keeps between steps (the same halfedge and edge numbering from one
/// remesh step to the next, while nothing else changes the connectivity). `progress`, when
/// set, is called now and then with an estimate of the fraction done (the edge scan, then
/// refinement as edges popped over popped plus queued, then decimation candidates
/// visited; not always monotone) and with 1 at the end; it never changes the result.
/// \throw InputError about "l_max" if l_max is automatic and no warp on the stack has a feature size
/// (no lattice).
RemeshStats adaptive_remesh(Mesh& mesh, HalfedgeCache& cache, const WarpStack& stack, const RemeshOptions& options,
                            const std::function<void(double)>& progress = {});

/// The smallest Warp::feature_size() over the stack (a lattice's: box edge length /
/// cells), or 0 when no warp has one. Gain & Dodgson's Lmax.
double smallest_cell_extent(const WarpStack& stack);

/// Each vertex's refinement level (0 for input vertices and for meshes never remeshed).
std::vector<int> vertex_levels(const Mesh& mesh);

/// A colour per vertex showing its level: level 0 light grey, then blue through green
/// and yellow to red at `top_level` and above.
std::vector<Eigen::Vector3f> level_colors(const Mesh& mesh, int top_level);

}  // namespace ffd
