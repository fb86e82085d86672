// The numeric Cholesky factorization of the bcm suite's k = 3 system (the 35k-vertex
// cap, cotan, C^2 boundaries) two ways, on the same CHOLMOD ordering and supernodal
// analysis: lib/bcm's SupernodalCholesky (Eigen's dense kernels, one thread) and
// CHOLMOD's own supernodal numeric phase, which calls the system BLAS and LAPACK (and,
// for scale, Eigen's SimplicialLLT on its own ordering).
// Which BLAS that is, Debian's alternatives decide (libblas.so.3-x86_64-linux-gnu and
// liblapack.so.3-x86_64-linux-gnu: the reference BLAS, or OpenBLAS once
// libopenblas0-pthread is installed); the row names the libraries this process loaded
// and OPENBLAS_NUM_THREADS, so run it once per setting:
//   update-alternatives --set libblas.so.3-x86_64-linux-gnu <path>   (and liblapack)
//   OPENBLAS_NUM_THREADS=1 ffdbench --suite cholesky
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <random>
#include <set>

#include "bcm/bcm_regions.h"
#include "bcm/cotan_laplacian.h"
#include "bcm/kharmonic_system.h"
#include "common/supernodal_cholesky.h"
#include "bench.h"
#include "common/errors.h"
#include "common/timer.h"

namespace ffd::bench {
namespace {

using json = nlohmann::ordered_json;
using Sparse = Eigen::SparseMatrix<double>;

// The free block of the k = 3, C^2 system the editor factorizes on `r` (its stencil, the
// cotangent Laplacian at the setup positions relative to their centroid, eq. 5).
Sparse k3_free_block(const Mesh& mesh, const Regions& r) {
  const BcmRegions regions = bcm_regions(r.support, {r.handle});
  const BcmStencil stencil = bcm_stencil(mesh, vertex_adjacency(mesh), regions, 3);
  Eigen::Matrix3Xd positions(3, static_cast<Eigen::Index>(stencil.vertices.size()));
  for (std::size_t i = 0; i < stencil.vertices.size(); ++i)
    positions.col(static_cast<Eigen::Index>(i)) = mesh.positions().col(stencil.vertices[i]);
  positions.colwise() -= Eigen::Vector3d(positions.rowwise().mean());
  const Laplacian laplacian = cotan_laplacian(positions, stencil.triangles);
  const Eigen::VectorXd continuity = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(stencil.num_constrained()), 2);
  return kharmonic_system(laplacian, static_cast<Eigen::Index>(stencil.num_free), continuity, 3).free_block;
}

// The BLAS and LAPACK shared objects mapped into this process (resolved paths).
json loaded_blas() {
  std::ifstream maps("/proc/self/maps");
  std::set<std::string> found;
  std::string line;
  while (std::getline(maps, line)) {
    const std::size_t slash = line.find('/');
    if (slash == std::string::npos) continue;
    const std::string path = line.substr(slash);
    if (path.find("blas") != std::string::npos || path.find("lapack") != std::string::npos) found.insert(path);
  }
  return json(std::vector<std::string>(found.begin(), found.end()));
}

// λ_max / λ_min of the symmetric positive definite `a`, by 60 steps of power iteration
// and 30 of inverse iteration with `factor`: cond · 2^-53 bounds the relative forward
// error any double-precision solver can promise (and so how closely two agree).
double condition_estimate(const Sparse& a, const SupernodalCholesky& factor) {
  Eigen::VectorXd v = Eigen::VectorXd::Ones(a.rows()).normalized();
  double largest = 0, smallest = 0;
  for (int i = 0; i < 60; ++i) {
    const Eigen::VectorXd w = a.selfadjointView<Eigen::Lower>() * v;
    largest = w.norm();
    v = w / largest;
  }
  v = Eigen::VectorXd::Ones(a.rows()).normalized();
  for (int i = 0; i < 30; ++i) {
    const Eigen::VectorXd w = factor.solve(v);
    smallest = 1 / w.norm();
    v = w * smallest;
  }
  return largest / smallest;
}

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// CHOLMOD's supernodal LLᵀ with lib/bcm's settings (AMD, postordered, one method):
// analysis once, then `repeats` numeric factorizations; returns their median ms and the
// solution of A·x = b.
double cholmod_numeric_ms(const Sparse& a, int repeats, const Eigen::MatrixXd& b, Eigen::MatrixXd& x) {
  cholmod_common common;
  cholmod_start(&common);
  common.print = 0;
  common.supernodal = CHOLMOD_SUPERNODAL;
  common.nmethods = 1;
  common.method[0].ordering = CHOLMOD_AMD;
  common.postorder = true;
  cholmod_sparse view = Eigen::viewAsCholmod(a.selfadjointView<Eigen::Lower>());
  cholmod_factor* factor = cholmod_analyze(&view, &common);
  if (!factor) throw SolverError("CHOLMOD's analysis failed");
  std::vector<double> times;
  for (int i = 0; i < std::max(1, repeats) + 1; ++i) {  // the first run warms the BLAS up
    Stopwatch clock;
    cholmod_factorize(&view, factor, &common);
    if (i > 0) times.push_back(clock.ms());
    if (common.status != CHOLMOD_OK || factor->minor != factor->n) throw SolverError("CHOLMOD's factorization failed");
  }
  Eigen::MatrixXd rhs = b;
  cholmod_dense rhs_view = Eigen::viewAsCholmod(rhs);
  cholmod_dense* solution = cholmod_solve(CHOLMOD_A, factor, &rhs_view, &common);
  x = Eigen::Map<Eigen::MatrixXd>(static_cast<double*>(solution->x), b.rows(), b.cols());
  cholmod_free_dense(&solution, &common);
  cholmod_free_factor(&factor, &common);
  cholmod_finish(&common);
  return median_of(times);
}

// Eigen's own sparse LLᵀ (simplicial, its own AMD ordering, no BLAS): the median ms of
// `repeats` numeric factorizations after one analysis.
double eigen_numeric_ms(const Sparse& a, int repeats) {
  Eigen::SimplicialLLT<Sparse, Eigen::Lower> llt;
  llt.analyzePattern(a);
  std::vector<double> times;
  for (int i = 0; i < std::max(1, repeats); ++i) {
    Stopwatch clock;
    llt.factorize(a);
    times.push_back(clock.ms());
    if (llt.info() != Eigen::Success) throw SolverError("Eigen's SimplicialLLT failed");
  }
  return median_of(times);
}

}  // namespace

