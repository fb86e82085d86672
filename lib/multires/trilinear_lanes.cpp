// Compiled with -ffp-contract=off (lib/CMakeLists.txt): every fused multiply-add below is
// written out, where GCC fuses the scalar code's, and no other product is fused.
#include "multires/trilinear_lanes.h"

#ifdef __AVX2__
#include <immintrin.h>
#endif
#if defined(__AVX2__) && defined(__FMA__) && !defined(__clang__)
#define FFD_TRILINEAR_LANES 1
#endif

namespace ffd {

void TrilinearLanes::pad(int from) {
  for (int lane = from; lane < kLanes; ++lane)
    for (int i = 0; i < 3; ++i)
      for (int c = 0; c < 8; ++c) corners[i][c][lane] = corners[i][c][0];
  pad_points(from);
}

void TrilinearLanes::pad_points(int from) {
  for (int lane = from; lane < kLanes; ++lane)
    for (int i = 0; i < 3; ++i) x[i][lane] = x[i][0], guess[i][lane] = guess[i][0];
}

void TrilinearLanes::set_cells(const Eigen::Matrix3Xd& positions, const std::int32_t corner[kLanes][8]) {
#ifdef __AVX2__
  static_assert(kLanes == 4, "one four-by-four transpose per corner");
  const double* data = positions.data();
  // Column p as (x, y, z, 0): two loads that stay inside the column (the last one too).
  const auto column = [data](std::int32_t p) {
    const double* q = data + 3 * static_cast<std::ptrdiff_t>(p);
    return _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(q)), _mm_load_sd(q + 2), 1);
  };
  for (int c = 0; c < 8; ++c) {
    const __m256d v0 = column(corner[0][c]), v1 = column(corner[1][c]);
    const __m256d v2 = column(corner[2][c]), v3 = column(corner[3][c]);
    const __m256d xz01 = _mm256_unpacklo_pd(v0, v1), y01 = _mm256_unpackhi_pd(v0, v1);  // (x0 x1 z0 z1), (y0 y1 0 0)
    const __m256d xz23 = _mm256_unpacklo_pd(v2, v3), y23 = _mm256_unpackhi_pd(v2, v3);
    _mm256_store_pd(corners[0][c], _mm256_permute2f128_pd(xz01, xz23, 0x20));
    _mm256_store_pd(corners[1][c], _mm256_permute2f128_pd(y01, y23, 0x20));
    _mm256_store_pd(corners[2][c], _mm256_permute2f128_pd(xz01, xz23, 0x31));
  }
#else
  for (int lane = 0; lane < kLanes; ++lane) set_cell(lane, positions, corner[lane]);
#endif
}

namespace {

/// Each lane by the scalar inverse_trilinear; a lane it fails is left undecided (it fails
/// again when called).
[[maybe_unused]] void solve_each(TrilinearLanes& lanes) {
  for (int lane = 0; lane < TrilinearLanes::kLanes; ++lane) {
    CellCorners Q;
    for (int i = 0; i < 3; ++i)
      for (int c = 0; c < 8; ++c) Q(i, c) = lanes.corners[i][c][lane];
    const Eigen::Vector3d x(lanes.x[0][lane], lanes.x[1][lane], lanes.x[2][lane]);
    const Eigen::Vector3d guess(lanes.guess[0][lane], lanes.guess[1][lane], lanes.guess[2][lane]);
    Eigen::Vector3d u;
    Eigen::Matrix3d J;
    lanes.decided[lane] = inverse_trilinear(Q, x, u, guess, &J);
    for (int i = 0; i < 3; ++i) {
      lanes.u[i][lane] = u[i];
      for (int j = 0; j < 3; ++j) lanes.dx_du[i][j][lane] = J(i, j);
    }
  }
}

#ifdef FFD_TRILINEAR_LANES
using V = __m256d;

inline V add(V a, V b) { return _mm256_add_pd(a, b); }
inline V sub(V a, V b) { return _mm256_sub_pd(a, b); }
inline V mul(V a, V b) { return _mm256_mul_pd(a, b); }
inline V fma(V a, V b, V c) { return _mm256_fmadd_pd(a, b, c); }       // a b + c
inline V fms(V a, V b, V c) { return _mm256_fmsub_pd(a, b, c); }       // a b - c
inline V fnma(V a, V b, V c) { return _mm256_fnmadd_pd(a, b, c); }     // c - a b
inline V blend(V a, V b, V mask) { return _mm256_blendv_pd(a, b, mask); }  // b where mask
inline V negate(V a) { return _mm256_xor_pd(a, _mm256_set1_pd(-0.0)); }
inline V magnitude(V a) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), a); }
template <int Compare>
inline V where(V a, V b) { return _mm256_cmp_pd(a, b, Compare); }

/// trilinear(Q, u, &J) and its residual r = x(u) - point.
struct Evaluation {
  V r[3];
  V J[3][3];
};

