#include "bcm/bcm_editor.h"

#include "mesh/halfedge_view.h"

#include <Eigen/UmfPackSupport>

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "bcm/anisotropic_laplacian.h"
#include "bcm/basis_rows.h"
#include "common/supernodal_cholesky.h"
#include "common/errors.h"
#include "common/timer.h"

namespace ffd {

using Sparse = Eigen::SparseMatrix<double>;

struct BcmFactor {
  std::unique_ptr<SupernodalCholesky> cholesky;  // symmetric systems
  std::unique_ptr<Eigen::UmfPackLU<Sparse>> lu;  // unsymmetric ones
  Eigen::MatrixXd solve(const Eigen::MatrixXd& rhs) const { return cholesky ? cholesky->solve(rhs) : lu->solve(rhs); }
};

void BcmFactorDelete::operator()(BcmFactor* factor) const { delete factor; }

namespace {

// The mean of the columns, summed in column order. Eigen's rowwise().mean() into a
// Vector3d sums two of the rows as one SIMD packet, pairwise, and the third alone, in
// order; which two share the packet depends on the destination's address, so the same
// points gave origins 1e-17 apart in two BcmData objects on different stack slots.
Eigen::Vector3d column_mean(const Eigen::Matrix3Xd& points) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < points.cols(); ++i) sum += points.col(i);
  return sum / static_cast<double>(points.cols());
}

// The affine frame of a handle (eq. 6). The paper picks four affinely independent handle
// vertices a, b, c, d; we use the handle's centroid and the centroid plus one RMS radius
// along each world axis instead. Only affine invariance matters to eq. 6 (T(Q[a b c d]ᵀ)
// = Q·T([a b c d]ᵀ) for any affine frame), and this frame always exists and is well
// conditioned, where a flat, straight or one-vertex handle has no four affinely
// independent vertices.
void handle_frame(const Eigen::Matrix3Xd& points, Eigen::Vector3d& centroid, double& radius) {
  centroid = column_mean(points);
  radius = std::sqrt((points.colwise() - centroid).colwise().squaredNorm().mean());
  if (!(radius > 0)) radius = 1.0;
}

// Affine coordinates of x in the frame (c, c + r·x̂, c + r·ŷ, c + r·ẑ): the row of Q.
Eigen::Vector4d affine_coordinates(const Eigen::Vector3d& x, const Eigen::Vector3d& centroid, double radius) {
  const Eigen::Vector3d u = (x - centroid) / radius;
  return {1.0 - u.sum(), u.x(), u.y(), u.z()};
}

// The error of a singular system, about what the user can change.
InputError singular(const BcmOptions& options) {
  if (options.laplacian == LaplacianKind::Anisotropic)
    return InputError("the k-harmonic system on this support's conformal map is numerically "
                      "singular: the map is too distorted (the support is far from developable, "
                      "e.g. most of a closed surface); use \"cotan\" or a smaller support",
                      {"laplacian"});
  return InputError("the k-harmonic system of this support is singular: degenerate (zero-area or "
                    "needle) triangles, whose cotangents are clamped, make it indefinite or cut part "
                    "of it off from its boundary (try \"laplacian\": \"uniform\")",
                    {"support"});
}

// Checks k and the continuities; negative continuity means k − 1.
BcmOptions resolved_options(const BcmOptions& options) {
  BcmOptions out = options;
  const int k = options.k;
  if (k < 1 || k > 3)
    throw InputError("k must be 1, 2 or 3 (higher orders are numerically unstable), found " + std::to_string(k), {"k"});
  if (out.outer_continuity < 0) out.outer_continuity = k - 1;
  if (out.inner_continuity < 0) out.inner_continuity = k - 1;
  for (const auto& [argument, c] : {std::pair<const char*, double>{"outer_continuity", out.outer_continuity},
                                    std::pair<const char*, double>{"inner_continuity", out.inner_continuity}})
    if (c > k - 1)
      throw InputError("must be at most k - 1 = " + std::to_string(k - 1) + ", found " + std::to_string(c), {argument});
  return out;
}

