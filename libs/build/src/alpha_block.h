#pragma once
// BC4 blocks (a BC5 block is two): the 8-value mode between the block's maximum and minimum,
// each texel's index the nearest of the eight (Fabian Giesen's exact index arithmetic, as in
// stb_dxt). The same bytes as stb_dxt's encoder, faster: a textured build encodes tens of
// millions of blocks, and stb_dxt's branches on every texel and byte-at-a-time bit writer made
// them an eighth of its time. With SSE2 (every x86-64) a block's 16 texels are worked on at
// once; elsewhere the portable loop below does the same arithmetic.

#include <algorithm>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace terralod {
namespace alpha_block {

struct Range {
  int mn, mx;
  int dist() const { return mx - mn; }
  // Added to 7 x texel, this places the texel on the linear scale 0 (min) .. 7 (max) so that
  // the thresholds below round it to the nearest step.
  int bias() const { return (dist() < 8 ? dist() - 1 : dist() / 2 + 2) - 7 * mn; }
};

// The texel's linear step (0 = min, 7 = max) turned into BC4's index order (0 and 1 are the
// end points, max first).
inline int indexOfStep(int step) {
  const int index = -step & 7;
  return index ^ (index < 2 ? 1 : 0);
}

// 16 three-bit indices, one per byte of `lo` (texels 0-7) and `hi` (8-15), packed as BC4
// stores them: texel i at bits 3i.
inline uint64_t packIndices(uint64_t lo, uint64_t hi) {
  auto pack8 = [](uint64_t x) {
    x = (x & 0x0007000700070007ull) | ((x >> 5) & 0x0038003800380038ull);
    x = (x & 0x0000003F0000003Full) | ((x >> 10) & 0x00000FC000000FC0ull);
    return (x & 0xFFFull) | ((x >> 20) & 0xFFF000ull);
  };
  return pack8(lo) | (pack8(hi) << 24);
}

inline void store(uint8_t* dest, Range r, uint64_t bits) {
  dest[0] = uint8_t(r.mx);
  dest[1] = uint8_t(r.mn);
  for (int k = 0; k < 6; ++k) dest[2 + k] = uint8_t(bits >> (8 * k));
}

}  // namespace alpha_block

/// The portable encoder: the 16 texels at src[0], src[stride], ... src[15 * stride] (4 rows
/// of 4) into dest[0 .. 7].
template <int stride>
inline void encodeAlphaBlockPortable(uint8_t* dest, const uint8_t* src) {
  alpha_block::Range r{src[0], src[0]};
  for (int i = 1; i < 16; ++i) {
    r.mn = std::min<int>(r.mn, src[i * stride]);
    r.mx = std::max<int>(r.mx, src[i * stride]);
  }
  const int dist = r.dist(), bias = r.bias();
  uint64_t bits = 0;
  for (int i = 0; i < 16; ++i) {
    int a = 7 * src[i * stride] + bias, step = 0;
    if (a >= 4 * dist) step += 4, a -= 4 * dist;
    if (a >= 2 * dist) step += 2, a -= 2 * dist;
    step += a >= dist ? 1 : 0;
    bits |= uint64_t(alpha_block::indexOfStep(step)) << (3 * i);
  }
  alpha_block::store(dest, r, bits);
}

#if defined(__SSE2__)
namespace alpha_block {

// The block of 16 texels in `v`'s bytes.
inline void encodeVector(uint8_t* dest, __m128i v) {
  __m128i mn = _mm_min_epu8(v, _mm_srli_si128(v, 8)), mx = _mm_max_epu8(v, _mm_srli_si128(v, 8));
  mn = _mm_min_epu8(mn, _mm_srli_si128(mn, 4));
  mx = _mm_max_epu8(mx, _mm_srli_si128(mx, 4));
  mn = _mm_min_epu8(mn, _mm_srli_si128(mn, 2));
  mx = _mm_max_epu8(mx, _mm_srli_si128(mx, 2));
  mn = _mm_min_epu8(mn, _mm_srli_si128(mn, 1));
  mx = _mm_max_epu8(mx, _mm_srli_si128(mx, 1));
  const Range r{_mm_cvtsi128_si32(mn) & 0xFF, _mm_cvtsi128_si32(mx) & 0xFF};
  const int dist = r.dist();
  const __m128i zero = _mm_setzero_si128(), bias = _mm_set1_epi16(int16_t(r.bias()));
  // a >= t is a > t - 1: the thresholds less one.
  const __m128i below4 = _mm_set1_epi16(int16_t(4 * dist - 1)),
                below2 = _mm_set1_epi16(int16_t(2 * dist - 1)),
                below1 = _mm_set1_epi16(int16_t(dist - 1));
  const __m128i four = _mm_set1_epi16(4), two = _mm_set1_epi16(2), one = _mm_set1_epi16(1),
                seven = _mm_set1_epi16(7), dist4 = _mm_set1_epi16(int16_t(4 * dist)),
                dist2 = _mm_set1_epi16(int16_t(2 * dist));
  auto indices = [&](__m128i texels) {
    __m128i a = _mm_add_epi16(_mm_sub_epi16(_mm_slli_epi16(texels, 3), texels), bias);
    __m128i t = _mm_cmpgt_epi16(a, below4);
    __m128i step = _mm_and_si128(t, four);
    a = _mm_sub_epi16(a, _mm_and_si128(t, dist4));
    t = _mm_cmpgt_epi16(a, below2);
    step = _mm_add_epi16(step, _mm_and_si128(t, two));
    a = _mm_sub_epi16(a, _mm_and_si128(t, dist2));
    step = _mm_sub_epi16(step, _mm_cmpgt_epi16(a, below1));  // true is -1
    const __m128i index = _mm_and_si128(_mm_sub_epi16(zero, step), seven);
    return _mm_xor_si128(index, _mm_and_si128(_mm_cmpgt_epi16(two, index), one));
  };
  const __m128i packed =
      _mm_packus_epi16(indices(_mm_unpacklo_epi8(v, zero)), indices(_mm_unpackhi_epi8(v, zero)));
  const uint64_t lo = uint64_t(_mm_cvtsi128_si64(packed));
  const uint64_t hi = uint64_t(_mm_cvtsi128_si64(_mm_unpackhi_epi64(packed, packed)));
  store(dest, r, packIndices(lo, hi));
}

}  // namespace alpha_block
#endif

/// A BC4 block of 16 one-byte texels (4 rows of 4) into dest[0 .. 7].
inline void encodeBc4Block(uint8_t* dest, const uint8_t* src) {
#if defined(__SSE2__)
  alpha_block::encodeVector(dest, _mm_loadu_si128(reinterpret_cast<const __m128i*>(src)));
#else
  encodeAlphaBlockPortable<1>(dest, src);
#endif
}

/// A BC5 block of 16 two-byte texels (x, y interleaved) into dest[0 .. 15].
inline void encodeBc5Block(uint8_t* dest, const uint8_t* src) {
#if defined(__SSE2__)
  const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(src)),
                b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(src + 16));
  const __m128i low = _mm_set1_epi16(0xFF);
  alpha_block::encodeVector(dest, _mm_packus_epi16(_mm_and_si128(a, low), _mm_and_si128(b, low)));
  alpha_block::encodeVector(dest + 8, _mm_packus_epi16(_mm_srli_epi16(a, 8), _mm_srli_epi16(b, 8)));
#else
  encodeAlphaBlockPortable<2>(dest, src);
  encodeAlphaBlockPortable<2>(dest + 8, src + 1);
#endif
}

}  // namespace terralod