/// trilinear_weights' products: w_c = (a0 a1) a2 and dw_c = (+-a1) a2, (+-a0) a2, (a0 a1)(+-1)
/// with a = (1 - u, u) by the corner's bits, each the same rounded product.
void weights(const V u[3], V w[8], V dw[8][3]) {
  const V one = _mm256_set1_pd(1.0);
  const V a[2][3] = {{sub(one, u[0]), sub(one, u[1]), sub(one, u[2])}, {u[0], u[1], u[2]}};
  V a01[2][2], a02[2][2], a12[2][2];
  for (int s = 0; s < 2; ++s)
    for (int t = 0; t < 2; ++t)
      a01[s][t] = mul(a[s][0], a[t][1]), a02[s][t] = mul(a[s][0], a[t][2]), a12[s][t] = mul(a[s][1], a[t][2]);
  for (int c = 0; c < 8; ++c) {
    const int s0 = c & 1, s1 = (c >> 1) & 1, s2 = (c >> 2) & 1;
    w[c] = mul(a01[s0][s1], a[s2][2]);
    dw[c][0] = s0 ? a12[s1][s2] : negate(a12[s1][s2]);
    dw[c][1] = s1 ? a02[s0][s2] : negate(a02[s0][s2]);
    dw[c][2] = s2 ? a01[s0][s1] : negate(a01[s0][s1]);
  }
}

/// trilinear() as GCC compiles it: the position summed corner by corner, each product fused
/// into the sum; the Jacobian's first two rows (a vector of two) likewise from a first
/// rounded product; its last row a pairwise sum whose pairs fuse their second product.
void evaluate(const TrilinearLanes& in, const V u[3], Evaluation& e) {
  V w[8], dw[8][3];
  weights(u, w, dw);
  V q[3][8];
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 8; ++c) q[i][c] = _mm256_load_pd(in.corners[i][c]);
  for (int i = 0; i < 3; ++i) {
    V x = fma(w[0], q[i][0], _mm256_setzero_pd());
    for (int c = 1; c < 8; ++c) x = fma(w[c], q[i][c], x);
    e.r[i] = sub(x, _mm256_load_pd(in.x[i]));
  }
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 2; ++i) {
      V sum = mul(q[i][0], dw[0][j]);
      for (int c = 1; c < 8; ++c) sum = fma(q[i][c], dw[c][j], sum);
      e.J[i][j] = sum;
    }
    V pair[4];
    for (int p = 0; p < 4; ++p) pair[p] = fma(q[2][2 * p + 1], dw[2 * p + 1][j], mul(q[2][2 * p], dw[2 * p][j]));
    e.J[2][j] = add(add(pair[0], pair[1]), add(pair[2], pair[3]));
  }
}

/// r.norm(): (r0^2 + r1^2), then r2^2 fused into it.
V norm(const V r[3]) { return _mm256_sqrt_pd(fma(r[2], r[2], add(mul(r[0], r[0]), mul(r[1], r[1])))); }

/// Eigen's 3 x 3 determinant by cofactors of the first row, fused as GCC fuses it.
V determinant(const V J[3][3]) {
  const V c0 = fms(J[1][1], J[2][2], mul(J[1][2], J[2][1]));
  const V c1 = fms(J[2][2], J[1][0], mul(J[1][2], J[2][0]));
  const V c2 = fms(J[2][1], J[1][0], mul(J[1][1], J[2][0]));
  return fma(c2, J[0][2], fms(c0, J[0][0], mul(c1, J[0][1])));
}

/// Swaps rows a and b of lu and x in the lanes of `mask`.
void swap_rows(V lu[3][3], V x[3], int a, int b, V mask) {
  for (int j = 0; j < 3; ++j) {
    const V ra = lu[a][j];
    lu[a][j] = blend(ra, lu[b][j], mask), lu[b][j] = blend(lu[b][j], ra, mask);
  }
  const V xa = x[a];
  x[a] = blend(xa, x[b], mask), x[b] = blend(x[b], xa, mask);
}

/// Divides column k below the pivot by it, where the pivot is not zero.
void divide_below(V lu[3][3], int k) {
  const V nonzero = where<_CMP_NEQ_UQ>(lu[k][k], _mm256_setzero_pd());
  for (int i = k + 1; i < 3; ++i) lu[i][k] = blend(lu[i][k], _mm256_div_pd(lu[i][k], lu[k][k]), nonzero);
}

