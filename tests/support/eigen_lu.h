// Eigen's own 3 x 3 partial-pivoting solve, the oracle of pivoted_solve
// (lib/multires/cell_coordinates.h): in the oracles' shared library (compiled with the
// library's compiler, its Eigen symbols hidden), so that the test compares with Eigen's
// code as the library's compiler builds it, not as the tests' -O1 does.
#pragma once

#ifndef FFD_ORACLE_API
#define FFD_ORACLE_API __attribute__((visibility("default")))
#endif

namespace ffd {

/// x = A.partialPivLu().solve(b) for a column-major 3 x 3 A.
FFD_ORACLE_API void eigen_partial_pivot_solve(const double A[9], const double b[3], double x[3]);

}  // namespace ffd
