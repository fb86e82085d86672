#include "bcm/bcm_editor.h"

#include <Eigen/UmfPackSupport>

#include <algorithm>
#include <cmath>

#include "common/errors.h"
#include "bcm/anisotropic_laplacian.h"
#include "bcm/bcm_regions.h"
#include "bcm/kharmonic_system.h"
#include "bcm/normal_detail.h"
#include "bcm/supernodal_cholesky.h"
#include "common/timer.h"

namespace ffd {
namespace {

using Sparse = Eigen::SparseMatrix<double>;
using Frame = Eigen::Matrix<double, 3, 4>;  // columns: the frame points a, b, c, d

}  // namespace

struct BcmEditor::Impl {
  BcmOptions options;
  Stats stats;
  std::uint64_t topology_version = 0;
  std::vector<std::string> names;
  BcmRegions regions;
  BcmStencil stencil;
  std::vector<std::uint32_t> moved, normal_vertices, watched;
  Eigen::Matrix3Xd watched_positions;

  // Eq. 5: the free block's factorization and the constrained block (for solve_free).
  Sparse constrained_block;
  std::unique_ptr<SupernodalCholesky> cholesky;
  std::unique_ptr<Eigen::UmfPackLU<Sparse>> lu;

  // Eq. 6. Positions are solved relative to `origin` (the stencil's centroid) so that a
  // mesh far from the world origin loses no digits; `constant` has it added back.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Matrix3Xd stencil_setup;  // 3 × V, setup positions relative to origin
  Eigen::Matrix3Xd constant;       // 3 × P: origin + L⁻¹(0, f, 0)ᵀ
  Eigen::MatrixXd basis;           // 4·handles × P: (L⁻¹(0, 0, Q)ᵀ)ᵀ, a vertex's 4·m weights contiguous
  std::vector<Frame> frame_setup, frame;  // per handle, relative to origin
  std::vector<Eigen::Vector3d> centroid;
  std::vector<Eigen::Matrix3Xd> handle_setup;  // absolute setup positions of each handle's vertices
  std::vector<std::vector<std::uint32_t>> handle_local;  // their stencil indices (UINT32_MAX outside)
  std::vector<Eigen::Matrix3d> linear;
  std::vector<Eigen::Vector3d> translation;

  // Section 4.
  NormalDetail detail;
  Eigen::Matrix3Xd base;  // 3 × V: the base surface on the stencil for the current poses

  Eigen::MatrixXd solve(const Eigen::MatrixXd& rhs) const {
    if (cholesky) return cholesky->solve(rhs);
    return lu->solve(rhs);
  }
  // Constrained positions (relative to origin) for the current poses, C × 3.
  Eigen::MatrixXd constrained_positions() const;
};

namespace {

// The affine frame of a handle (eq. 6). The paper picks four affinely independent handle
// vertices a, b, c, d; we use the handle's centroid and the centroid plus one RMS radius
// along each world axis instead. Only affine invariance matters to eq. 6 (T(Q[a b c d]ᵀ)
// = Q·T([a b c d]ᵀ) for any affine frame), and this frame always exists and is well
// conditioned, where a flat, straight or one-vertex handle has no four affinely
// independent vertices.
void handle_frame(const Eigen::Matrix3Xd& points, Eigen::Vector3d& centroid, double& radius) {
  centroid = points.rowwise().mean();
  radius = std::sqrt((points.colwise() - centroid).colwise().squaredNorm().mean());
  if (!(radius > 0)) radius = 1.0;
}

// Affine coordinates of x in the frame (c, c + r·x̂, c + r·ŷ, c + r·ẑ): the row of Q.
Eigen::Vector4d affine_coordinates(const Eigen::Vector3d& x, const Eigen::Vector3d& centroid, double radius) {
  const Eigen::Vector3d u = (x - centroid) / radius;
  return {1.0 - u.sum(), u.x(), u.y(), u.z()};
}

}  // namespace

Eigen::MatrixXd BcmEditor::Impl::constrained_positions() const {
  const std::size_t p = stencil.num_free;
  const Eigen::Index c = static_cast<Eigen::Index>(stencil.num_constrained());
  Eigen::MatrixXd x(c, 3);
  for (Eigen::Index j = 0; j < c; ++j) {
    const std::size_t local = p + static_cast<std::size_t>(j);
    const Eigen::Vector3d rest = stencil_setup.col(static_cast<Eigen::Index>(local));
    const int h = stencil.handle[local];
    x.row(j) = h < 0 ? rest : Eigen::Vector3d(linear[h] * (rest + origin) + translation[h] - origin);
  }
  return x;
}

BcmEditor::BcmEditor(const Mesh& mesh, const std::vector<std::uint32_t>& support, const std::vector<BcmHandle>& handles,
                     const BcmOptions& options)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  std::vector<std::vector<std::uint32_t>> handle_sets;
  for (const BcmHandle& handle : handles) {
    s.names.push_back(handle.name);
    handle_sets.push_back(handle.vertices);
  }
  s.options = options;
  const int k = options.k;
  if (k < 1 || k > 3)
    throw InputError("k must be 1, 2 or 3 (higher orders are numerically unstable), found " + std::to_string(k), {"k"});
  if (s.options.outer_continuity < 0) s.options.outer_continuity = k - 1;
  if (s.options.inner_continuity < 0) s.options.inner_continuity = k - 1;
  for (const auto& [argument, c] : {std::pair<const char*, double>{"outer_continuity", s.options.outer_continuity},
                                    std::pair<const char*, double>{"inner_continuity", s.options.inner_continuity}})
    if (c > k - 1)
      throw InputError("must be at most k - 1 = " + std::to_string(k - 1) + ", found " + std::to_string(c), {argument});
  s.topology_version = mesh.topology_version();
  const auto positions = mesh.positions();

