// The detail of one block of slots in their frames (normal_detail.h), row by row, with its
// fused multiply-adds written out (detail_rows.cpp), so that its bits do not depend on the
// loop around it or on how the compiler vectorizes it.
#pragma once

namespace ffd {

/// Slots per block: the length of every row below.
constexpr int kDetailRowLength = 128;

/// A block's rows x, y, z (each kDetailRowLength long): the coefficients (α, β, γ) in `c`,
/// the frames' normal n, tangent t and bitangent b, and one flag per slot (0 or 1). Writes
/// detail[r][j] = c[r][j] where flag j is set (a degenerate frame), else
/// α n_r + β t_r + γ b_r, rounded as fma(β, t_r, α n_r) + γ b_r in rows x and y and as
/// fma(γ, b_r, fma(β, t_r, α n_r)) in row z: how GCC 12 fused the column-at-a-time loop
/// that this replaces, in the default build (AVX-512), so that its outputs kept their bits.
void detail_rows(const double* const c[3], const double* const n[3], const double* const t[3],
                 const double* const b[3], const unsigned char* flat, double* const detail[3]);

}  // namespace ffd