// The anisotropic Laplacian's planar domain covers the whole support, handles included
// (they lie inside it), and the k rings the system reaches, so that every weight of eq. 5
// comes from one planar triangulation of a disk. Vertices beyond the stencil (deep inside
// a handle) are numbered after it.
Laplacian anisotropic_operator(const BcmData& data, const Mesh& mesh) {
  const BcmStencil& st = data.stencil;
  const Eigen::Index v_count = static_cast<Eigen::Index>(st.vertices.size());
  const auto positions = mesh.positions();
  std::vector<std::uint32_t> local(mesh.num_vertices(), UINT32_MAX);
  std::vector<char> in_handle(mesh.num_vertices(), 0);
  for (const auto& handle : data.regions.handles)
    for (std::uint32_t v : handle) in_handle[v] = 1;
  for (std::size_t i = 0; i < st.vertices.size(); ++i) local[st.vertices[i]] = static_cast<std::uint32_t>(i);
  std::vector<Eigen::Vector3d> extra;
  std::vector<Triangle> domain = st.triangles;
  std::vector<char> taken(mesh.num_faces(), 0);
  for (std::uint32_t f : st.faces) taken[f] = 1;
  std::vector<std::uint32_t> ids;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    if (taken[f]) continue;
    mesh.face_vertices(f, ids);
    if (std::none_of(ids.begin(), ids.end(), [&](std::uint32_t v) { return in_handle[v] != 0; })) continue;
    if (ids.size() != 3)
      throw TopologyError("face " + std::to_string(f) + " has " + std::to_string(ids.size()) +
                              " sides; the anisotropic Laplacian needs triangles in the handles",
                          {"handles"});
    Triangle t;
    for (int c = 0; c < 3; ++c) {
      if (local[ids[c]] == UINT32_MAX) {
        local[ids[c]] = static_cast<std::uint32_t>(st.vertices.size() + extra.size());
        extra.push_back(Eigen::Vector3d(positions.col(ids[c])) - data.origin);
      }
      t[c] = local[ids[c]];
    }
    domain.push_back(t);
  }
  Eigen::Matrix3Xd domain_positions(3, v_count + static_cast<Eigen::Index>(extra.size()));
  domain_positions.leftCols(v_count) = data.stencil_setup;
  for (std::size_t i = 0; i < extra.size(); ++i) domain_positions.col(v_count + static_cast<Eigen::Index>(i)) = extra[i];
  return anisotropic_laplacian(domain_positions, domain, st.triangles);
}

// The handles' affine frames at setup (eq. 6), their vertices' stencil indices, and
// identity poses.
void handle_frames(BcmData& data) {
  const std::size_t m = data.regions.handles.size();
  data.centroid.resize(m);
  data.radius.resize(m);
  data.frame_setup.resize(m);
  data.handle_local.assign(m, {});
  data.linear.assign(m, Eigen::Matrix3d::Identity());
  data.translation.assign(m, Eigen::Vector3d::Zero());
  std::vector<std::uint32_t> local_of;
  for (std::size_t i = 0; i < data.stencil.vertices.size(); ++i) {
    const std::uint32_t v = data.stencil.vertices[i];
    if (v >= local_of.size()) local_of.resize(v + 1, UINT32_MAX);
    local_of[v] = static_cast<std::uint32_t>(i);
  }
  for (std::size_t h = 0; h < m; ++h) {
    for (std::uint32_t v : data.regions.handles[h])
      data.handle_local[h].push_back(v < local_of.size() ? local_of[v] : UINT32_MAX);
    handle_frame(data.handle_setup[h], data.centroid[h], data.radius[h]);
    const Eigen::Vector3d c = data.centroid[h] - data.origin;
    data.frame_setup[h].col(0) = c;
    for (int a = 0; a < 3; ++a) data.frame_setup[h].col(a + 1) = c + data.radius[h] * Eigen::Vector3d::Unit(a);
  }
  data.frame = data.frame_setup;
}

// Constrained positions (relative to origin) for the current poses, C × 3.
Eigen::MatrixXd constrained_positions(const BcmData& data) {
  const BcmStencil& st = data.stencil;
  const std::size_t p = st.num_free;
  const Eigen::Index c = static_cast<Eigen::Index>(st.num_constrained());
  Eigen::MatrixXd x(c, 3);
  for (Eigen::Index j = 0; j < c; ++j) {
    const std::size_t local = p + static_cast<std::size_t>(j);
    const Eigen::Vector3d rest = data.stencil_setup.col(static_cast<Eigen::Index>(local));
    const int h = st.handle[local];
    x.row(j) = h < 0 ? rest : Eigen::Vector3d(data.linear[h] * (rest + data.origin) + data.translation[h] - data.origin);
  }
  return x;
}