  Stopwatch clock;
  s.regions = bcm_regions(support, handle_sets);
  s.stencil = bcm_stencil(mesh, vertex_adjacency(mesh), s.regions, k);
  const BcmStencil& st = s.stencil;
  s.stats.regions_ms = clock.ms();
  clock.restart();
  const Eigen::Index v_count = static_cast<Eigen::Index>(st.vertices.size());
  const Eigen::Index p_count = static_cast<Eigen::Index>(st.num_free);
  const std::size_t m = s.regions.handles.size();

  s.stencil_setup.resize(3, v_count);
  for (Eigen::Index i = 0; i < v_count; ++i) s.stencil_setup.col(i) = positions.col(st.vertices[static_cast<std::size_t>(i)]);
  s.origin = s.stencil_setup.rowwise().mean();
  s.stencil_setup.colwise() -= s.origin;

  // Eq. 4 on the surface as it is now (or on its conformal map): never on a moved pose.
  Laplacian laplacian;
  switch (options.laplacian) {
    case LaplacianKind::Cotan:
      laplacian = cotan_laplacian(s.stencil_setup, st.triangles);
      break;
    case LaplacianKind::Uniform:
      laplacian = uniform_laplacian(v_count, st.triangles);
      break;
    case LaplacianKind::Anisotropic: {
      // The conformal map covers the whole support, handles included (they lie inside
      // it), and the k rings the system reaches, so that every weight of eq. 5 comes from
      // one planar triangulation of a disk. Vertices beyond the stencil (deep inside a
      // handle) are numbered after it.
      std::vector<std::uint32_t> local(mesh.num_vertices(), UINT32_MAX);
      std::vector<char> in_handle(mesh.num_vertices(), 0);
      for (const auto& handle : s.regions.handles)
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
            extra.push_back(Eigen::Vector3d(positions.col(ids[c])) - s.origin);
          }
          t[c] = local[ids[c]];
        }
        domain.push_back(t);
      }
      Eigen::Matrix3Xd domain_positions(3, v_count + static_cast<Eigen::Index>(extra.size()));
      domain_positions.leftCols(v_count) = s.stencil_setup;
      for (std::size_t i = 0; i < extra.size(); ++i) domain_positions.col(v_count + static_cast<Eigen::Index>(i)) = extra[i];
      laplacian = anisotropic_laplacian(domain_positions, domain, st.triangles);
      break;
    }
  }
  s.stats.laplacian_ms = clock.ms();

  clock.restart();
  Eigen::VectorXd continuity(static_cast<Eigen::Index>(st.num_constrained()));
  for (Eigen::Index j = 0; j < continuity.size(); ++j)
    continuity[j] = st.handle[st.num_free + static_cast<std::size_t>(j)] >= 0 ? s.options.inner_continuity
                                                                              : s.options.outer_continuity;
  KHarmonicSystem system = kharmonic_system(laplacian, p_count, continuity, k);
  s.constrained_block = std::move(system.constrained_block);
  s.stats.symmetric = system.symmetric;
  s.stats.system_nonzeros = static_cast<std::size_t>(system.free_block.nonZeros());
  s.stats.system_ms = clock.ms();

  // Factorize once. Only the free rows exist: the constrained ones of eq. 5 are the
  // identity and move to the right-hand side.
  clock.restart();
  const auto singular = [&] {
    if (options.laplacian == LaplacianKind::Anisotropic)
      return InputError("the k-harmonic system on this support's conformal map is numerically "
                        "singular: the map is too distorted (the support is far from developable, "
                        "e.g. most of a closed surface); use \"cotan\" or a smaller support",
                        {"laplacian"});
    return InputError("the k-harmonic system of this support is singular: degenerate (zero-area) "
                      "triangles or zero cotangent weights cut part of it off from its boundary "
                      "(try \"laplacian\": \"uniform\")",
                      {"support"});
  };
  if (system.symmetric) {
    // Symmetric positive definite (see kharmonic_system): supernodal Cholesky.
    s.cholesky = std::make_unique<SupernodalCholesky>();
    if (!s.cholesky->compute(system.free_block)) throw singular();
    s.stats.factor_nonzeros = s.cholesky->factor_nonzeros();
    s.stats.solver = "supernodal Cholesky";
  } else {
    // Smoothness between C^0 and C^(k−1) with k = 3 makes Δ̄^k unsymmetric: UMFPACK's
    // sparse LU (Eigen's SparseLU takes minutes on the 35k-vertex benchmark system).
    system.free_block.makeCompressed();
    s.lu = std::make_unique<Eigen::UmfPackLU<Sparse>>();
    s.lu->umfpackControl()(UMFPACK_IRSTEP) = 0;  // no iterative refinement: 7 solves, not 21
    s.lu->compute(system.free_block);
    if (s.lu->info() != Eigen::Success) throw singular();
    s.stats.solver = "UMFPACK LU";
  }
  s.stats.factor_ms = clock.ms();

  // Eq. 6: 3 constant columns L⁻¹(0, f, 0)ᵀ and 4 per handle L⁻¹(0, 0, Q)ᵀ, one solve.
  clock.restart();
  s.centroid.resize(m);
  s.frame_setup.resize(m);
  s.handle_setup.resize(m);
  s.handle_local.resize(m);
  s.linear.assign(m, Eigen::Matrix3d::Identity());
  s.translation.assign(m, Eigen::Vector3d::Zero());
  std::vector<double> radius(m);
  std::vector<std::uint32_t> local_of(mesh.num_vertices(), UINT32_MAX);
  for (std::size_t i = 0; i < st.vertices.size(); ++i) local_of[st.vertices[i]] = static_cast<std::uint32_t>(i);
  for (std::size_t h = 0; h < m; ++h) {
    const std::vector<std::uint32_t>& ids = s.regions.handles[h];
    s.handle_setup[h].resize(3, static_cast<Eigen::Index>(ids.size()));
    for (std::size_t i = 0; i < ids.size(); ++i) {
      s.handle_setup[h].col(static_cast<Eigen::Index>(i)) = positions.col(ids[i]);
      s.handle_local[h].push_back(local_of[ids[i]]);
    }
    handle_frame(s.handle_setup[h], s.centroid[h], radius[h]);
    const Eigen::Vector3d c = s.centroid[h] - s.origin;
    s.frame_setup[h].col(0) = c;
    for (int a = 0; a < 3; ++a) s.frame_setup[h].col(a + 1) = c + radius[h] * Eigen::Vector3d::Unit(a);
  }
  s.frame = s.frame_setup;
  const Eigen::Index columns = 3 + 4 * static_cast<Eigen::Index>(m);
  Eigen::MatrixXd boundary = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(st.num_constrained()), columns);
  for (Eigen::Index j = 0; j < boundary.rows(); ++j) {
    const std::size_t local = st.num_free + static_cast<std::size_t>(j);
    const int h = st.handle[local];
    if (h < 0) {
      boundary.block<1, 3>(j, 0) = s.stencil_setup.col(static_cast<Eigen::Index>(local)).transpose();
    } else {
      const Eigen::Vector3d x = s.stencil_setup.col(static_cast<Eigen::Index>(local)) + s.origin;
      boundary.block<1, 4>(j, 3 + 4 * h) = affine_coordinates(x, s.centroid[h], radius[h]).transpose();
    }
  }
  const Eigen::MatrixXd rhs = -(s.constrained_block * boundary);
  const Eigen::MatrixXd solution = s.solve(rhs);
  if (!solution.allFinite()) throw singular();
  s.constant = solution.leftCols(3).transpose();
  s.constant.colwise() += s.origin;
  s.basis = solution.rightCols(columns - 3).transpose();
  s.stats.basis_ms = clock.ms();

  // Section 4: the base is the BCM fairing of the support with the same boundary, which
  // is eq. 6 at the setup poses; the detail is the surface over it.
  s.base = s.stencil_setup;
  s.base.colwise() += s.origin;
  if (options.detail) {
    clock.restart();
    Eigen::Matrix3Xd surface = s.base;
    for (Eigen::Index i = 0; i < p_count; ++i) {
      Eigen::Vector3d x = s.constant.col(i);
      for (std::size_t h = 0; h < m; ++h) x.noalias() += s.frame[h] * s.basis.block<4, 1>(4 * static_cast<Eigen::Index>(h), i);
      s.base.col(i) = x;
    }
    s.detail = NormalDetail(s.base, surface, st.num_free, st.triangles);
    s.stats.detail_ms = clock.ms();
  }

  // Bookkeeping for the ops: what moves, whose normals change, what must stay put.
  s.moved = s.regions.free;
  for (const auto& handle : s.regions.handles) s.moved.insert(s.moved.end(), handle.begin(), handle.end());
  std::sort(s.moved.begin(), s.moved.end());
  std::vector<char> is_moved(mesh.num_vertices(), 0);
  for (std::uint32_t v : s.moved) is_moved[v] = 1;
  std::vector<std::uint32_t> ids;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    mesh.face_vertices(f, ids);
    if (std::any_of(ids.begin(), ids.end(), [&](std::uint32_t v) { return is_moved[v] != 0; }))
      s.normal_vertices.insert(s.normal_vertices.end(), ids.begin(), ids.end());
  }
  s.normal_vertices.insert(s.normal_vertices.end(), s.moved.begin(), s.moved.end());
  std::sort(s.normal_vertices.begin(), s.normal_vertices.end());
  s.normal_vertices.erase(std::unique(s.normal_vertices.begin(), s.normal_vertices.end()), s.normal_vertices.end());
  s.watched = st.vertices;
  s.watched.insert(s.watched.end(), s.moved.begin(), s.moved.end());
  std::sort(s.watched.begin(), s.watched.end());
  s.watched.erase(std::unique(s.watched.begin(), s.watched.end()), s.watched.end());
  remember(positions);

  s.stats.free_vertices = st.num_free;
  for (const auto& handle : s.regions.handles) s.stats.handle_vertices += handle.size();
  for (std::size_t i = st.num_free; i < st.vertices.size(); ++i) s.stats.fixed_vertices += st.handle[i] < 0;
}

