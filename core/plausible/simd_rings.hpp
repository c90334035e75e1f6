// x, y and z of four consecutive rings in AVX2 lanes: the transposition of their 12 coordinates
// (x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3, as a (3, n) array holds them), shared by the sweeps'
// blocks and the per-ring passes. Only where CHAINMAIL_AVX2_SWEEPS
// (core/plausible/plausible_blocks.hpp).
#pragma once

#include "core/plausible/plausible_blocks.hpp"

#if defined(CHAINMAIL_AVX2_SWEEPS)
#include <immintrin.h>

namespace chainmail {

struct Lanes {
  __m256d x, y, z;
};

// the three vectors of 4 consecutive rings' coordinates as lanes, and back
__attribute__((target("avx2"), always_inline)) inline Lanes to_lanes(__m256d v0, __m256d v1,
                                                                     __m256d v2) {
  const __m256d xy = _mm256_permute2f128_pd(v0, v1, 0x30);  // x0 y0 | x2 y2
  const __m256d zx = _mm256_permute2f128_pd(v0, v2, 0x21);  // z0 x1 | z2 x3
  const __m256d yz = _mm256_permute2f128_pd(v1, v2, 0x30);  // y1 z1 | y3 z3
  return {_mm256_shuffle_pd(xy, zx, 0xA), _mm256_shuffle_pd(xy, yz, 0x5),
          _mm256_shuffle_pd(zx, yz, 0xA)};
}

__attribute__((target("avx2"), always_inline)) inline Lanes load_rings(const double* p) {
  return to_lanes(_mm256_loadu_pd(p), _mm256_loadu_pd(p + 4), _mm256_loadu_pd(p + 8));
}

__attribute__((target("avx2"), always_inline)) inline void store_rings(double* p, const Lanes& r) {
  const __m256d xy = _mm256_shuffle_pd(r.x, r.y, 0x0);
  const __m256d zx = _mm256_shuffle_pd(r.z, r.x, 0xA);
  const __m256d yz = _mm256_shuffle_pd(r.y, r.z, 0xF);
  _mm256_storeu_pd(p, _mm256_permute2f128_pd(xy, zx, 0x20));
  _mm256_storeu_pd(p + 4, _mm256_permute2f128_pd(yz, xy, 0x30));
  _mm256_storeu_pd(p + 8, _mm256_permute2f128_pd(zx, yz, 0x31));
}

}  // namespace chainmail
#endif