// Eq. 6 at the current poses for the free vertices whose constants and weights are the
// columns of `constant` and `basis` (stored by rows), vertex i into out's column i, or
// columns[i] where `columns` is given (basis_rows.h: row by row, its fusions written out).
// Inside an OpenMP team the threads share the vertices and meet at a barrier after them;
// outside one it runs alone.
void evaluate_basis(const BcmData& data, const BcmRows& constant, const BcmRows& basis, const std::uint32_t* columns,
                    double* out, long out_stride) {
  constexpr long kChunk = 512;
  const long p = static_cast<long>(constant.cols()), chunks = (p + kChunk - 1) / kChunk;
  const int handles = static_cast<int>(data.frame.size());
  static_assert(sizeof(BcmFrame) == 12 * sizeof(double), "frames are 12 doubles apart");
  const double* frames = handles > 0 ? data.frame.front().data() : nullptr;
#pragma omp for schedule(static)
  for (long chunk = 0; chunk < chunks; ++chunk)
    basis_rows(constant.data(), basis.data(), p, frames, handles, chunk * kChunk, std::min(p, (chunk + 1) * kChunk),
               columns, out_stride, out);
}

}  // namespace

void bcm_regions_and_rings(BcmData& data, const Mesh& mesh, const std::vector<std::uint32_t>& support,
                           const std::vector<BcmHandle>& handles, const BcmOptions& options) {
  Stopwatch clock;
  data.options = resolved_options(options);
  std::vector<std::vector<std::uint32_t>> handle_sets;
  data.names.clear();
  for (const BcmHandle& handle : handles) {
    data.names.push_back(handle.name);
    handle_sets.push_back(handle.vertices);
  }
  data.regions = bcm_regions(support, handle_sets);
  data.stencil = bcm_stencil(mesh, vertex_adjacency(mesh), data.regions, data.options.k);
  const BcmStencil& st = data.stencil;
  const auto positions = mesh.positions();
  const Eigen::Index v_count = static_cast<Eigen::Index>(st.vertices.size());
  data.stencil_setup.resize(3, v_count);
  for (Eigen::Index i = 0; i < v_count; ++i)
    data.stencil_setup.col(i) = positions.col(st.vertices[static_cast<std::size_t>(i)]);
  data.origin = column_mean(data.stencil_setup);
  data.stencil_setup.colwise() -= data.origin;
  data.handle_setup.assign(handles.size(), {});
  for (std::size_t h = 0; h < handles.size(); ++h) {
    const std::vector<std::uint32_t>& ids = data.regions.handles[h];
    data.handle_setup[h].resize(3, static_cast<Eigen::Index>(ids.size()));
    for (std::size_t i = 0; i < ids.size(); ++i) data.handle_setup[h].col(static_cast<Eigen::Index>(i)) = positions.col(ids[i]);
  }
  data.stats.free_vertices = st.num_free;
  data.stats.handle_vertices = 0;
  for (const auto& handle : data.regions.handles) data.stats.handle_vertices += handle.size();
  data.stats.fixed_vertices = 0;
  for (std::size_t i = st.num_free; i < st.vertices.size(); ++i) data.stats.fixed_vertices += st.handle[i] < 0;
  data.stats.regions_ms = clock.ms();
}

Laplacian bcm_operator(const BcmData& data, const Mesh& mesh) {
  // Eq. 4 on the surface as it is now (or on its conformal map): never on a moved pose.
  switch (data.options.laplacian) {
    case LaplacianKind::Cotan:
      return cotan_laplacian(data.stencil_setup, data.stencil.triangles);
    case LaplacianKind::CotanPositive:
      return cotan_laplacian(data.stencil_setup, data.stencil.triangles, CotanWeights::Positive);
    case LaplacianKind::Uniform:
      return uniform_laplacian(data.stencil_setup.cols(), data.stencil.triangles);
    case LaplacianKind::Anisotropic:
      break;
  }
  return anisotropic_operator(data, mesh);
}

KHarmonicSystem bcm_system(BcmData& data, const Laplacian& laplacian) {
  const BcmStencil& st = data.stencil;
  Eigen::VectorXd continuity(static_cast<Eigen::Index>(st.num_constrained()));
  for (Eigen::Index j = 0; j < continuity.size(); ++j)
    continuity[j] = st.handle[st.num_free + static_cast<std::size_t>(j)] >= 0 ? data.options.inner_continuity
                                                                              : data.options.outer_continuity;
  KHarmonicSystem system =
      kharmonic_system(laplacian, static_cast<Eigen::Index>(st.num_free), continuity, data.options.k);
  data.constrained_block = system.constrained_block;
  data.stats.symmetric = system.symmetric;
  data.stats.system_nonzeros = static_cast<std::size_t>(system.free_block.nonZeros());
  return system;
}

