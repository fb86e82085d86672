// Mesh: the polygon mesh every step acts on, with the attributes ffdtool keeps.
//
// Promises:
// - vertex i of the input file is vertex i here, until a step changes connectivity;
// - each vertex has a rest position (before any warp of the current stack), a current
//   (deformed) position, a rest normal and a current normal;
// - file attributes survive every step: per-corner UVs and normals (OBJ), vertex colours,
//   OBJ groups and material statements;
// - the elements are the file's, in order (mesh_elements.h): polygons of any size,
//   orientation or multiplicity, lines and points; no topology is assumed, so a space
//   warp acts on any of it (a point cloud deforms too). Ops that need an oriented
//   2-manifold build a checked halfedge view on demand (halfedge_view.h);
// - besides these, the mesh carries only the declared attributes below (refinement
//   levels, face starts, named vec3 attributes); an op's scratch data is removed before
//   the op returns.
// Storage is plain arrays: 3 × n matrices per vertex, flat index arrays per element; the
// per-vertex arrays are declared once, in FFD_MESH_VERTEX_ARRAYS. A halfedge view that
// an op builds is kept by whoever runs the ops (HalfedgeCache, halfedge_view.h), not here.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "mesh/mesh_elements.h"

namespace ffd {

struct GltfScene;
struct PlySource;
struct ObjSource;
struct VolumeSource;

/// Declared attributes: what steps other than the file's own data leave on a mesh, by
/// name. Each persists through every later step (copies and connectivity changes too),
/// because a later step reads it back:
/// - refinement levels, per vertex and per edge: a remesh step writes them and the next
///   remesh step's decimation reads them, since it may only remove what refinement made
///   and unwinds it level by level (Gain & Dodgson section 4); save's "level" colours
///   read them too (vertex_levels()). Absent means every level is 0;
/// - a face's start vertex: the vertex its corner cycle starts at as read (or as the
///   split that made it set it), so a face that decimation restores in a later remesh
///   step is written starting where it was;
/// - vec3 attributes (Mesh::vec3_attribute), e.g. each warp's input positions and normals
///   while the warp is on the stack (WarpStack::input_attribute()).
/// The names are what Mesh::attribute_names() lists.
namespace mesh_attribute {
/// Per vertex, RefinementLevel: 0 for input vertices, max(level of a, b, c, d) + 1 for
/// the midpoint of a split edge bc (faces abc, bcd).
inline constexpr char kVertexLevel[] = "v:level";
/// Per edge, RefinementLevel: 0 for input edges; a split's new edges am, dm take the
/// midpoint's level and its halves keep bc's.
inline constexpr char kEdgeLevel[] = "e:level";
/// Per face of the halfedge view, std::uint32_t: the index of the vertex the face's
/// corners start at (in the arrays, a polygon's corners simply start there).
inline constexpr char kFaceStart[] = "f:start";
}  // namespace mesh_attribute

/// A vertex's or an edge's refinement level (mesh_attribute::kVertexLevel, kEdgeLevel).
using RefinementLevel = std::uint8_t;

/// 3 × n view of a per-vertex array; valid until the mesh's connectivity changes.
using Vec3Array = Eigen::Map<Eigen::Matrix3Xd>;
using ConstVec3Array = Eigen::Map<const Eigen::Matrix3Xd>;

/// A copy of `from`, filled by the OpenMP team when large: each thread faults in and
/// writes its own part of the new array (a 1M-vertex mesh's positions are 24 MB of fresh
/// pages). The same values as a plain copy.
Eigen::Matrix3Xd copy_in_team(const Eigen::Ref<const Eigen::Matrix3Xd>& from);

/// The colour of a vertex that a coloured mesh gives no colour of its own (OBJ's grey).
inline const Eigen::Vector3f kDefaultColor(0.8f, 0.8f, 0.8f);

/// The declared per-vertex arrays of a Mesh, one line each:
///   X(member, storage, value, view property, default, optional)
/// `storage` is a 3 × n matrix (one column a vertex) or a std::vector of `value`; `view
/// property` names the array in the halfedge view (halfedge_view_cgal.h; "v:point" is its
/// points); a new vertex gets `default`; an optional array may be empty, and then every
/// vertex has the default. The Mesh's members, resize_vertices, clone and the halfedge
/// view's sync in both directions walk this table: a per-vertex attribute is one line.
#define FFD_MESH_VERTEX_ARRAYS(X)                                                                           \
  X(rest_, Eigen::Matrix3Xd, Eigen::Vector3d, "v:rest", Eigen::Vector3d::Zero(), false)                      \
  X(pos_, Eigen::Matrix3Xd, Eigen::Vector3d, "v:point", Eigen::Vector3d::Zero(), false)                      \
  X(rest_normal_, Eigen::Matrix3Xd, Eigen::Vector3d, "v:rest_normal", Eigen::Vector3d::Zero(), false)        \
  X(normal_, Eigen::Matrix3Xd, Eigen::Vector3d, "v:normal", Eigen::Vector3d::Zero(), false)                  \
  X(colors_, std::vector<Eigen::Vector3f>, Eigen::Vector3f, "v:color", kDefaultColor, true)                  \
  X(vertex_levels_, std::vector<RefinementLevel>, RefinementLevel, mesh_attribute::kVertexLevel, 0, true)

class Mesh;

/// One declared per-vertex array of a Mesh (a line of FFD_MESH_VERTEX_ARRAYS), as
/// Mesh::for_each_vertex_array hands it to code that walks them.
template <class Storage, class Value>
struct VertexArray {
  const char* name;       // the halfedge view's property
  Storage Mesh::*member;  // mesh.*member is the array
  Value fallback;         // of a new vertex, and of every vertex while an optional array is empty
  bool optional;
};

/// A refinement-made edge's level (mesh_attribute::kEdgeLevel), by its vertices a < b.
struct EdgeLevel {
  std::uint32_t a = 0, b = 0;
  RefinementLevel level = 0;
};

class Mesh {
public:
  Mesh();
  ~Mesh();
  Mesh(Mesh&&) noexcept;
  Mesh& operator=(Mesh&&) noexcept;
  Mesh& operator=(const Mesh&) = delete;
  /// A deep copy, attributes included (copies are explicit: a Mesh can be large).
  Mesh clone() const { return Mesh(*this); }

