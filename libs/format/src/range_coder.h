#pragma once
// An adaptive binary range coder (the scheme of LZMA's: 11-bit probabilities adapted by 1/32 of
// the error per bit, a 32-bit range renormalised a byte at a time, carries propagated through
// a cached byte) and signed integers coded over it in contexts. What payload version 3 of the
// chunk blobs stores its split decisions and height residuals with (docs/format.md "Version
// 7": the byte-exact definition). No Debian library offers bit-level adaptive coding; zstd
// codes bytes, and these decisions are bits whose odds depend on where in the bintree they
// fall.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace terralod::rc {

inline constexpr int kProbabilityBits = 11;
inline constexpr uint16_t kHalf = 1u << (kProbabilityBits - 1);
inline constexpr int kAdaptShift = 5;
inline constexpr uint32_t kTop = 1u << 24;

/// The odds that the next bit is 0, in 1/2048.
struct Probability {
  uint16_t p = kHalf;
};

class Encoder {
 public:
  void bit(Probability& prob, bool bit) {
    const uint32_t bound = (mRange >> kProbabilityBits) * prob.p;
    if (!bit) {
      mRange = bound;
      prob.p = uint16_t(prob.p + (((1u << kProbabilityBits) - prob.p) >> kAdaptShift));
    } else {
      mLow += bound;
      mRange -= bound;
      prob.p = uint16_t(prob.p - (prob.p >> kAdaptShift));
    }
    while (mRange < kTop) {
      mRange <<= 8;
      shiftLow();
    }
  }
  /// A bit at even odds, without a probability (LZMA's direct bits).
  void direct(bool bit) {
    mRange >>= 1;
    if (bit) mLow += mRange;
    while (mRange < kTop) {
      mRange <<= 8;
      shiftLow();
    }
  }
  /// Flushes; the coder is spent afterwards.
  std::vector<uint8_t> finish() {
    for (int i = 0; i < 5; ++i) shiftLow();
    return std::move(mOut);
  }

 private:
  void shiftLow() {
    if (uint32_t(mLow) < 0xFF000000u || (mLow >> 32) != 0) {
      const uint8_t carry = uint8_t(mLow >> 32);
      uint8_t pending = mCache;
      do {
        mOut.push_back(uint8_t(pending + carry));
        pending = 0xFF;
      } while (--mCacheSize != 0);
      mCache = uint8_t(mLow >> 24);
    }
    ++mCacheSize;
    mLow = (mLow & 0x00FFFFFFu) << 8;
  }

  uint64_t mLow = 0;
  uint32_t mRange = 0xFFFFFFFFu;
  uint8_t mCache = 0;
  uint64_t mCacheSize = 1;
  std::vector<uint8_t> mOut;
};

class Decoder {
 public:
  explicit Decoder(std::span<const uint8_t> in) : mIn(in) {
    for (int i = 0; i < 5; ++i) mCode = (mCode << 8) | next();
  }
  bool bit(Probability& prob) {
    const uint32_t bound = (mRange >> kProbabilityBits) * prob.p;
    bool bit;
    if (mCode < bound) {
      mRange = bound;
      prob.p = uint16_t(prob.p + (((1u << kProbabilityBits) - prob.p) >> kAdaptShift));
      bit = false;
    } else {
      mCode -= bound;
      mRange -= bound;
      prob.p = uint16_t(prob.p - (prob.p >> kAdaptShift));
      bit = true;
    }
    while (mRange < kTop) {
      mRange <<= 8;
      mCode = (mCode << 8) | next();
    }
    return bit;
  }
  bool direct() {
    mRange >>= 1;
    const bool bit = mCode >= mRange;
    if (bit) mCode -= mRange;
    while (mRange < kTop) {
      mRange <<= 8;
      mCode = (mCode << 8) | next();
    }
    return bit;
  }
  /// Read past the end of the input (a valid stream never does: the encoder flushes 5 bytes).
  bool failed() const { return mFailed; }
  /// Every byte of the input read (what a valid stream ends with).
  bool exhausted() const { return mPos == mIn.size(); }

 private:
  uint8_t next() {
    if (mPos < mIn.size()) return mIn[mPos++];
    mFailed = true;
    return 0;
  }
  std::span<const uint8_t> mIn;
  size_t mPos = 0;
  uint32_t mRange = 0xFFFFFFFFu, mCode = 0;
  bool mFailed = false;
};

/// A signed integer's model: whether it is 0, its sign, its magnitude's bit length (unary,
/// each step with its own odds) and the bit below the leading one (in the length's odds); the
/// lower bits direct, at even odds.
struct IntegerModel {
  static constexpr int kMaxLength = 32;
  Probability zero, sign;
  std::array<Probability, kMaxLength> longer;
  std::array<Probability, kMaxLength> second;
};

inline void encodeInteger(Encoder& e, IntegerModel& m, int32_t value) {
  e.bit(m.zero, value != 0);
  if (value == 0) return;
  e.bit(m.sign, value < 0);
  const uint32_t magnitude = value < 0 ? uint32_t(-int64_t(value)) : uint32_t(value);
  const int length = 32 - __builtin_clz(magnitude);  // 1..32
  for (int i = 1; i < length; ++i) e.bit(m.longer[size_t(i - 1)], true);
  if (length < IntegerModel::kMaxLength) e.bit(m.longer[size_t(length - 1)], false);
  if (length >= 2) e.bit(m.second[size_t(length - 1)], (magnitude >> (length - 2)) & 1u);
  for (int b = length - 3; b >= 0; --b) e.direct((magnitude >> b) & 1u);
}

/// The integer encodeInteger wrote; values outside int32 come back as 0 with the decoder
/// still consuming what was coded (the caller's range checks refuse them).
inline int64_t decodeInteger(Decoder& d, IntegerModel& m) {
  if (!d.bit(m.zero)) return 0;
  const bool negative = d.bit(m.sign);
  int length = 1;
  while (length < IntegerModel::kMaxLength && d.bit(m.longer[size_t(length - 1)])) ++length;
  uint64_t magnitude = 1;
  if (length >= 2) magnitude = (magnitude << 1) | (d.bit(m.second[size_t(length - 1)]) ? 1 : 0);
  for (int b = length - 3; b >= 0; --b) magnitude = (magnitude << 1) | (d.direct() ? 1 : 0);
  return negative ? -int64_t(magnitude) : int64_t(magnitude);
}

}  // namespace terralod::rc
