// The normals of a run of triangles (twice their areas long) with their fused
// multiply-adds written out (triangle_normals.cpp), so that their bits do not depend on the
// loop around them or on how the compiler vectorizes it; on AVX2 with FMA, one triangle per
// four-wide vector.
#pragma once

#include <cstdint>

namespace ffd {

/// For each triangle f in [begin, end) with corners t = corners[3f .. 3f + 2], writes
/// normals[4f .. 4f + 3] = ((p1 − p0) × (p2 − p0), 0), where p_i is points[4 t_i .. 4 t_i + 2]
/// (each point four doubles apart, its fourth zero). With e1 = p1 − p0 and e2 = p2 − p0,
/// rounded as x = fma(−e1z, e2y, e1y e2z), y = fma(−e1x, e2z, e1z e2x) and
/// z = fma(e1x, e2y, −(e1y e2x)): how GCC 12 fused Eigen's cross product in the loop that
/// this replaces, in the default build (AVX-512), so that its outputs kept their bits.
void triangle_normals(const double* points, const std::uint32_t* corners, long begin, long end, double* normals);

}  // namespace ffd
