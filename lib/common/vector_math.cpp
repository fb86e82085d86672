#include "common/vector_math.h"

#include <x86intrin.h>
#include <sleef.h>

#include <algorithm>

namespace ffd {
namespace {

#ifdef __AVX__
constexpr std::size_t kLanes = 4;
#else
constexpr std::size_t kLanes = 2;
#endif

/// Applies `lanes` (kLanes inputs to kLanes outputs, `inputs` arrays in, `outputs` out) to
/// every full group, then to the tail padded with copies of its first value.
template <int Inputs, int Outputs, class Lanes>
void over_lanes(const double* const (&in)[Inputs], double* const (&out)[Outputs], std::size_t n, Lanes lanes) {
  std::size_t i = 0;
  for (; i + kLanes <= n; i += kLanes) {
    const double* a[Inputs];
    double* b[Outputs];
    for (int k = 0; k < Inputs; ++k) a[k] = in[k] + i;
    for (int k = 0; k < Outputs; ++k) b[k] = out[k] + i;
    lanes(a, b);
  }
  if (i == n) return;
  double pad_in[Inputs][kLanes], pad_out[Outputs][kLanes];
  const double* a[Inputs];
  double* b[Outputs];
  for (int k = 0; k < Inputs; ++k) {
    std::fill(pad_in[k], pad_in[k] + kLanes, in[k][i]);
    std::copy(in[k] + i, in[k] + n, pad_in[k]);
    a[k] = pad_in[k];
  }
  for (int k = 0; k < Outputs; ++k) b[k] = pad_out[k];
  lanes(a, b);
  for (int k = 0; k < Outputs; ++k) std::copy(pad_out[k], pad_out[k] + (n - i), out[k] + i);
}

}  // namespace

void atan2_all(const double* y, const double* x, double* out, std::size_t n) {
  over_lanes<2, 1>({y, x}, {out}, n, [](const double* const* a, double* const* b) {
#ifdef __AVX__
    _mm256_storeu_pd(b[0], Sleef_atan2d4_u10(_mm256_loadu_pd(a[0]), _mm256_loadu_pd(a[1])));
#else
    _mm_storeu_pd(b[0], Sleef_atan2d2_u10(_mm_loadu_pd(a[0]), _mm_loadu_pd(a[1])));
#endif
  });
}

void asin_all(const double* x, double* out, std::size_t n) {
  over_lanes<1, 1>({x}, {out}, n, [](const double* const* a, double* const* b) {
#ifdef __AVX__
    _mm256_storeu_pd(b[0], Sleef_asind4_u10(_mm256_loadu_pd(a[0])));
#else
    _mm_storeu_pd(b[0], Sleef_asind2_u10(_mm_loadu_pd(a[0])));
#endif
  });
}

void sincos_all(const double* x, double* s, double* c, std::size_t n) {
  over_lanes<1, 2>({x}, {s, c}, n, [](const double* const* a, double* const* b) {
#ifdef __AVX__
    const Sleef___m256d_2 r = Sleef_sincosd4_u10(_mm256_loadu_pd(a[0]));
    _mm256_storeu_pd(b[0], r.x);
    _mm256_storeu_pd(b[1], r.y);
#else
    const Sleef___m128d_2 r = Sleef_sincosd2_u10(_mm_loadu_pd(a[0]));
    _mm_storeu_pd(b[0], r.x);
    _mm_storeu_pd(b[1], r.y);
#endif
  });
}

}  // namespace ffd
