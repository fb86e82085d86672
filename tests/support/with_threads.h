// Runs a piece of a test with a given OpenMP thread count, for the tests that check the
// same result at any count.
#pragma once

#include <omp.h>

namespace ffd::test {

/// f() with `threads` OpenMP threads; the count in force before is restored after.
template <class F>
auto with_threads(int threads, F f) {
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
  auto result = f();
  omp_set_num_threads(before);
  return result;
}

}  // namespace ffd::test