BcmEditor::~BcmEditor() = default;

const BcmOptions& BcmEditor::options() const { return impl_->options; }
const BcmEditor::Stats& BcmEditor::stats() const { return impl_->stats; }
std::uint64_t BcmEditor::topology_version() const { return impl_->topology_version; }
std::size_t BcmEditor::num_handles() const { return impl_->regions.handles.size(); }
const std::string& BcmEditor::handle_name(std::size_t h) const { return impl_->names.at(h); }
std::size_t BcmEditor::handle_index(const std::string& name) const {
  const auto& names = impl_->names;
  return static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
}
Eigen::Vector3d BcmEditor::handle_centroid(std::size_t h) const { return impl_->centroid.at(h); }
const std::vector<std::uint32_t>& BcmEditor::free_vertices() const { return impl_->regions.free; }
const std::vector<std::uint32_t>& BcmEditor::handle_vertices(std::size_t h) const { return impl_->regions.handles.at(h); }
const std::vector<std::uint32_t>& BcmEditor::moved_vertices() const { return impl_->moved; }
const std::vector<std::uint32_t>& BcmEditor::normal_vertices() const { return impl_->normal_vertices; }

void BcmEditor::set_pose(std::size_t h, const Eigen::Matrix3d& linear, const Eigen::Vector3d& translation) {
  Impl& s = *impl_;
  s.linear.at(h) = linear;
  s.translation.at(h) = translation;
  // T applied to the frame points (eq. 6: T(Q[a b c d]ᵀ) = Q·T([a b c d]ᵀ)).
  s.frame[h] = ((linear * (s.frame_setup[h].colwise() + s.origin)).colwise() + translation).colwise() - s.origin;
}

