// BcmEditor: a boundary-constraint modeling editor (Botsch & Kobbelt), set up once on a
// support with handles, then driven by 9-dof handle poses at the cost of a small dense
// product per frame.
//
// Promises:
// - the Laplacian is taken from the surface at setup (never from a moved pose);
// - setup factorizes the free block of eq. 5 once (a supernodal Cholesky when it is
//   symmetric, a sparse LU otherwise), keeps the factorization, and solves for 3 constant
//   columns plus 4 basis columns per handle (eq. 6); no inverse is ever formed;
// - update() writes p = const + B·[a b c d]ᵀ for the handles' current poses, with no solve
//   and no allocation; a handle never posed stays where it was (a fixed island, Figure 4);
// - with detail (section 4) the edit acts on the smooth base, the base being the BCM
//   fairing of the support with the same boundary, and the detail rides on the base;
// - deterministic: the same mesh and regions give bit-identical results.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "bcm/bcm_options.h"
#include "mesh/mesh.h"

namespace ffd {

/// A handle region: a name (for scripts and messages) and its vertices, ascending.
struct BcmHandle {
  std::string name;
  std::vector<std::uint32_t> vertices;
};

class BcmEditor {
public:
  /// Setup times and sizes, for stats.
  struct Stats {
    std::size_t free_vertices = 0, handle_vertices = 0, fixed_vertices = 0;  // fixed: in the k rings
    std::size_t system_nonzeros = 0, factor_nonzeros = 0;  // factor: entries of L (Cholesky; 0 for the LU)
    bool symmetric = true;
    const char* solver = "";
    double regions_ms = 0, laplacian_ms = 0, system_ms = 0, factor_ms = 0, basis_ms = 0, detail_ms = 0;
  };

  /// Sets an editor up on `mesh`'s current positions. `support` and each handle's
  /// vertices are ascending, duplicate-free vertex lists. \throw InputError (its subject the argument at
  /// fault: "support", element j of "handles", "laplacian", "k", "outer_continuity" or
  /// "inner_continuity"; TopologyError for faces that are not triangles) when a handle leaves the support or overlaps another, nothing is free, a part
  /// of the support touches no fixed or handle vertex, a face the system reaches is not a
  /// triangle, an anisotropic support is not a disk, the system is singular, k is not
  /// 1, 2 or 3, or a continuity exceeds k−1 (negative means k−1).
  BcmEditor(const Mesh& mesh, const std::vector<std::uint32_t>& support, const std::vector<BcmHandle>& handles,
            const BcmOptions& options);
  ~BcmEditor();
  BcmEditor(const BcmEditor&) = delete;
  BcmEditor& operator=(const BcmEditor&) = delete;

  const BcmOptions& options() const;
  const Stats& stats() const;
  /// The mesh's topology_version() at setup: vertex indices are valid while it matches.
  std::uint64_t topology_version() const;

  std::size_t num_handles() const;
  const std::string& handle_name(std::size_t h) const;
  /// The handle called `name`, or num_handles() if there is none.
  std::size_t handle_index(const std::string& name) const;
  /// Handle h's centroid at setup: the default centre of its transforms.
  Eigen::Vector3d handle_centroid(std::size_t h) const;
  /// Sets handle h's pose relative to setup: x ↦ linear·x + translation.
  void set_pose(std::size_t h, const Eigen::Matrix3d& linear, const Eigen::Vector3d& translation);
  /// Writes the free and handle vertices' positions (columns of the mesh's 3 × n array)
  /// for the current poses: eq. 6 plus, with detail, the detail added back.
  void update(Eigen::Ref<Eigen::Matrix3Xd> positions);

  /// The free vertices of eq. 5 solved directly for the current poses with the stored
  /// factorization (no basis), 3 × num_free in free_vertices() order, without detail.
  /// For checks; update() is the fast path.
  Eigen::Matrix3Xd solve_free() const;

  /// Support minus handles, ascending.
  const std::vector<std::uint32_t>& free_vertices() const;
  const std::vector<std::uint32_t>& handle_vertices(std::size_t h) const;
  /// What update() writes: free and handle vertices, ascending.
  const std::vector<std::uint32_t>& moved_vertices() const;
  /// The moved vertices and every vertex sharing a face with one (whose normals a move
  /// changes), ascending.
  const std::vector<std::uint32_t>& normal_vertices() const;

  /// Remembers where the vertices the editor reads and writes are now (setup does this).
  void remember(const Eigen::Ref<const Eigen::Matrix3Xd>& positions);
  /// The first such vertex that is no longer where remember() saw it (another step moved
  /// it), or -1.
  long changed_vertex(const Eigen::Ref<const Eigen::Matrix3Xd>& positions) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ffd
