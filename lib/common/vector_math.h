// Transcendental functions over arrays, by SLEEF's vector functions (1 ulp): four lanes
// where the build has AVX, two (SSE2, on every x86-64) otherwise; both dispatch to the
// best variant of the CPU at run time. glibc's scalar atan2 saves and restores the
// rounding mode on every call (14 ns against SLEEF's 3.5 ns here); its asin and sincos
// are scalar. The results do not depend on the thread count or on where an array starts.
#pragma once

#include <cstddef>

namespace ffd {

/// out[i] = atan2(y[i], x[i]) for i < n.
void atan2_all(const double* y, const double* x, double* out, std::size_t n);
/// out[i] = asin(x[i]) for i < n.
void asin_all(const double* x, double* out, std::size_t n);
/// s[i] = sin(x[i]), c[i] = cos(x[i]) for i < n.
void sincos_all(const double* x, double* s, double* c, std::size_t n);

}  // namespace ffd
