// WarpStack: the ordered space warps acting on a mesh.
//
// A vertex's current position is the composition of every warp, in creation order,
// applied to its rest position; its normal goes through each warp's cofactor (covariant
// rule). Each warp's input (the output of the warps below it) is kept per vertex, so a
// change to warp k re-evaluates only the vertices inside what k changed (its bit index),
// through k and the warps above it. New vertices (refinement) are evaluated from rest
// space through the whole stack, so they sample the true deformed surface.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "warp/warp.h"

namespace ffd {

class WarpStack {
public:
  struct Update {
    std::size_t moved = 0;   // vertices re-evaluated
    std::size_t folded = 0;  // of those, where some warp has det(J) <= 0
  };

  std::size_t size() const { return warps_.size(); }
  /// Adds a warp on top; the mesh's current state becomes its input.
  void push(Mesh& mesh, std::string name, std::unique_ptr<Warp> warp);
  /// The warp called `name`, or null.
  Warp* find(const std::string& name) const;
  Warp& warp(std::size_t k) const { return *warps_[k]; }
  /// Position of warp `name`; size() if there is none.
  std::size_t index_of(const std::string& name) const;
  /// Vertex v's position in the input space of warp k (its rest position for k = 0).
  Eigen::Vector3d input_position(const Mesh& mesh, std::size_t k, std::uint32_t v) const;
  const std::string& name(std::size_t k) const { return names_[k]; }

  /// Re-evaluates the vertices that warp `k` changed since its last update, through k and
  /// every warp above it, then clears k's changes.
  Update update(Mesh& mesh, std::size_t k);
  /// Update for the warp called `name`.
  Update update(Mesh& mesh, const std::string& name);

  /// A point of warp k's output space carried through the warps above k (what a
  /// lattice's control point looks like after the lattices created after it).
  Eigen::Vector3d carry_from(std::size_t k, const Eigen::Vector3d& x) const;
  /// A rest-space point through every warp; the total Jacobian when asked.
  Eigen::Vector3d evaluate(const Eigen::Vector3d& rest, Eigen::Matrix3d* jacobian) const;
  /// Carries a rest position `x` and rest normal `n` through every warp, in place (the
  /// covariant rule for n); `input(k, x, n)`, when set, sees warp k's input for k >= 1.
  using InputSink = std::function<void(std::size_t, const Eigen::Vector3d&, const Eigen::Vector3d&)>;
  void evaluate_point(Eigen::Vector3d& x, Eigen::Vector3d& n, const InputSink& input) const;
  /// Fills vertex v's per-warp inputs, current position and normal from its rest
  /// position and rest normal (for vertices a step has just created).
  void evaluate_vertex(Mesh& mesh, std::uint32_t v) const;
  /// A rest-space normal at vertex v carried through every warp, unit length.
  Eigen::Vector3d transform_normal(const Mesh& mesh, std::uint32_t v, const Eigen::Vector3d& n) const;

  /// Freezes the deformation: rest := current (positions, normals, file normals), and
  /// drops every warp. Returns the names of the warps dropped.
  std::vector<std::string> bake(Mesh& mesh);
  /// What bake does to the mesh, done to `copy`, a clone of the mesh this stack deforms
  /// (the stack and its own mesh stay as they are): a run's result fed to another run.
  void bake_copy(Mesh& copy) const;

  /// Name of the mesh attribute (Mesh::vec3_attribute) holding warp k's input positions
  /// (k >= 1; warp 0 reads the rest positions).
  static std::string input_attribute(std::size_t k) { return input_name(k, "pos"); }
  /// The same for warp k's input normals.
  static std::string input_normal_attribute(std::size_t k) { return input_name(k, "nrm"); }

private:
  static std::string input_name(std::size_t k, const char* what);
  std::vector<std::string> names_;
  std::vector<std::unique_ptr<Warp>> warps_;
};

}  // namespace ffd
