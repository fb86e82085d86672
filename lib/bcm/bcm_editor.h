// Boundary-constraint modeling (Botsch & Kobbelt) in libigl's precompute/solve shape: a
// plain data struct, one free function per setup phase, bcm_precompute() running them all,
// and bcm_set_pose() / bcm_pose() per frame at the cost of a small dense product.
//
// Promises:
// - the Laplacian is taken from the surface at setup (never from a moved pose);
// - setup factorizes the free block of eq. 5 once (a supernodal Cholesky when it is
//   symmetric, a sparse LU otherwise), keeps the factorization, and solves for 3 constant
//   columns plus 4 basis columns per handle (eq. 6); no inverse is ever formed;
// - bcm_pose() writes p = const + B·[a b c d]ᵀ for the handles' current poses, with no
//   solve and no allocation; a handle never posed stays where it was (Figure 4);
// - with detail (section 4) the edit acts on the smooth base, the base being the BCM
//   fairing of the support with the same boundary, and the detail rides on the base;
// - deterministic: the same mesh and regions give bit-identical results.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "bcm/bcm_options.h"
#include "bcm/bcm_regions.h"
#include "bcm/cotan_laplacian.h"
#include "bcm/kharmonic_system.h"
#include "bcm/normal_detail.h"
#include "mesh/mesh.h"

