// The topology view: what the ops that need an oriented 2-manifold (remesh, bcm) check
// and build on demand from a Mesh's arrays. This header keeps CGAL out; the view itself
// (a CGAL::Surface_mesh) is in halfedge_view_cgal.h.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace ffd {

struct HalfedgeView;

/// Checks that the polygons of `mesh` form an oriented 2-manifold (boundaries allowed;
/// lines and points are ignored), in element order:
/// - at least one face (a point cloud is not a surface);
/// - degenerate face f: fewer than three corners, or a vertex used twice;
/// - non-manifold edge i–j: a third face on it;
/// - face f flipped against its neighbour g, or a duplicate of g: both run i→j;
/// - non-manifold vertex v: its faces form more than one fan.
/// \throw TopologyError naming the first offending element (its file line when known,
/// from Mesh::source()) and what is wrong.
void check_two_manifold(const Mesh& mesh);

/// A deep copy of a view (for Mesh::clone).
std::shared_ptr<HalfedgeView> copy_view(const HalfedgeView& view);

/// The names of a view's properties, sorted (for Mesh::attribute_names).
std::vector<std::string> view_property_names(const HalfedgeView& view);

}  // namespace ffd
