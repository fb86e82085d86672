// Mesh: the polygon mesh every step acts on, with the attributes ffdtool keeps.
//
// Promises:
// - vertex i of the input file is vertex i here, until a step changes connectivity;
// - each vertex has a rest position (before any warp of the current stack), a current
//   (deformed) position, a rest normal and a current normal;
// - file attributes survive every step: per-corner UVs and normals (OBJ), vertex colours,
//   OBJ groups and material statements;
// - the mesh is an oriented 2-manifold polygon mesh, boundaries allowed, isolated vertices
//   allowed (a point cloud deforms too);
// - besides these, the mesh carries only the declared attributes below (refinement
//   levels, face starts, named vec3 attributes); an op's scratch data is removed before
//   the op returns.
// Storage is a CGAL::Surface_mesh behind MeshStorage (mesh_storage.h); this header keeps
// CGAL out of code that only needs positions.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace ffd {

struct MeshStorage;
struct PolygonSoup;

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
/// Stored as CGAL Surface_mesh properties under these names (mesh_storage.h).
namespace mesh_attribute {
/// Per vertex, RefinementLevel: 0 for input vertices, max(level of a, b, c, d) + 1 for
/// the midpoint of a split edge bc (faces abc, bcd).
inline constexpr char kVertexLevel[] = "v:level";
/// Per edge, RefinementLevel: 0 for input edges; a split's new edges am, dm take the
/// midpoint's level and its halves keep bc's.
inline constexpr char kEdgeLevel[] = "e:level";
/// Per face, std::uint32_t: the index of the vertex the face's corners start at.
inline constexpr char kFaceStart[] = "f:start";
}  // namespace mesh_attribute

/// A vertex's or an edge's refinement level (mesh_attribute::kVertexLevel, kEdgeLevel).
using RefinementLevel = std::uint8_t;

/// 3 × n view of a per-vertex array; valid until the mesh's connectivity changes.
using Vec3Array = Eigen::Map<Eigen::Matrix3Xd>;
using ConstVec3Array = Eigen::Map<const Eigen::Matrix3Xd>;

class Mesh {
public:
  Mesh();
  ~Mesh();
  Mesh(Mesh&&) noexcept;
  Mesh& operator=(Mesh&&) noexcept;
  Mesh(const Mesh&) = delete;
  Mesh& operator=(const Mesh&) = delete;
  /// A deep copy, attributes included.
  Mesh clone() const;

  std::size_t num_vertices() const;
  std::size_t num_faces() const;
  std::size_t num_edges() const;
  /// True when every face is a triangle.
  bool is_triangle_mesh() const;

  /// Rest positions: where each vertex lives before the warps of the current stack.
  Vec3Array rest_positions();
  ConstVec3Array rest_positions() const;
  /// Current (deformed) positions: what is written on save.
  Vec3Array positions();
  ConstVec3Array positions() const;
  /// Unit rest normals (angle-weighted from the rest mesh); zero at isolated vertices.
  Vec3Array rest_normals();
  ConstVec3Array rest_normals() const;
  /// Unit current normals: rest normals carried through the warps (covariant rule).
  Vec3Array normals();
  ConstVec3Array normals() const;

  /// A named per-vertex 3-vector array owned by the mesh, created (zero) if missing.
  /// It follows the vertices through every connectivity change.
  Vec3Array vec3_attribute(const std::string& name);
  bool has_vec3_attribute(const std::string& name) const;
  void remove_vec3_attribute(const std::string& name);

  /// The vertex indices of face f, in order.
  void face_vertices(std::size_t f, std::vector<std::uint32_t>& out) const;
  /// All faces as index lists, in face order.
  std::vector<std::vector<std::uint32_t>> faces() const;

  bool has_uvs() const;
  bool has_file_normals() const;
  bool has_colors() const;

  /// Counts connectivity changes: ops that split, join or re-triangulate faces call
  /// mark_topology_changed(), so state built on vertex indices can tell it is stale.
  std::uint64_t topology_version() const;
  void mark_topology_changed();

  /// Sets rest positions and rest normals to the current ones (a bake of the warps).
  void bake();
  /// Recomputes rest normals from rest positions, and copies them to current normals
  /// where `also_current` is set.
  void recompute_rest_normals(bool also_current);

  MeshStorage& storage() { return *storage_; }
  const MeshStorage& storage() const { return *storage_; }

private:
  std::unique_ptr<MeshStorage> storage_;
};

}  // namespace ffd