void bench_cholesky(Context& ctx) {
  const std::string name = "bunny00.off";
  const Mesh mesh = load(ctx, name);
  const std::size_t support_size = ctx.quick ? 5000 : 35000;
  const Regions r = cap_regions(mesh, support_size, std::max<std::size_t>(10, support_size / 100));
  const Sparse a = k3_free_block(mesh, r);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(-1, 1);
  Eigen::MatrixXd b(a.rows(), 7);
  for (Eigen::Index i = 0; i < b.size(); ++i) b.data()[i] = unit(rng);

  SupernodalCholesky ours;
  std::vector<double> ours_ms;
  for (int i = 0; i < std::max(1, ctx.repeats) + 1; ++i) {
    if (!ours.compute(a)) throw SolverError("the supernodal Cholesky failed");
    if (i > 0) ours_ms.push_back(ours.numeric_ms());
  }
  const Eigen::MatrixXd x_ours = ours.solve(b);
  Eigen::MatrixXd x_cholmod;
  const double cholmod_ms = cholmod_numeric_ms(a, ctx.repeats, b, x_cholmod);
  const double ours_median = median_of(ours_ms), gflop = ours.factor_flops() / 1e9;
  const double condition = condition_estimate(a, ours);
  const double eigen_ms = eigen_numeric_ms(a, std::min(ctx.repeats, 3));
  const char* threads = std::getenv("OPENBLAS_NUM_THREADS");
  ctx.out["cholesky"] = json::array(
      {{{"case", "k=3 cotan, C^2: numeric supernodal LL^T, same AMD ordering and analysis"},
        {"mesh", name},
        {"free_vertices", a.rows()},
        {"system_nonzeros", a.nonZeros()},
        {"factor_nonzeros", ours.factor_nonzeros()},
        {"gflop", gflop},
        {"blas_loaded", loaded_blas()},
        {"openblas_num_threads", threads ? threads : "(unset)"},
        {"ours_numeric_ms", ours_median},
        {"ours_gflops", gflop / (ours_median / 1e3)},
        {"cholmod_numeric_ms", cholmod_ms},
        {"cholmod_gflops", gflop / (cholmod_ms / 1e3)},
        {"cholmod_over_ours", cholmod_ms / ours_median},
        {"eigen_simplicial_numeric_ms", eigen_ms},
        {"eigen_simplicial_over_ours", eigen_ms / ours_median},
        {"max_solution_difference_relative", (x_ours - x_cholmod).cwiseAbs().maxCoeff() / x_cholmod.cwiseAbs().maxCoeff()},
        {"condition_estimate", condition},
        {"condition_times_epsilon", condition * 0x1p-53}}});
}

}  // namespace ffd::bench
