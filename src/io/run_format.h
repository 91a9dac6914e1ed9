#pragma once
// The on-disk layout of an nsf run file, shared by RunWriter and RunReader so the two cannot
// drift apart. docs/OUTPUT.md describes the same layout for h5py users.
#include <array>
#include <cstddef>

#include "core/types.h"

namespace nsf::run_format {

inline constexpr const char* kFormat = "nsf-run";
// Bump when a reader of the old version could misread a new file (renamed or reinterpreted
// datasets). Adding datasets or attributes does not need a bump.
inline constexpr int kFormatVersion = 1;

// Per-frame datasets under /frames, each F×P×width doubles.
inline constexpr std::size_t kVectorWidth = 3;  // x, v
inline constexpr std::size_t kMatrixWidth = 9;  // C, F, row-major
inline constexpr std::size_t kSymWidth = 6;     // τ: xx, yy, zz, xy, yz, xz

// τ is stored as its six independent components in this order. The paper only says τ has 6 degrees
// of freedom; this order is nsf's choice; anything else that flattens τ (e.g. the stress network's
// output) should use the same one.
inline constexpr std::array<std::array<int, 2>, 6> kSymOrder = {
    {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}}};

// Pack into / unpack from a flat double buffer at out[0 .. width-1].
inline void pack_vec(const Vec3& a, double* out) {
  for (int i = 0; i < 3; ++i) out[i] = a[i];
}
inline void pack_mat(const Mat3& a, double* out) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out[3 * i + j] = a(i, j);
}
// Averages the off-diagonal pairs: the symmetric part is what the stress means, and rounding can
// leave τ a few ulps from symmetric.
inline void pack_sym(const Mat3& a, double* out) {
  for (std::size_t k = 0; k < kSymOrder.size(); ++k) {
    const auto [i, j] = kSymOrder[k];
    out[k] = 0.5 * (a(i, j) + a(j, i));
  }
}
inline Vec3 unpack_vec(const double* in) {
  return Vec3(in[0], in[1], in[2]);
}
inline Mat3 unpack_mat(const double* in) {
  Mat3 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = in[3 * i + j];
  return m;
}
inline Mat3 unpack_sym(const double* in) {
  Mat3 m;
  for (std::size_t k = 0; k < kSymOrder.size(); ++k) {
    const auto [i, j] = kSymOrder[k];
    m(i, j) = m(j, i) = in[k];
  }
  return m;
}

}  // namespace nsf::run_format
