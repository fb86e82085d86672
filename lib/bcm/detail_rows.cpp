// Compiled with -ffp-contract=off and without the shared precompiled header, whose own
// options would override it (lib/CMakeLists.txt): every fused multiply-add below is written
// out and no other product is fused.
#include "bcm/detail_rows.h"

#include <cmath>

namespace ffd {

namespace {

template <bool kFuseLast>
void detail_row(const double* __restrict c0, const double* __restrict c1, const double* __restrict c2,
                const double* __restrict own, const double* __restrict n, const double* __restrict t,
                const double* __restrict b, const unsigned char* __restrict flat, double* __restrict detail) {
  for (int j = 0; j < kDetailRowLength; ++j) {
    const double inner = std::fma(c1[j], t[j], c0[j] * n[j]);
    const double framed = kFuseLast ? std::fma(c2[j], b[j], inner) : inner + c2[j] * b[j];
    const double plain = own[j];  // loaded whatever the flag: a select, not a branch
    detail[j] = flat[j] ? plain : framed;
  }
}

}  // namespace

void detail_rows(const double* const c[3], const double* const n[3], const double* const t[3],
                 const double* const b[3], const unsigned char* flat, double* const detail[3]) {
  for (int r = 0; r < 3; ++r)
    (r < 2 ? detail_row<false> : detail_row<true>)(c[0], c[1], c[2], c[r], n[r], t[r], b[r], flat, detail[r]);
}

}  // namespace ffd