/// pivoted_solve(J, r), lane by lane: the pivots chosen as it chooses them (first largest),
/// and its fused products.
void solve(const V J[3][3], const V r[3], V x[3]) {
  V lu[3][3];
  for (int i = 0; i < 3; ++i) {
    x[i] = r[i];
    for (int j = 0; j < 3; ++j) lu[i][j] = J[i][j];
  }
  const V row1 = where<_CMP_GT_OQ>(magnitude(lu[1][0]), magnitude(lu[0][0]));
  const V row2 = where<_CMP_GT_OQ>(magnitude(lu[2][0]), blend(magnitude(lu[0][0]), magnitude(lu[1][0]), row1));
  swap_rows(lu, x, 0, 1, _mm256_andnot_pd(row2, row1));
  swap_rows(lu, x, 0, 2, row2);
  divide_below(lu, 0);
  for (int j = 1; j < 3; ++j)
    for (int i = 1; i < 3; ++i) lu[i][j] = fnma(lu[i][0], lu[0][j], lu[i][j]);
  swap_rows(lu, x, 1, 2, where<_CMP_GT_OQ>(magnitude(lu[2][1]), magnitude(lu[1][1])));
  divide_below(lu, 1);
  lu[2][2] = fnma(lu[2][1], lu[1][2], lu[2][2]);
  x[1] = fnma(lu[1][0], x[0], x[1]);
  x[2] = _mm256_div_pd(sub(x[2], fma(lu[2][1], x[1], mul(lu[2][0], x[0]))), lu[2][2]);
  x[1] = _mm256_div_pd(fnma(lu[1][2], x[2], x[1]), lu[1][1]);
  x[0] = _mm256_div_pd(sub(x[0], fma(lu[0][2], x[2], mul(lu[0][1], x[1]))), lu[0][0]);
}

/// The cells' sizes, as inverse_trilinear measures them: the largest extent of a coordinate.
V cell_scale(const TrilinearLanes& in) {
  V scale = _mm256_setzero_pd();
  for (int i = 0; i < 3; ++i) {
    V high = _mm256_load_pd(in.corners[i][0]), low = high;
    for (int c = 1; c < 8; ++c) {
      const V q = _mm256_load_pd(in.corners[i][c]);
      high = _mm256_max_pd(high, q), low = _mm256_min_pd(low, q);
    }
    scale = i == 0 ? sub(high, low) : _mm256_max_pd(scale, sub(high, low));
  }
  return scale;
}

/// Past this many Newton steps a lane is left to the scalar code (which allows 50); the
/// cells of the octree's locates converge within 2 or 3.
constexpr int kLaneIterations = 12;

/// Newton's method of inverse_trilinear in the four lanes, while every active lane's full
/// step reduces its residual (the scalar code's first try of its line search); a lane that
/// would halve, is singular, or has not converged is left undecided.
void newton(TrilinearLanes& lanes) {
  V u[3];
  for (int i = 0; i < 3; ++i) u[i] = _mm256_load_pd(lanes.guess[i]);
  const V scale = cell_scale(lanes);
  const V tolerance = mul(_mm256_set1_pd(1e-13), scale);
  V active = where<_CMP_GT_OQ>(scale, _mm256_setzero_pd()), decided = _mm256_setzero_pd();
  V out_u[3] = {u[0], u[1], u[2]}, out_J[3][3];
  Evaluation e;
  evaluate(lanes, u, e);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out_J[i][j] = e.J[i][j];
  V residual = norm(e.r);
  for (int iteration = 0; iteration < kLaneIterations; ++iteration) {
    const V converged = _mm256_and_pd(active, where<_CMP_LE_OQ>(residual, tolerance));
    for (int i = 0; i < 3; ++i) {
      out_u[i] = blend(out_u[i], u[i], converged);
      for (int j = 0; j < 3; ++j) out_J[i][j] = blend(out_J[i][j], e.J[i][j], converged);
    }
    decided = _mm256_or_pd(decided, converged);
    active = _mm256_andnot_pd(converged, active);
    active = _mm256_and_pd(active, where<_CMP_GT_OQ>(magnitude(determinant(e.J)), _mm256_set1_pd(1e-300)));
    if (_mm256_movemask_pd(active) == 0) break;
    V step[3], next_u[3];
    solve(e.J, e.r, step);
    for (int i = 0; i < 3; ++i) next_u[i] = sub(u[i], step[i]);
    Evaluation next;
    evaluate(lanes, next_u, next);
    const V next_residual = norm(next.r);
    active = _mm256_and_pd(active, where<_CMP_LT_OQ>(next_residual, residual));
    for (int i = 0; i < 3; ++i) {
      u[i] = blend(u[i], next_u[i], active), e.r[i] = blend(e.r[i], next.r[i], active);
      for (int j = 0; j < 3; ++j) e.J[i][j] = blend(e.J[i][j], next.J[i][j], active);
    }
    residual = blend(residual, next_residual, active);
  }
  for (int i = 0; i < 3; ++i) {
    _mm256_store_pd(lanes.u[i], out_u[i]);
    for (int j = 0; j < 3; ++j) _mm256_store_pd(lanes.dx_du[i][j], out_J[i][j]);
  }
  const int mask = _mm256_movemask_pd(decided);
  for (int lane = 0; lane < TrilinearLanes::kLanes; ++lane) lanes.decided[lane] = (mask >> lane) & 1;
}
#endif

}  // namespace

void inverse_trilinear(TrilinearLanes& lanes) {
#ifdef FFD_TRILINEAR_LANES
  newton(lanes);
#else
  solve_each(lanes);
#endif
}

}  // namespace ffd
