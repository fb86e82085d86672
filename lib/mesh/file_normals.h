// File normals (OBJ vn, NOFF, PLY) carried into deformed space.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "mesh/mesh.h"

namespace ffd {

/// Carries a rest-space normal found at a vertex into deformed space.
using NormalTransform = std::function<Eigen::Vector3d(std::uint32_t vertex, const Eigen::Vector3d&)>;

/// The file-normal table after a deformation, and each corner's entry in it.
struct CornerNormals {
  std::vector<Eigen::Vector3d> table;
  /// Per element corner (MeshElements::corners): index into table, -1 for none; empty
  /// when no corner has a file normal.
  std::vector<std::int64_t> corner;
};

/// Transforms every corner's file normal at its vertex (each distinct (normal, vertex)
/// pair once). Entry k of the old table becomes its distinct results, in the order
/// corners first meet them, so an identity transform returns the table unchanged;
/// unreferenced entries are kept as they are. A null transform keeps the table.
CornerNormals transformed_file_normals(const Mesh& mesh, const NormalTransform& transform);

/// One normal per vertex for formats that hold them so (OFF, PLY, glTF): each vertex's
/// file normal from its first corner that has one, carried into deformed space.
struct VertexFileNormals {
  std::vector<Eigen::Vector3d> value;  // zero where `has` is not set
  std::vector<char> has;               // the vertex has a file normal
  std::vector<char> moved;             // the transform changed it
};
VertexFileNormals vertex_file_normals(const Mesh& mesh, const NormalTransform& transform);

/// Whether vertex_file_normals finds a file normal at every vertex, so that a writer of
/// one normal per vertex (OFF, PLY) never falls back to the mesh's computed normals.
bool every_vertex_has_file_normal(const Mesh& mesh);

/// Replaces the mesh's file normals by their transformed values (a bake).
void bake_file_normals(Mesh& mesh, const NormalTransform& transform);

}  // namespace ffd