  /// Calls f(VertexArray<Storage, Value>{...}) for each line of FFD_MESH_VERTEX_ARRAYS, in order.
  template <class F>
  static void for_each_vertex_array(F&& f) {
#define FFD_VISIT_VERTEX_ARRAY(member, storage, value, name, fallback, optional) \
  f(VertexArray<storage, value>{name, &Mesh::member, fallback, optional});
    FFD_MESH_VERTEX_ARRAYS(FFD_VISIT_VERTEX_ARRAY)
#undef FFD_VISIT_VERTEX_ARRAY
  }

  std::size_t num_vertices() const { return static_cast<std::size_t>(pos_.cols()); }
  /// The number of polygon elements (faces); lines and points are not faces.
  std::size_t num_faces() const { return num_polygons_; }
  std::size_t num_elements() const { return elements_.size(); }
  /// True when every polygon is a triangle.
  bool is_triangle_mesh() const;

  /// Sets the vertex count to n: positions, normals and every per-vertex attribute are
  /// kept for the first min(n, old) vertices and zero past them.
  void resize_vertices(std::size_t n);
  /// Makes `positions` the vertices, rest and current, with the normals of the elements
  /// already set; every other per-vertex attribute is resized as by resize_vertices.
  /// What build_mesh does, without resize_vertices' zero fill of arrays that are written next.
  /// Without `normals`, the rest and current normals stay zero until
  /// compute_deferred_normals() (a run whose steps and outputs need none skips them).
  void set_vertices(Eigen::Matrix3Xd positions, bool normals = true);
  /// Whether set_vertices left the normals to compute_deferred_normals().
  bool normals_deferred() const { return normals_deferred_; }
  /// Computes the deferred normals: what set_vertices would have computed. Call it before
  /// any warp moves the mesh (the current normals are set to the rest normals).
  void compute_deferred_normals() {
    if (normals_deferred_) recompute_rest_normals(true);
  }

  /// Rest positions: where each vertex lives before the warps of the current stack.
  Vec3Array rest_positions() { return map(rest_); }
  ConstVec3Array rest_positions() const { return map(rest_); }
  /// Current (deformed) positions: what is written on save.
  Vec3Array positions() { return map(pos_); }
  ConstVec3Array positions() const { return map(pos_); }
  /// Unit rest normals (angle-weighted over the polygons); zero where no polygon is.
  Vec3Array rest_normals() { return map(rest_normal_); }
  ConstVec3Array rest_normals() const { return map(rest_normal_); }
  /// Unit current normals: rest normals carried through the warps (covariant rule).
  Vec3Array normals() { return map(normal_); }
  ConstVec3Array normals() const { return map(normal_); }

