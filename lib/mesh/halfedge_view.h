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

/// The halfedge view that the last op which built one for a mesh left (remesh), kept so
/// that consecutive ops see the same halfedge and edge numbering; valid while the mesh's
/// connectivity is as that op left it. Whoever runs the ops keeps it beside the mesh
/// (Scene::halfedges); halfedge_view() and write_back() (halfedge_view_cgal.h) use it.
class HalfedgeCache {
public:
  HalfedgeCache();
  ~HalfedgeCache();
  HalfedgeCache(HalfedgeCache&&) noexcept;
  HalfedgeCache& operator=(HalfedgeCache&&) noexcept;
  /// A deep copy (the view's property maps bound to the copy).
  HalfedgeCache clone() const;

  /// The kept view, or null.
  HalfedgeView* view() const { return view_.get(); }
  /// Whether the view is up to date with `mesh`'s connectivity (its topology version).
  bool valid_for(const Mesh& mesh) const { return view_ && version_ == mesh.topology_version(); }
  /// Keeps `view` as up to date with `mesh`.
  void keep(std::shared_ptr<HalfedgeView> view, const Mesh& mesh);
  /// Marks the view stale (an op is changing it), or up to date with `mesh` again.
  void invalidate() { version_ = ~std::uint64_t(0); }
  void revalidate(const Mesh& mesh) { version_ = mesh.topology_version(); }

private:
  std::shared_ptr<HalfedgeView> view_;
  std::uint64_t version_ = ~std::uint64_t(0);
};

/// The names of a view's properties, sorted.
std::vector<std::string> view_property_names(const HalfedgeView& view);

/// Mesh::attribute_names() and the kept view's properties as "view NAME", sorted: every
/// attribute a mesh and its cache carry besides the file's data.
std::vector<std::string> attribute_names(const Mesh& mesh, const HalfedgeCache& cache);

}  // namespace ffd
