// FFD throughput: cubic B-spline (positions; positions + normals) and Bernstein 5×5×5,
// against the straightforward evaluation measured in the same run: per vertex, the
// 64-term (or 216-term) triple sum with the weight product formed per term, positions only.
#include <omp.h>

#include <cmath>
#include <numeric>
#include <random>

#include "bench.h"
#include "common/timer.h"
#include "warp/bernstein_lattice.h"
#include "warp/bspline_lattice.h"

namespace ffd::bench {
namespace {

using json = nlohmann::ordered_json;

// Every movable point displaced by up to 2% of the box's size (fixed seed).
void perturb(Lattice& lattice, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1, 1);
  const double size = 0.02 * lattice.box().extents().maxCoeff();
  for (std::size_t f = 0; f < lattice.num_points(); ++f) {
    const Index3 ijk = lattice.index(f);
    if (!lattice.movable(ijk)) continue;
    lattice.move_point(ijk, lattice.point(ijk) + size * Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng)));
  }
  lattice.prepare();
}

// The straightforward evaluation: full control points P, per vertex the weights of each
// axis, then sum_ijk (wu_i · wv_j · ww_k) P_ijk with the product formed per term.
void naive_positions(const Lattice& lattice, const Eigen::Matrix3Xd& in, Eigen::Matrix3Xd& out) {
  std::vector<Eigen::Vector3d> P(lattice.num_points());
  for (std::size_t f = 0; f < P.size(); ++f) P[f] = lattice.point(lattice.index(f));
  const int n0 = lattice.order(0), n1 = lattice.order(1), n2 = lattice.order(2);
  for (Eigen::Index v = 0; v < in.cols(); ++v) {
    const Eigen::Vector3d u = lattice.box().to_local(in.col(v));
    if (!Lattice::inside(u)) {
      out.col(v) = in.col(v);
      continue;
    }
    int first[3];
    double w[3][32], dw[3][32];
    for (int a = 0; a < 3; ++a) lattice.axis_weights(a, u[a], first[a], w[a], dw[a]);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int i = 0; i < n0; ++i)
      for (int j = 0; j < n1; ++j)
        for (int k = 0; k < n2; ++k)
          sum += (w[0][i] * w[1][j] * w[2][k]) * P[lattice.flat({first[0] + i, first[1] + j, first[2] + k})];
    out.col(v) = sum;
  }
}

json row(const std::string& name, std::size_t vertices, double ms, double baseline_ms) {
  json r = {{"case", name}, {"vertices", vertices}, {"ms", ms},
            {"mvertices_per_s", vertices / ms / 1e3}};
  if (baseline_ms > 0) r["speedup_vs_baseline"] = baseline_ms / ms;
  return r;
}

}  // namespace

void bench_ffd(Context& ctx) {
  json rows = json::array();
  const Mesh base = load(ctx, "bunny.obj");
  const std::vector<std::size_t> sizes = ctx.quick ? std::vector<std::size_t>{20000}
                                                   : std::vector<std::size_t>{100000, 1000000};
  for (std::size_t target : sizes) {
    const Mesh mesh = subdivided(base, target);
    const std::size_t n = mesh.num_vertices();
    const Eigen::Matrix3Xd pos = mesh.positions(), nrm = mesh.normals();
    std::vector<std::uint32_t> ids(n);
    std::iota(ids.begin(), ids.end(), 0u);
    Eigen::Matrix3Xd out_pos(3, n), out_nrm(3, n), ref(3, n);
    const Eigen::Vector3d lo = pos.rowwise().minCoeff(), hi = pos.rowwise().maxCoeff();
    const Eigen::Vector3d pad = 0.05 * (hi - lo).maxCoeff() * Eigen::Vector3d::Ones();
    const Parallelepiped box = Parallelepiped::from_min_max(lo - pad, hi + pad);

    omp_set_num_threads(1);
    BSplineLattice cubic(box, {8, 8, 8}, 3);
    perturb(cubic, 7);
    const double base_ms = median_ms(ctx.repeats, [&] { naive_positions(cubic, pos, ref); });
    rows.push_back(row("baseline: cubic B-spline, triple sum, positions", n, base_ms, 0));
    const double pos_ms = median_ms(ctx.repeats, [&] { cubic.apply_positions(pos, ids, out_pos); });
    rows.push_back(row("cubic B-spline 8x8x8, positions", n, pos_ms, base_ms));
    rows.back()["max_difference_vs_baseline"] = (out_pos - ref).cwiseAbs().maxCoeff();
    WarpCounts counts;
    const double full_ms =
        median_ms(ctx.repeats, [&] { cubic.apply(pos, nrm, ids, out_pos, out_nrm, counts); });
    rows.push_back(row("cubic B-spline 8x8x8, positions + normals", n, full_ms, base_ms));

    BernsteinLattice bezier(box, {5, 5, 5});
    perturb(bezier, 11);
    const double bez_base_ms = median_ms(ctx.repeats, [&] { naive_positions(bezier, pos, ref); });
    rows.push_back(row("baseline: Bernstein 5x5x5, triple sum, positions", n, bez_base_ms, 0));
    const double bez_ms =
        median_ms(ctx.repeats, [&] { bezier.apply(pos, nrm, ids, out_pos, out_nrm, counts); });
    rows.push_back(row("Bernstein 5x5x5, positions + normals", n, bez_ms, bez_base_ms));
    rows.back()["max_difference_vs_baseline"] = (out_pos - ref).cwiseAbs().maxCoeff();

    const int cores = omp_get_num_procs();
    omp_set_num_threads(cores);
    Eigen::Matrix3Xd par_pos(3, n), par_nrm(3, n);
    const double par_ms = median_ms(ctx.repeats, [&] { cubic.apply(pos, nrm, ids, par_pos, par_nrm, counts); });
    cubic.apply(pos, nrm, ids, out_pos, out_nrm, counts);
    rows.push_back(row("cubic B-spline 8x8x8, positions + normals, " + std::to_string(cores) + " threads", n,
                       par_ms, base_ms));
    omp_set_num_threads(1);
    Eigen::Matrix3Xd one_pos(3, n), one_nrm(3, n);
    cubic.apply(pos, nrm, ids, one_pos, one_nrm, counts);
    rows.back()["bit_identical_to_one_thread"] = one_pos == par_pos && one_nrm == par_nrm;
  }
  ctx.out["ffd"] = rows;
}

}  // namespace ffd::bench
