// Mesh: the polygon mesh every step acts on, with the attributes ffdtool keeps.
//
// Promises:
// - vertex i of the input file is vertex i here, until a step changes connectivity;
// - each vertex has a rest position (before any warp of the current stack), a current
//   (deformed) position, a rest normal and a current normal;
// - file attributes survive every step: per-corner UVs and normals (OBJ), vertex colours,
//   OBJ groups and material statements;
// - the mesh is an oriented 2-manifold polygon mesh, boundaries allowed, isolated vertices
//   allowed (a point cloud deforms too).
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
