// Compiled with -ffp-contract=off and without the shared precompiled header, whose own
// options would override it (lib/CMakeLists.txt): every fused multiply-add below is written
// out and no other product is fused.
#include "bcm/basis_rows.h"

#include <algorithm>
#include <cmath>

namespace ffd {

namespace {

constexpr int kRun = 64;  // vertices per run of row arithmetic (three rows fit in L1)

// Rows x, y, z of `count` vertices (kRun when the run is whole, so that it vectorizes).
template <int kCount>
void run_rows(const double* const c[3], const double* weights, long stride, const double* frames, int handles,
              int count, double (&x)[3][kRun]) {
  const int n = kCount > 0 ? kCount : count;
  for (int r = 0; r < 3; ++r)
    for (int j = 0; j < n; ++j) x[r][j] = c[r][j];
  for (int h = 0; h < handles; ++h) {
    const double* f = frames + 12 * h;  // F(r, k) = f[3 k + r]
    const double *w0 = weights + (4 * h) * stride, *w1 = w0 + stride, *w2 = w1 + stride, *w3 = w2 + stride;
    for (int r = 0; r < 2; ++r)
      for (int j = 0; j < n; ++j)
        x[r][j] = x[r][j] + std::fma(w3[j], f[9 + r], std::fma(w2[j], f[6 + r], std::fma(w1[j], f[3 + r], w0[j] * f[r])));
    for (int j = 0; j < n; ++j) {
      const double low = std::fma(w1[j], f[5], w0[j] * f[2]), high = std::fma(w3[j], f[11], w2[j] * f[8]);
      x[2][j] = x[2][j] + (high + low);
    }
  }
}

}  // namespace

void basis_rows(const double* constant, const double* weights, long stride, const double* frames, int handles,
                long begin, long end, const std::uint32_t* columns, long out_stride, double* out) {
  double x[3][kRun];
  for (long first = begin; first < end; first += kRun) {
    const int count = static_cast<int>(std::min<long>(kRun, end - first));
    const double* c[3] = {constant + first, constant + stride + first, constant + 2 * stride + first};
    if (count == kRun)
      run_rows<kRun>(c, weights + first, stride, frames, handles, count, x);
    else
      run_rows<0>(c, weights + first, stride, frames, handles, count, x);
    for (int j = 0; j < count; ++j) {
      const long i = first + j;
      double* column = out + (columns ? static_cast<long>(columns[i]) : i) * out_stride;
      for (int r = 0; r < 3; ++r) column[r] = x[r][j];
    }
  }
}

}  // namespace ffd
