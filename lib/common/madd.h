// madd: a * b + c as this build's Eigen expressions compute it, for code that writes such
// an expression out by hand and must give the same bits.
#pragma once

#include <cmath>

namespace ffd {

/// Fused (one rounding) where the CPU has FMA, as Eigen's packet multiply-add and the
/// compiler's contraction do; a product and a sum otherwise.
inline double madd(double a, double b, double c) {
#ifdef __FMA__
  return std::fma(a, b, c);
#else
  return a * b + c;
#endif
}

}  // namespace ffd