void bcm_factorize(BcmData& data, const KHarmonicSystem& system) {
  // Only the free rows exist: the constrained ones of eq. 5 are the identity and move to
  // the right-hand side.
  data.factor.reset(new BcmFactor);
  if (system.symmetric) {
    // Symmetric positive definite (see kharmonic_system): supernodal Cholesky.
    data.factor->cholesky = std::make_unique<SupernodalCholesky>();
    if (!data.factor->cholesky->compute(system.free_block)) throw singular(data.options);
    data.stats.factor_nonzeros = data.factor->cholesky->factor_nonzeros();
    data.stats.solver = "supernodal Cholesky";
    return;
  }
  // Smoothness between C^0 and C^(k−1) with k = 3 makes Δ̄^k unsymmetric: UMFPACK's
  // sparse LU (Eigen's SparseLU takes minutes on the 35k-vertex benchmark system).
  Sparse free_block = system.free_block;
  free_block.makeCompressed();
  data.factor->lu = std::make_unique<Eigen::UmfPackLU<Sparse>>();
  data.factor->lu->umfpackControl()(UMFPACK_IRSTEP) = 0;  // no iterative refinement: 7 solves, not 21
  data.factor->lu->compute(free_block);
  if (data.factor->lu->info() != Eigen::Success) throw singular(data.options);
  data.stats.solver = "UMFPACK LU";
}

void bcm_basis(BcmData& data) {
  // Eq. 6: 3 constant columns L⁻¹(0, f, 0)ᵀ and 4 per handle L⁻¹(0, 0, Q)ᵀ, one solve.
  const BcmStencil& st = data.stencil;
  handle_frames(data);
  const std::size_t m = data.regions.handles.size();
  const Eigen::Index columns = 3 + 4 * static_cast<Eigen::Index>(m);
  Eigen::MatrixXd boundary = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(st.num_constrained()), columns);
  for (Eigen::Index j = 0; j < boundary.rows(); ++j) {
    const std::size_t local = st.num_free + static_cast<std::size_t>(j);
    const int h = st.handle[local];
    if (h < 0) {
      boundary.block<1, 3>(j, 0) = data.stencil_setup.col(static_cast<Eigen::Index>(local)).transpose();
    } else {
      const Eigen::Vector3d x = data.stencil_setup.col(static_cast<Eigen::Index>(local)) + data.origin;
      boundary.block<1, 4>(j, 3 + 4 * h) = affine_coordinates(x, data.centroid[h], data.radius[h]).transpose();
    }
  }
  const Eigen::MatrixXd rhs = -(data.constrained_block * boundary);
  const Eigen::MatrixXd solution = data.factor->solve(rhs);
  if (!solution.allFinite()) throw singular(data.options);
  data.constant = solution.leftCols(3).transpose();
  data.constant.colwise() += data.origin;
  data.basis = solution.rightCols(columns - 3).transpose();
}

void bcm_detail(BcmData& data) {
  // The base is the BCM fairing of the support with the same boundary, which is eq. 6 at
  // the setup poses; the detail is the surface over it.
  if (!data.options.detail) return;
  Eigen::Matrix3Xd surface = data.stencil_setup;
  surface.colwise() += data.origin;
  Eigen::Matrix3Xd base = surface;
  evaluate_basis(data, data.constant, data.basis, nullptr, base.data(), base.outerStride());
  data.detail = NormalDetail(base, surface, data.stencil.num_free, data.stencil.triangles);
  // The weights again in the detail's slot order, so that each frame writes its base
  // straight along the detail's copy of it.
  const Eigen::Index p = static_cast<Eigen::Index>(data.stencil.num_free);
  data.slot_constant.resize(3, p);
  data.slot_basis.resize(data.basis.rows(), p);
  for (Eigen::Index i = 0; i < p; ++i) {
    const Eigen::Index s = data.detail.slot(static_cast<std::uint32_t>(i));
    data.slot_constant.col(s) = data.constant.col(i);
    data.slot_basis.col(s) = data.basis.col(i);
  }
}