namespace ffd {

/// A handle region: a name (for scripts and messages) and its vertices, ascending.
struct BcmHandle {
  std::string name;
  std::vector<std::uint32_t> vertices;
};

/// Setup times and sizes, for stats.
struct BcmStats {
  std::size_t free_vertices = 0, handle_vertices = 0, fixed_vertices = 0;  // fixed: in the k rings
  std::size_t system_nonzeros = 0, factor_nonzeros = 0;  // factor: entries of L (Cholesky; 0 for the LU)
  bool symmetric = true;
  const char* solver = "";
  double regions_ms = 0, laplacian_ms = 0, system_ms = 0, factor_ms = 0, basis_ms = 0, detail_ms = 0;
};

/// The factorization of eq. 5's free block: Cholesky or LU (behind a pointer, so that
/// this header needs neither solver's headers).
struct BcmFactor;
struct BcmFactorDelete {
  void operator()(BcmFactor* factor) const;
};

/// An affine frame of a handle: its points a, b, c, d as columns (eq. 6).
using BcmFrame = Eigen::Matrix<double, 3, 4>;
/// Per-vertex numbers stored by rows (a row is one coordinate or one weight over the
/// vertices), as eq. 6's row kernel reads them (basis_rows.h).
using BcmRows = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// What a boundary-constraint edit precomputes, phase by phase, and its current poses.
/// Local vertex numbering is the stencil's: free vertices first, then constrained ones.
struct BcmData {
  BcmOptions options;  // continuity resolved (k − 1 where not given)
  BcmStats stats;
  std::vector<std::string> names;  // of the handles
  // Regions and rings.
  BcmRegions regions;
  BcmStencil stencil;
  // Positions are solved relative to `origin` (the stencil's centroid) so that a mesh far
  // from the world origin loses no digits; `constant` has it added back.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Matrix3Xd stencil_setup;  // 3 × V, setup positions relative to origin
  // System and factorization (eq. 5).
  Eigen::SparseMatrix<double> constrained_block;
  std::unique_ptr<BcmFactor, BcmFactorDelete> factor;
  // Basis (eq. 6).
  BcmRows constant;  // 3 × P: origin + L⁻¹(0, f, 0)ᵀ
  BcmRows basis;     // 4·handles × P: handle h's weights in rows 4h .. 4h + 3
  std::vector<BcmFrame> frame_setup, frame;  // per handle, relative to origin
  std::vector<Eigen::Vector3d> centroid;
  std::vector<double> radius;
  std::vector<Eigen::Matrix3Xd> handle_setup;            // absolute setup positions of each handle
  std::vector<std::vector<std::uint32_t>> handle_local;  // their stencil indices (UINT32_MAX outside)
  std::vector<Eigen::Matrix3d> linear;                   // current poses
  std::vector<Eigen::Vector3d> translation;
  // Detail (section 4): it holds the base surface for the current poses, and the basis
  // comes again with its columns in the detail's slot order (free vertex i at
  // detail.slot(i)).
  NormalDetail detail;
  BcmRows slot_constant;
  BcmRows slot_basis;
};

/// Phase 1, regions and rings: checks the options, splits the support into free and
/// handle vertices and finds the k rings of fixed vertices around them. \throw
/// InputError about "k", "outer_continuity", "inner_continuity", "support" or element j of
/// "handles" (bcm_regions, bcm_stencil); TopologyError about "support" for a face the
/// system reaches that is not a triangle.
void bcm_regions_and_rings(BcmData& data, const Mesh& mesh, const std::vector<std::uint32_t>& support,
                           const std::vector<BcmHandle>& handles, const BcmOptions& options);

/// Phase 2, the operator: eq. 4's Laplacian on the stencil at setup (cotan, cotan_positive,
/// uniform, or anisotropic on the support's conformal map). \throw TopologyError about "handles" (a
/// handle face that is not a triangle) or "laplacian" (the support is not a disk).
Laplacian bcm_operator(const BcmData& data, const Mesh& mesh);

/// Phase 3, the system and its ordering: eq. 5's blocks with each constrained vertex's
/// continuity. Keeps the constrained block in `data`.
KHarmonicSystem bcm_system(BcmData& data, const Laplacian& laplacian);

/// Phase 4, factorization of the free block, once. \throw InputError about "support" (or
/// "laplacian" for the anisotropic kind) when the system is singular; SolverError when the
/// factor does not fit in memory.
void bcm_factorize(BcmData& data, const KHarmonicSystem& system);

/// Phase 5, the basis of eq. 6: the constant columns and 4 columns per handle in its
/// affine frame. \throw InputError about "support" when a solve is not finite.
void bcm_basis(BcmData& data);

/// Phase 6, detail (section 4): the base is eq. 6 at the setup poses; the detail is the
/// surface over it, encoded in the base's local frames. Does nothing without detail.
void bcm_detail(BcmData& data);

/// Every phase on `mesh`'s current positions. `support` and each handle's vertices are
/// ascending, duplicate-free vertex lists. `progress`, when set, is called after each
/// phase with the fraction of the setup done (increasing, 1 after the last phase; each
/// phase weighs its typical share of the time); it never changes the result. Throws what
/// the phases throw, and first TopologyError naming the first element that keeps the
/// mesh from being an oriented 2-manifold (check_two_manifold).
BcmData bcm_precompute(const Mesh& mesh, const std::vector<std::uint32_t>& support,
                       const std::vector<BcmHandle>& handles, const BcmOptions& options,
                       const std::function<void(double)>& progress = {});

/// Sets handle h's pose relative to setup: x ↦ linear·x + translation.
void bcm_set_pose(BcmData& data, std::size_t h, const Eigen::Matrix3d& linear, const Eigen::Vector3d& translation);

/// Writes the free and handle vertices' positions (columns of the mesh's 3 × n array) for
/// the current poses: eq. 6 plus, with detail, the detail added back. `threads`: the
/// team's size (0: OpenMP's default); the result is the same whatever it is.
void bcm_pose(BcmData& data, Eigen::Ref<Eigen::Matrix3Xd> positions, int threads = 0);

/// The free vertices of eq. 5 solved directly for the current poses with the stored
/// factorization (no basis), 3 × num_free in regions.free order, without detail. For
/// checks; bcm_pose() is the fast path.
Eigen::Matrix3Xd bcm_solve_free(const BcmData& data);

/// The handle called `name`, or names.size() if there is none.
std::size_t bcm_handle_index(const BcmData& data, const std::string& name);

}  // namespace ffd
