#include "terralod/build/mosaic_builder.h"

#include <algorithm>
#include <cassert>
#include <cstring>

#include "resample_taps.h"

namespace terralod {

MosaicBuilder::MosaicBuilder(uint32_t childSize, uint32_t channels, uint32_t size,
                             std::array<bool, 4> present)
    : mChild(childSize),
      mChannels(channels),
      mSize(size),
      mSource(2 * childSize - 1),
      mPresent(present) {
  assert(present[0] && (!present[3] || (present[1] && present[2])));
  if (mSize == mSource) return;  // the mosaic itself: children are kept, then joined
  mOut = TexelTile(size, channels);
  const std::vector<Taps>& taps = tapsFor(mSource, mSize, Placement::kEdgeAligned);
  mRowClass.resize(mSize);
  mColClass.resize(mSize);
  uint32_t rowLo = mSource, rowHi = 0, colLo = mSource, colHi = 0;
  for (uint32_t i = 0; i < mSize; ++i) {
    const Taps& t = taps[i];
    mRowClass[i] = ownerOfTaps(t.first, t.weights.size(), true);
    mColClass[i] = ownerOfTaps(t.first, t.weights.size(), false);
    const uint32_t last = t.first + uint32_t(t.weights.size()) - 1;
    if (mRowClass[i] == kMixed) rowLo = std::min(rowLo, t.first), rowHi = std::max(rowHi, last);
    if (mColClass[i] == kMixed) colLo = std::min(colLo, t.first), colHi = std::max(colHi, last);
  }
  if (rowLo <= rowHi) {
    mBandRow0 = rowLo;
    mBandRows = rowHi - rowLo + 1;
    mBandRowValues.assign(size_t(mBandRows) * mSource * mChannels, 0.0f);
  }
  if (colLo <= colHi) {
    mBandCol0 = colLo;
    mBandCols = colHi - colLo + 1;
    mBandColSums.assign(size_t(mSize) * mBandCols * mChannels, 0.0f);
  }
}

// The mosaic's shared middle line belongs to the north (east) child when there is one;
// without one, the south (west) child's texels repeat to the far side.
uint8_t MosaicBuilder::rowOwner(uint32_t r) const {
  return mPresent[2] && r >= mChild - 1 ? kNorthOrEast : kSouthOrWest;
}
uint8_t MosaicBuilder::colOwner(uint32_t k) const {
  return mPresent[1] && k >= mChild - 1 ? kNorthOrEast : kSouthOrWest;
}

uint8_t MosaicBuilder::ownerOfTaps(uint32_t first, size_t count, bool rows) const {
  const uint32_t last = first + uint32_t(count) - 1;
  const uint8_t a = rows ? rowOwner(first) : colOwner(first);
  const uint8_t b = rows ? rowOwner(last) : colOwner(last);
  return a == b ? a : uint8_t(kMixed);
}

void MosaicBuilder::add(size_t quadrant, TexelTile&& child) {
  assert(mPresent[quadrant] && child.size == mChild && child.channels == mChannels);
  if (mSize == mSource) {
    mKept[quadrant] = std::move(child);
    return;
  }
  add(quadrant, static_cast<const TexelTile&>(child));
}

// Mosaic row r: for each half of the columns, the row of the child that holds it (rowOwner,
// colOwner), the last texel repeated where the east child is missing; zeros for a child that
// is not there (which trees do not make: a north-east child exists when the north and east
// ones do).
TexelTile MosaicBuilder::joinKept() {
  const uint32_t n = mChild, c = mChannels, m = mSource;
  TexelTile out;
  out.size = m;
  out.channels = c;
  out.values.reserve(size_t(m) * m * c);
  auto append = [&](const TexelTile& child, uint32_t row, uint32_t count) {
    if (child.values.empty()) {
      out.values.insert(out.values.end(), size_t(count) * c, 0.0f);
      return;
    }
    const float* in = child.at(0, row);
    const uint32_t own = std::min(count, n);
    out.values.insert(out.values.end(), in, in + size_t(own) * c);
    for (uint32_t k = own; k < count; ++k)
      out.values.insert(out.values.end(), in + size_t(n - 1) * c, in + size_t(n) * c);
  };
  for (uint32_t r = 0; r < m; ++r) {
    const uint32_t half = rowOwner(r), row = std::min(r - half * (n - 1), n - 1);
    append(mKept[half * 2], row, mPresent[1] ? n - 1 : m);
    if (mPresent[1]) append(mKept[half * 2 + 1], row, n);
  }
  return out;
}

void MosaicBuilder::add(size_t quadrant, const TexelTile& child) {
  assert(mPresent[quadrant] && child.size == mChild && child.channels == mChannels);
  if (mSize == mSource) {
    mKept[quadrant] = child;
    return;
  }
  const uint8_t hx = uint8_t(quadrant & 1), hy = uint8_t(quadrant >> 1);
  const uint32_t n = mChild, c = mChannels, ox = hx * (n - 1), oy = hy * (n - 1);
  // The mosaic's rows and columns this child holds (as rowOwner and colOwner give them): its
  // own, and beyond them the repeats standing in for a missing neighbour.
  const uint32_t k0 = ox, k1 = hx || !mPresent[1] ? mSource : n - 1;
  const uint32_t r0 = oy, r1 = hy || !mPresent[2] ? mSource : n - 1;
  // Mosaic row r's texels k0 .. k1 - 1, as placeChildren would hold them.
  std::vector<float> segment(size_t(k1 - k0) * c);
  const uint32_t held = std::min(k1, ox + n);  // k0 .. held - 1 are the child's own
  auto rowOf = [&](uint32_t r) {
    const float* in = child.at(k0 - ox, std::min(r - oy, n - 1));
    if (held == k1) return in;  // no repeats: the child's row itself
    std::memcpy(segment.data(), in, sizeof(float) * (held - k0) * c);
    for (uint32_t k = held; k < k1; ++k)
      std::memcpy(segment.data() + size_t(k - k0) * c, in + size_t(held - 1 - k0) * c,
                  sizeof(float) * c);
    return static_cast<const float*>(segment.data());
  };
  for (uint32_t r = r0; r < r1; ++r)
    if (r >= mBandRow0 && r < mBandRow0 + mBandRows)
      std::memcpy(mBandRowValues.data() + (size_t(r - mBandRow0) * mSource + k0) * c, rowOf(r),
                  sizeof(float) * (k1 - k0) * c);
  const std::vector<Taps>& taps = tapsFor(mSource, mSize, Placement::kEdgeAligned);
  // Sums over the whole width, though only k0 .. k1 - 1 are made here, so that texels index
  // them as resampleTile does.
  std::vector<float> sums(size_t(mSource) * c);
  for (uint32_t y = 0; y < mSize; ++y) {
    if (mRowClass[y] != hy) continue;
    const Taps& t = taps[y];
    float* part = sums.data() + size_t(k0) * c;
    std::fill_n(part, size_t(k1 - k0) * c, 0.0f);
    for (size_t i = 0; i < t.weights.size(); ++i)
      addWeightedRow(part, rowOf(uint32_t(t.first + i)), t.weights[i], size_t(k1 - k0) * c);
    for (uint32_t x = 0; x < mSize; ++x)
      if (mColClass[x] == hx)
        resampleTexel(mOut.at(x, y), sums.data() + size_t(taps[x].first) * c, taps[x], c);
    for (uint32_t k = std::max(k0, mBandCol0); k < std::min(k1, mBandCol0 + mBandCols); ++k)
      std::memcpy(mBandColSums.data() + (size_t(y) * mBandCols + (k - mBandCol0)) * c,
                  sums.data() + size_t(k) * c, sizeof(float) * c);
  }
}

TexelTile MosaicBuilder::finish() {
  if (mSize == mSource) {
    TexelTile out = joinKept();
    mKept = {};
    return out;
  }
  const std::vector<Taps>& taps = tapsFor(mSource, mSize, Placement::kEdgeAligned);
  const uint32_t c = mChannels;
  const size_t sourceRow = size_t(mSource) * c;
  std::vector<float> sums(sourceRow);
  for (uint32_t y = 0; y < mSize; ++y) {
    if (mRowClass[y] == kMixed) {
      // Rows across the seam: every tap row is whole by now.
      const Taps& t = taps[y];
      std::fill(sums.begin(), sums.end(), 0.0f);
      for (size_t i = 0; i < t.weights.size(); ++i)
        addWeightedRow(sums.data(),
                       mBandRowValues.data() + size_t(t.first + i - mBandRow0) * sourceRow,
                       t.weights[i], sourceRow);
      for (uint32_t x = 0; x < mSize; ++x)
        resampleTexel(mOut.at(x, y), sums.data() + size_t(taps[x].first) * c, taps[x], c);
      continue;
    }
    // Columns across the seam of a row one child made.
    const float* band = mBandColSums.data() + size_t(y) * mBandCols * c;
    for (uint32_t x = 0; x < mSize; ++x)
      if (mColClass[x] == kMixed)
        resampleTexel(mOut.at(x, y), band + size_t(taps[x].first - mBandCol0) * c, taps[x], c);
  }
  mBandRowValues = {};
  mBandColSums = {};
  return std::move(mOut);
}

}  // namespace terralod