  /// A named per-vertex 3-vector array owned by the mesh, created (zero) if missing.
  /// It follows the vertices through every connectivity change.
  Vec3Array vec3_attribute(const std::string& name);
  /// The named vec3 attribute, read-only. \pre has_vec3_attribute(name).
  ConstVec3Array vec3_attribute(const std::string& name) const { return map(attributes_.at(name)); }
  bool has_vec3_attribute(const std::string& name) const;
  void remove_vec3_attribute(const std::string& name);
  /// The names of the vec3 attributes, sorted.
  std::vector<std::string> vec3_attribute_names() const;
  /// Every attribute the mesh carries besides its file data, by the names of
  /// mesh_attribute (vec3 attributes as "v:attr:NAME"), sorted: what a test checks for
  /// leftover scratch data (with a HalfedgeCache's: attribute_names in halfedge_view.h).
  std::vector<std::string> attribute_names() const;

  /// The file's elements in order. An op that changes them calls set_elements() and,
  /// when the connectivity differs, mark_topology_changed().
  const MeshElements& elements() const { return elements_; }
  void set_elements(MeshElements elements);
  /// The elements, for edits that keep the connectivity (corner attributes, groups).
  MeshElements& corner_data() { return elements_; }
  /// The vertex indices of polygon f (the f-th polygon element), in order.
  void face_vertices(std::size_t f, std::vector<std::uint32_t>& out) const {
    const std::size_t e = polygon_element_.empty() ? f : polygon_element_[f];
    out.assign(elements_.vertices(e), elements_.vertices(e) + elements_.degree(e));
  }
  /// The element index of polygon f.
  std::size_t polygon_element(std::size_t f) const { return polygon_element_.empty() ? f : polygon_element_[f]; }
  /// The vertex indices of every polygon, in order (a copy; for tests and small tools).
  std::vector<std::vector<std::uint32_t>> faces() const;

  /// Tables the elements' corners index: texture coordinates, file normals (rest space;
  /// transformed on save), OBJ grouping states; and the OBJ header lines (mtllib).
  std::vector<Eigen::Vector2d>& uvs() { return uvs_; }
  const std::vector<Eigen::Vector2d>& uvs() const { return uvs_; }
  std::vector<Eigen::Vector3d>& file_normals() { return file_normals_; }
  const std::vector<Eigen::Vector3d>& file_normals() const { return file_normals_; }
  std::vector<ObjState>& groups() { return groups_; }
  const std::vector<ObjState>& groups() const { return groups_; }
  std::vector<std::string>& header() { return header_; }
  const std::vector<std::string>& header() const { return header_; }
  /// Table sizes as read from the file: entries past these were made by refinement and
  /// are dropped again when no corner uses them.
  std::size_t file_uv_count = 0;
  std::size_t file_normal_count = 0;
  /// The file's normal table holds one normal per vertex (NOFF, PLY): a vertex in no
  /// element, a point of a cloud, has its normal too.
  bool file_normals_per_vertex = false;
  /// One colour per vertex (RGB in [0,1]), or empty.
  std::vector<Eigen::Vector3f>& colors() { return colors_; }
  const std::vector<Eigen::Vector3f>& colors() const { return colors_; }

  bool has_uvs() const { return !uvs_.empty(); }
  bool has_file_normals() const { return !file_normals_.empty(); }
  bool has_colors() const { return !colors_.empty(); }

  /// The file the mesh was read from (for messages naming elements), or empty.
  const std::string& source() const { return source_; }
  void set_source(std::string file) { source_ = std::move(file); }
  /// Whether the source file was binary (PLY or STL): PLY and STL outputs are written in
  /// the input's encoding (mesh_io.h, WriteOptions::encoding).
  bool source_binary() const { return source_binary_; }
  void set_source_binary(bool binary) { source_binary_ = binary; }
  /// The glTF file the mesh was read from (gltf_io.h): its nodes, materials, buffers and
  /// the map from its primitives to these vertices, so a write can keep its structure;
  /// null for other formats, and once the connectivity has changed since the read.
  const GltfScene* gltf_scene() const {
    return gltf_ && gltf_version_ == topology_version_ ? gltf_.get() : nullptr;
  }
  void set_gltf_scene(std::shared_ptr<const GltfScene> scene) {
    gltf_ = std::move(scene);
    gltf_version_ = topology_version_;
  }