void BcmEditor::update(Eigen::Ref<Eigen::Matrix3Xd> positions) {
  Impl& s = *impl_;
  const std::uint32_t* free = s.regions.free.data();
  const long p_count = static_cast<long>(s.regions.free.size());
  const Eigen::Index m = static_cast<Eigen::Index>(s.frame.size());
  const bool detail = s.options.detail;
  // Eq. 6 per free vertex: p = const + Σ_h [a b c d]_h · (its 4 basis weights of h), a
  // (3 × 4m)·(4m) product with the vertex's weights contiguous; fixed-size 3 × 4 blocks,
  // no temporaries. One thread: at 35k vertices this takes about 0.15 ms, less than
  // waking a second thread costs when the machine is busy.
  Eigen::Matrix3Xd& target = s.base;
  for (long i = 0; i < p_count; ++i) {
    Eigen::Vector3d x = s.constant.col(i);
    for (Eigen::Index h = 0; h < m; ++h) x.noalias() += s.frame[static_cast<std::size_t>(h)] * s.basis.block<4, 1>(4 * h, i);
    if (detail)
      target.col(i) = x;
    else
      positions.col(free[i]) = x;
  }
  for (std::size_t h = 0; h < s.frame.size(); ++h) {
    const std::vector<std::uint32_t>& ids = s.regions.handles[h];
    const Eigen::Matrix3d& a = s.linear[h];
    const Eigen::Vector3d& t = s.translation[h];
    for (std::size_t i = 0; i < ids.size(); ++i) {
      const Eigen::Vector3d x = a * s.handle_setup[h].col(static_cast<Eigen::Index>(i)) + t;
      positions.col(ids[i]) = x;
      if (detail && s.handle_local[h][i] != UINT32_MAX) s.base.col(s.handle_local[h][i]) = x;
    }
  }
  if (detail) {
    // Section 4: the detail rides on the moved base.
    s.detail.reconstruct(s.base, positions, s.regions.free);
  }
}

Eigen::Matrix3Xd BcmEditor::solve_free() const {
  const Impl& s = *impl_;
  const Eigen::MatrixXd rhs = -(s.constrained_block * s.constrained_positions());
  Eigen::Matrix3Xd out = s.solve(rhs).transpose();
  out.colwise() += s.origin;
  return out;
}

void BcmEditor::remember(const Eigen::Ref<const Eigen::Matrix3Xd>& positions) {
  Impl& s = *impl_;
  s.watched_positions.resize(3, static_cast<Eigen::Index>(s.watched.size()));
  for (std::size_t i = 0; i < s.watched.size(); ++i)
    s.watched_positions.col(static_cast<Eigen::Index>(i)) = positions.col(s.watched[i]);
}

long BcmEditor::changed_vertex(const Eigen::Ref<const Eigen::Matrix3Xd>& positions) const {
  const Impl& s = *impl_;
  for (std::size_t i = 0; i < s.watched.size(); ++i)
    if (positions.col(s.watched[i]) != s.watched_positions.col(static_cast<Eigen::Index>(i)))
      return static_cast<long>(s.watched[i]);
  return -1;
}

}  // namespace ffd
