// Compiled with -ffp-contract=off and without the shared precompiled header, whose own
// options would override it (lib/CMakeLists.txt): every fused multiply-add below is written
// out and no other product is fused.
#include "bcm/triangle_normals.h"

#include <cmath>

#if defined(__AVX2__) && defined(__FMA__)
#define FFD_TRIANGLE_VECTORS 1
#include <immintrin.h>
#endif

namespace ffd {

#ifdef FFD_TRIANGLE_VECTORS

void triangle_normals(const double* points, const std::uint32_t* corners, long begin, long end, double* normals) {
  // Lane by lane (x, y, z, w): the rounded product e1(y z y w)·e2(z x x w), its sign flipped
  // in lane z, plus the fused product ∓e1(z x x w)·e2(y z y w), negative in lanes x and y.
  // Lane w multiplies the points' zeros and stays zero. Flipping a sign is exact, so this is
  // fnmadd in x and y and fmsub in z, as written in the header.
  const __m256d flip_rounded = _mm256_set_pd(0.0, -0.0, 0.0, 0.0);  // lanes w z y x
  const __m256d flip_fused = _mm256_set_pd(0.0, 0.0, -0.0, -0.0);
  for (long f = begin; f < end; ++f) {
    const std::uint32_t* t = corners + 3 * f;
    const __m256d a = _mm256_loadu_pd(points + 4 * static_cast<long>(t[0]));
    const __m256d e1 = _mm256_sub_pd(_mm256_loadu_pd(points + 4 * static_cast<long>(t[1])), a);
    const __m256d e2 = _mm256_sub_pd(_mm256_loadu_pd(points + 4 * static_cast<long>(t[2])), a);
    const __m256d e1_yzy = _mm256_permute4x64_pd(e1, _MM_SHUFFLE(3, 1, 2, 1));
    const __m256d e1_zxx = _mm256_permute4x64_pd(e1, _MM_SHUFFLE(3, 0, 0, 2));
    const __m256d e2_zxx = _mm256_permute4x64_pd(e2, _MM_SHUFFLE(3, 0, 0, 2));
    const __m256d e2_yzy = _mm256_permute4x64_pd(e2, _MM_SHUFFLE(3, 1, 2, 1));
    const __m256d rounded = _mm256_xor_pd(_mm256_mul_pd(e1_yzy, e2_zxx), flip_rounded);
    const __m256d fused = _mm256_xor_pd(e1_zxx, flip_fused);
    _mm256_storeu_pd(normals + 4 * f, _mm256_fmadd_pd(fused, e2_yzy, rounded));
  }
}

#else

void triangle_normals(const double* points, const std::uint32_t* corners, long begin, long end, double* normals) {
  for (long f = begin; f < end; ++f) {
    const std::uint32_t* t = corners + 3 * f;
    const double *a = points + 4 * static_cast<long>(t[0]), *b = points + 4 * static_cast<long>(t[1]),
                 *c = points + 4 * static_cast<long>(t[2]);
    const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double* n = normals + 4 * f;
    n[0] = std::fma(-e1[2], e2[1], e1[1] * e2[2]);
    n[1] = std::fma(-e1[0], e2[2], e1[2] * e2[0]);
    n[2] = std::fma(e1[0], e2[1], -(e1[1] * e2[0]));
    n[3] = 0.0;
  }
}

#endif

}  // namespace ffd