  /// The PLY file the mesh was read from (ply_source.h): every element and property, so
  /// a PLY write gives the file back; null for other formats, and once the connectivity
  /// has changed since the read.
  const PlySource* ply_source() const { return ply_ && ply_version_ == topology_version_ ? ply_.get() : nullptr; }
  /// The same, even after a connectivity change (to name what a write no longer carries).
  const PlySource* ply_source_as_read() const { return ply_.get(); }
  void set_ply_source(std::shared_ptr<const PlySource> source) {
    ply_ = std::move(source);
    ply_version_ = topology_version_;
  }

  /// What an OBJ file held that ffdtool does not interpret (obj_source.h), for the OBJ
  /// writer to put back in place; null for other formats, for an OBJ with nothing of the
  /// kind, and once the connectivity has changed since the read.
  const ObjSource* obj_source() const { return obj_ && obj_version_ == topology_version_ ? obj_.get() : nullptr; }
  /// The same, even after a connectivity change (to name what a write no longer carries).
  const ObjSource* obj_source_as_read() const { return obj_.get(); }
  void set_obj_source(std::shared_ptr<const ObjSource> source) {
    obj_ = std::move(source);
    obj_version_ = topology_version_;
  }

  /// The volume mesh the vertices are the nodes of (volume_mesh.h): its cells, markers and
  /// file, which a write patches with the current positions; null for surface formats.
  /// A volume mesh's connectivity never changes (the ops that would change it refuse it).
  const VolumeSource* volume_source() const { return volume_.get(); }
  void set_volume_source(std::shared_ptr<const VolumeSource> source) { volume_ = std::move(source); }
  /// The current positions as the matrix they are stored in (for writers that take one).
  const Eigen::Matrix3Xd& position_matrix() const { return pos_; }

  /// Refinement levels (mesh_attribute): per vertex (empty: all 0), and the edges whose
  /// level is not 0, sorted by (a, b).
  std::vector<RefinementLevel>& vertex_levels() { return vertex_levels_; }
  const std::vector<RefinementLevel>& vertex_levels() const { return vertex_levels_; }
  std::vector<EdgeLevel>& edge_levels() { return edge_levels_; }
  const std::vector<EdgeLevel>& edge_levels() const { return edge_levels_; }

  /// Counts connectivity changes: ops that split, join or re-triangulate faces call
  /// mark_topology_changed(), so state built on vertex indices can tell it is stale.
  std::uint64_t topology_version() const { return topology_version_; }
  void mark_topology_changed() { ++topology_version_; }

  /// Sets rest positions and rest normals to the current ones (a bake of the warps).
  void bake();
  /// Recomputes rest normals from rest positions, and copies them to current normals
  /// where `also_current` is set.
  void recompute_rest_normals(bool also_current);

private:
  Mesh(const Mesh&) = default;  // clone()
  bool normals_deferred_ = false;
  static Vec3Array map(Eigen::Matrix3Xd& m) { return {m.data(), 3, m.cols()}; }
  static ConstVec3Array map(const Eigen::Matrix3Xd& m) { return {m.data(), 3, m.cols()}; }

#define FFD_DECLARE_VERTEX_ARRAY(member, storage, value, name, fallback, optional) storage member;
  FFD_MESH_VERTEX_ARRAYS(FFD_DECLARE_VERTEX_ARRAY)
#undef FFD_DECLARE_VERTEX_ARRAY
  std::map<std::string, Eigen::Matrix3Xd> attributes_;
  MeshElements elements_;
  std::size_t num_polygons_ = 0;
  std::vector<std::uint32_t> polygon_element_;  // empty while every element is a polygon
  std::vector<Eigen::Vector2d> uvs_;
  std::vector<Eigen::Vector3d> file_normals_;
  std::vector<ObjState> groups_;
  std::vector<std::string> header_;
  std::string source_;
  bool source_binary_ = false;
  std::shared_ptr<const GltfScene> gltf_;  // shared by clones: it is never changed
  std::uint64_t gltf_version_ = 0;
  std::shared_ptr<const PlySource> ply_;  // shared by clones: it is never changed
  std::uint64_t ply_version_ = 0;
  std::shared_ptr<const ObjSource> obj_;  // shared by clones: it is never changed
  std::uint64_t obj_version_ = 0;
  std::shared_ptr<const VolumeSource> volume_;  // shared by clones: it is never changed
  std::vector<EdgeLevel> edge_levels_;
  std::uint64_t topology_version_ = 0;
};

}  // namespace ffd
