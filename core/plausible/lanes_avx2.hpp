// The AVX2 lane type of core/plausible/lanes.hpp: each operation one AVX2 instruction (or a few
// shuffles), compiled for AVX2 function by function (the target attribute), so this header builds
// without -mavx2 and the code that includes it still runs on any x86; only the kernels built over
// Avx2Lanes need the instructions, and they are called only where the machine has them.
#pragma once

#include <immintrin.h>

#include <cstddef>

#include "core/plausible/lanes.hpp"

// an AVX2 function, inlined wherever it is called (from AVX2 code only)
#define CHAINMAIL_AVX2_INLINE __attribute__((target("avx2"), always_inline)) inline

namespace chainmail {

struct Avx2Lanes {
  struct Mask {
    __m256d m;  // per lane all ones or all zeros
  };
  __m256d v;

  CHAINMAIL_AVX2_INLINE static Avx2Lanes load(const double* p) { return {_mm256_loadu_pd(p)}; }
  CHAINMAIL_AVX2_INLINE static Avx2Lanes splat(double a) { return {_mm256_set1_pd(a)}; }
  CHAINMAIL_AVX2_INLINE static Avx2Lanes set(double a, double b, double c, double d) {
    return {_mm256_setr_pd(a, b, c, d)};
  }
  CHAINMAIL_AVX2_INLINE static Avx2Lanes zero() { return {_mm256_setzero_pd()}; }
  CHAINMAIL_AVX2_INLINE static Rings<Avx2Lanes> load_rings(const double* p);
  CHAINMAIL_AVX2_INLINE static Rings<Avx2Lanes> gather_rings(const double* x, const int ring[4]);
};
using Avx2Mask = Avx2Lanes::Mask;

CHAINMAIL_AVX2_INLINE void store(double* p, Avx2Lanes a) {
  _mm256_storeu_pd(p, a.v);
}
CHAINMAIL_AVX2_INLINE Avx2Lanes operator+(Avx2Lanes a, Avx2Lanes b) {
  return {_mm256_add_pd(a.v, b.v)};
}
CHAINMAIL_AVX2_INLINE Avx2Lanes operator-(Avx2Lanes a, Avx2Lanes b) {
  return {_mm256_sub_pd(a.v, b.v)};
}
CHAINMAIL_AVX2_INLINE Avx2Lanes operator*(Avx2Lanes a, Avx2Lanes b) {
  return {_mm256_mul_pd(a.v, b.v)};
}
CHAINMAIL_AVX2_INLINE Avx2Lanes operator/(Avx2Lanes a, Avx2Lanes b) {
  return {_mm256_div_pd(a.v, b.v)};
}
CHAINMAIL_AVX2_INLINE Avx2Lanes operator-(Avx2Lanes a) {
  return {_mm256_xor_pd(a.v, _mm256_set1_pd(-0.0))};
}
CHAINMAIL_AVX2_INLINE Avx2Lanes abs(Avx2Lanes a) {
  return {_mm256_andnot_pd(_mm256_set1_pd(-0.0), a.v)};
}
CHAINMAIL_AVX2_INLINE Avx2Lanes sqrt(Avx2Lanes a) {
  return {_mm256_sqrt_pd(a.v)};
}
CHAINMAIL_AVX2_INLINE Avx2Lanes lane_min(Avx2Lanes a, Avx2Lanes b) {
  return {_mm256_min_pd(a.v, b.v)};
}
CHAINMAIL_AVX2_INLINE Avx2Lanes lane_max(Avx2Lanes a, Avx2Lanes b) {
  return {_mm256_max_pd(a.v, b.v)};
}
CHAINMAIL_AVX2_INLINE Avx2Mask operator<=(Avx2Lanes a, Avx2Lanes b) {
  return {_mm256_cmp_pd(a.v, b.v, _CMP_LE_OQ)};
}
CHAINMAIL_AVX2_INLINE Avx2Mask operator>=(Avx2Lanes a, Avx2Lanes b) {
  return {_mm256_cmp_pd(a.v, b.v, _CMP_GE_OQ)};
}
CHAINMAIL_AVX2_INLINE Avx2Mask operator>(Avx2Lanes a, Avx2Lanes b) {
  return {_mm256_cmp_pd(a.v, b.v, _CMP_GT_OQ)};
}
CHAINMAIL_AVX2_INLINE Avx2Mask operator!=(Avx2Lanes a, Avx2Lanes b) {
  return {_mm256_cmp_pd(a.v, b.v, _CMP_NEQ_UQ)};
}
CHAINMAIL_AVX2_INLINE Avx2Mask not_less(Avx2Lanes a, Avx2Lanes b) {
  return {_mm256_cmp_pd(a.v, b.v, _CMP_NLT_UQ)};
}
CHAINMAIL_AVX2_INLINE Avx2Mask operator&(Avx2Mask a, Avx2Mask b) {
  return {_mm256_and_pd(a.m, b.m)};
}
CHAINMAIL_AVX2_INLINE Avx2Mask and_not(Avx2Mask a, Avx2Mask b) {
  return {_mm256_andnot_pd(a.m, b.m)};
}
CHAINMAIL_AVX2_INLINE bool all(Avx2Mask m) {
  return _mm256_movemask_pd(m.m) == 0xF;
}
CHAINMAIL_AVX2_INLINE bool any(Avx2Mask m) {
  return _mm256_movemask_pd(m.m) != 0;
}
CHAINMAIL_AVX2_INLINE Avx2Lanes blend(Avx2Mask m, Avx2Lanes yes, Avx2Lanes no) {
  return {_mm256_blendv_pd(no.v, yes.v, m.m)};
}
CHAINMAIL_AVX2_INLINE Avx2Lanes keep(Avx2Mask m, Avx2Lanes a) {
  return {_mm256_and_pd(a.v, m.m)};
}
CHAINMAIL_AVX2_INLINE Avx2Lanes unpack_lo(Avx2Lanes a, Avx2Lanes b) {
  return {_mm256_unpacklo_pd(a.v, b.v)};
}
CHAINMAIL_AVX2_INLINE Avx2Lanes unpack_hi(Avx2Lanes a, Avx2Lanes b) {
  return {_mm256_unpackhi_pd(a.v, b.v)};
}
CHAINMAIL_AVX2_INLINE void spread(Avx2Lanes a, Avx2Lanes out[3]) {
  out[0].v = _mm256_permute4x64_pd(a.v, 0x40);  // 0 0 0 1
  out[1].v = _mm256_permute4x64_pd(a.v, 0xA5);  // 1 1 2 2
  out[2].v = _mm256_permute4x64_pd(a.v, 0xFE);  // 2 3 3 3
}
CHAINMAIL_AVX2_INLINE void spread(Avx2Mask a, Avx2Mask out[3]) {
  Avx2Lanes lanes[3];
  spread(Avx2Lanes{a.m}, lanes);
  for (int k = 0; k < 3; ++k) out[k].m = lanes[k].v;
}

CHAINMAIL_AVX2_INLINE Rings<Avx2Lanes> to_rings(Avx2Lanes v0, Avx2Lanes v1, Avx2Lanes v2) {
  const __m256d xy = _mm256_permute2f128_pd(v0.v, v1.v, 0x30);  // x0 y0 | x2 y2
  const __m256d zx = _mm256_permute2f128_pd(v0.v, v2.v, 0x21);  // z0 x1 | z2 x3
  const __m256d yz = _mm256_permute2f128_pd(v1.v, v2.v, 0x30);  // y1 z1 | y3 z3
  return {{_mm256_shuffle_pd(xy, zx, 0xA)},
          {_mm256_shuffle_pd(xy, yz, 0x5)},
          {_mm256_shuffle_pd(zx, yz, 0xA)}};
}
CHAINMAIL_AVX2_INLINE Rings<Avx2Lanes> Avx2Lanes::load_rings(const double* p) {
  return to_rings(load(p), load(p + 4), load(p + 8));
}
CHAINMAIL_AVX2_INLINE void store_rings(double* p, const Rings<Avx2Lanes>& r) {
  const __m256d xy = _mm256_shuffle_pd(r.x.v, r.y.v, 0x0);
  const __m256d zx = _mm256_shuffle_pd(r.z.v, r.x.v, 0xA);
  const __m256d yz = _mm256_shuffle_pd(r.y.v, r.z.v, 0xF);
  _mm256_storeu_pd(p, _mm256_permute2f128_pd(xy, zx, 0x20));
  _mm256_storeu_pd(p + 4, _mm256_permute2f128_pd(yz, xy, 0x30));
  _mm256_storeu_pd(p + 8, _mm256_permute2f128_pd(zx, yz, 0x31));
}
// each ring loaded as x y, then z, and the four transposed
CHAINMAIL_AVX2_INLINE Rings<Avx2Lanes> Avx2Lanes::gather_rings(const double* x, const int ring[4]) {
  __m256d r[4];
  for (int l = 0; l < 4; ++l) {
    const double* const p = x + 3 * static_cast<std::ptrdiff_t>(ring[l]);
    r[l] = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p)), _mm_load_sd(p + 2), 1);
  }
  const __m256d xz01 = _mm256_unpacklo_pd(r[0], r[1]), y01 = _mm256_unpackhi_pd(r[0], r[1]);
  const __m256d xz23 = _mm256_unpacklo_pd(r[2], r[3]), y23 = _mm256_unpackhi_pd(r[2], r[3]);
  return {{_mm256_permute2f128_pd(xz01, xz23, 0x20)},
          {_mm256_permute2f128_pd(y01, y23, 0x20)},
          {_mm256_permute2f128_pd(xz01, xz23, 0x31)}};
}

}  // namespace chainmail
