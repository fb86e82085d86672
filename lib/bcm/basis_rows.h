// Eq. 6 of Botsch & Kobbelt for a run of free vertices, row by row (vectors over the
// vertices), with its fused multiply-adds written out (basis_rows.cpp), so that its bits
// do not depend on the loop around it or on how the compiler vectorizes it.
#pragma once

#include <cstdint>

namespace ffd {

/// Writes x_i = constant_i + Σ_h F_h w_hi for each vertex i in [begin, end) to
/// out[c · out_stride .. c · out_stride + 2], c = columns[i] (or i where `columns` is
/// null): `constant` is 3 rows and `weights` 4·handles rows (handle h's four at rows
/// 4h .. 4h + 3), each `stride` long; F_h is the 3 × 4 frame of handle h, column by column,
/// 12 doubles from frames + 12 h. Handle by handle, rows x and y add
/// fma(w3, F3, fma(w2, F2, fma(w1, F1, w0 F0))) and row z adds
/// fma(w3, F3, w2 F2) + fma(w1, F1, w0 F0): how GCC 12 fused the per-vertex loop that this
/// replaces, in the default build (AVX-512), so that its outputs kept their bits.
void basis_rows(const double* constant, const double* weights, long stride, const double* frames, int handles,
                long begin, long end, const std::uint32_t* columns, long out_stride, double* out);

}  // namespace ffd