BcmData bcm_precompute(const Mesh& mesh, const std::vector<std::uint32_t>& support,
                       const std::vector<BcmHandle>& handles, const BcmOptions& options,
                       const std::function<void(double)>& progress) {
  // Each phase's share of a typical setup's time, in order: regions and rings, operator,
  // system, factorization, basis, detail (left out without detail).
  static constexpr double kWeights[] = {0.10, 0.10, 0.15, 0.40, 0.15, 0.10};
  const int last = options.detail ? 5 : 4;
  const double total = options.detail ? 1.0 : 1.0 - kWeights[5];
  double done = 0;
  const auto phase_done = [&](int phase) {
    done += kWeights[phase];
    if (progress) progress(phase == last ? 1.0 : std::min(1.0, done / total));
  };
  // Cotangent Laplacians, rings and the conformal parametrization assume an oriented
  // 2-manifold: refuse anything else up front, naming the element.
  check_two_manifold(mesh);
  BcmData data;
  bcm_regions_and_rings(data, mesh, support, handles, options);
  phase_done(0);
  Stopwatch clock;
  const Laplacian laplacian = bcm_operator(data, mesh);
  data.stats.laplacian_ms = clock.ms();
  phase_done(1);
  clock.restart();
  const KHarmonicSystem system = bcm_system(data, laplacian);
  data.stats.system_ms = clock.ms();
  phase_done(2);
  clock.restart();
  bcm_factorize(data, system);
  data.stats.factor_ms = clock.ms();
  phase_done(3);
  clock.restart();
  bcm_basis(data);
  data.stats.basis_ms = clock.ms();
  phase_done(4);
  clock.restart();
  bcm_detail(data);
  if (data.options.detail) {
    data.stats.detail_ms = clock.ms();
    phase_done(5);
  }
  return data;
}

void bcm_set_pose(BcmData& data, std::size_t h, const Eigen::Matrix3d& linear, const Eigen::Vector3d& translation) {
  data.linear.at(h) = linear;
  data.translation.at(h) = translation;
  // T applied to the frame points (eq. 6: T(Q[a b c d]ᵀ) = Q·T([a b c d]ᵀ)).
  data.frame[h] =
      ((linear * (data.frame_setup[h].colwise() + data.origin)).colwise() + translation).colwise() - data.origin;
}

void bcm_pose(BcmData& data, Eigen::Ref<Eigen::Matrix3Xd> positions, int threads) {
  // Eq. 6 per free vertex: p = const + Σ_h [a b c d]_h · (its 4 basis weights of h), a
  // (3 × 4m)·(4m) product, row by row over the vertices (basis_rows.h); with detail, in
  // the detail's slot order. One team of threads for the whole frame; each vertex is
  // written by one thread with the same arithmetic whatever their number.
  const bool detail = data.options.detail;
  const std::uint32_t* free = data.regions.free.data();
#pragma omp parallel num_threads(threads > 0 ? threads : omp_get_max_threads())
  {
    // With detail, the moved base goes straight into the detail's own copy of it.
    Eigen::Matrix4Xd& base = data.detail.base_in_slots();
    // The handles first, by one thread without a barrier: they write other columns than
    // the basis below, whose loop ends with the barrier that both need before the detail.
#pragma omp single nowait
    for (std::size_t h = 0; h < data.frame.size(); ++h) {
      const std::vector<std::uint32_t>& ids = data.regions.handles[h];
      const Eigen::Matrix3d& a = data.linear[h];
      const Eigen::Vector3d& t = data.translation[h];
      for (std::size_t i = 0; i < ids.size(); ++i) {
        const Eigen::Vector3d x = a * data.handle_setup[h].col(static_cast<Eigen::Index>(i)) + t;
        positions.col(ids[i]) = x;
        const std::uint32_t slot = detail ? data.detail.slot(data.handle_local[h][i]) : UINT32_MAX;
        if (slot != UINT32_MAX) base.col(slot).head<3>() = x;
      }
    }
    if (detail)
      evaluate_basis(data, data.slot_constant, data.slot_basis, nullptr, base.data(), base.outerStride());
    else
      evaluate_basis(data, data.constant, data.basis, free, positions.data(), positions.outerStride());
    // Section 4: the detail rides on the moved base.
    if (detail) data.detail.reconstruct_in_team(positions, data.regions.free);
  }
}

Eigen::Matrix3Xd bcm_solve_free(const BcmData& data) {
  const Eigen::MatrixXd rhs = -(data.constrained_block * constrained_positions(data));
  Eigen::Matrix3Xd out = data.factor->solve(rhs).transpose();
  out.colwise() += data.origin;
  return out;
}

std::size_t bcm_handle_index(const BcmData& data, const std::string& name) {
  return static_cast<std::size_t>(std::find(data.names.begin(), data.names.end(), name) - data.names.begin());
}

}  // namespace ffd
