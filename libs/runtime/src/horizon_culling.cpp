#include "terralod/runtime/horizon_culling.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>

namespace terralod {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// The angular margin, in pixels (a pixel spans at most 1/K radians anywhere in the image).
constexpr double kMarginPixels = 1.0;
// An occluder hides only what lies farther than its far corner by this fraction (depth
// precision, interpolation), and only with the eye this many near planes away from every chunk.
constexpr double kDepthMargin = 1e-3;
constexpr double kNearPlanes = 4.0;
// Occluders: each selected chunk and its descendants down to this many levels below it.
constexpr int kOccluderDepth = 3;

struct Rect {
  double x0, y0, x1, y1;
};

Rect footprint(const ChunkNode& n, double grow = 0.0) {
  return {n.box.min[0] - grow, n.box.min[1] - grow, n.box.max[0] + grow, n.box.max[1] + grow};
}

bool overlaps(const Rect& a, const Rect& b) {
  return a.x0 <= b.x1 && b.x0 <= a.x1 && a.y0 <= b.y1 && b.y0 <= a.y1;
}

bool contains(const Rect& r, const glm::dvec3& p) {
  return p.x >= r.x0 && p.x <= r.x1 && p.y >= r.y0 && p.y <= r.y1;
}

double nearestDistance(const Rect& r, const glm::dvec3& p) {
  const double dx = std::max({r.x0 - p.x, p.x - r.x1, 0.0});
  const double dy = std::max({r.y0 - p.y, p.y - r.y1, 0.0});
  return std::hypot(dx, dy);
}

double farthestDistance(const Rect& r, const glm::dvec3& p) {
  return std::hypot(std::max(p.x - r.x0, r.x1 - p.x), std::max(p.y - r.y0, r.y1 - p.y));
}

// The azimuths (radians, a0 <= a1 < a0 + pi) a rectangle that does not contain the eye spans.
std::pair<double, double> azimuthRange(const Rect& r, const glm::dvec3& eye) {
  const double cx = 0.5 * (r.x0 + r.x1) - eye.x, cy = 0.5 * (r.y0 + r.y1) - eye.y;
  const double centre = std::atan2(cy, cx);
  double lo = 0.0, hi = 0.0;
  for (const double x : {r.x0, r.x1})
    for (const double y : {r.y0, r.y1}) {
      const double vx = x - eye.x, vy = y - eye.y;
      const double a = std::atan2(cx * vy - cy * vx, cx * vx + cy * vy);
      lo = std::min(lo, a);
      hi = std::max(hi, a);
    }
  return {centre + lo, centre + hi};
}

// The azimuths in [0, 2 pi) of the corners a rectangle that does not contain the eye spans
// from and to (counter-clockwise). A corner two rectangles share gets the same value in both.
std::pair<double, double> cornerAzimuths(const Rect& r, const glm::dvec3& eye) {
  const double centre = std::atan2(0.5 * (r.y0 + r.y1) - eye.y, 0.5 * (r.x0 + r.x1) - eye.x);
  double lo = 0.0, hi = 0.0, loRel = std::numeric_limits<double>::infinity(), hiRel = -loRel;
  for (const double x : {r.x0, r.x1})
    for (const double y : {r.y0, r.y1}) {
      double a = std::atan2(y - eye.y, x - eye.x);
      if (a < 0.0) a += kTwoPi;
      if (a >= kTwoPi) a = 0.0;
      const double rel = std::remainder(a - centre, kTwoPi);
      if (rel < loRel) loRel = rel, lo = a;
      if (rel > hiRel) hiRel = rel, hi = a;
    }
  return {lo, hi};
}

// The box selection culls with: skirts hang below the surface's box.
Box cullingBox(const ChunkNode& n) {
  Box b = n.box;
  b.min[2] = std::min(b.min[2], n.skirtBottom);
  return b;
}

// Distance along a direction component `d` to the plane `offset` away; the limit 0 when the
// plane passes through the eye, +-inf for a direction parallel to it (d a signed zero).
double slabDistance(double offset, double d) {
  return offset == 0.0 ? 0.0 : offset / d;
}

// The horizon angle a rectangle occluder gives the rays between two directions of one bin
// (quarter `quarter`, both hitting the rectangle), or -inf.
double occluderAngle(const Rect& r, const glm::dvec3& eye, double dz, int quarter,
                     std::array<glm::dvec2, 2> directions) {
  // The signs of the direction within the bin (constant: no bin straddles an axis). A component
  // of the other sign or zero is a rounding of the axis: a signed zero of the bin's sign.
  const double sx = quarter == 0 || quarter == 3 ? 1.0 : -1.0;
  const double sy = quarter <= 1 ? 1.0 : -1.0;
  double enter = -std::numeric_limits<double>::infinity();
  double exit = std::numeric_limits<double>::infinity();
  for (const glm::dvec2& d : directions) {
    const double dx = d.x * sx > 0.0 ? d.x : std::copysign(0.0, sx);
    const double dy = d.y * sy > 0.0 ? d.y : std::copysign(0.0, sy);
    // Each slab distance is monotonic over the bin: its extremes are at the ends.
    enter = std::max({enter, slabDistance((sx > 0 ? r.x0 : r.x1) - eye.x, dx),
                      slabDistance((sy > 0 ? r.y0 : r.y1) - eye.y, dy)});
    exit = std::min({exit, slabDistance((sx > 0 ? r.x1 : r.x0) - eye.x, dx),
                     slabDistance((sy > 0 ? r.y1 : r.y0) - eye.y, dy)});
  }
  // Every ray is in the footprint at its exit (the farthest point, best below the eye) and at
  // max(enter, 0) (the nearest, best above it): the horizon is the worst over the rays.
  if (!std::isfinite(enter) || !std::isfinite(exit) || !(exit > 0.0))
    return -std::numeric_limits<double>::infinity();
  if (dz < 0.0) return std::atan(dz / exit);
  if (enter > 0.0) return std::atan(dz / enter);
  return -std::numeric_limits<double>::infinity();  // (the eye below an occluder around it)
}

}  // namespace

HorizonCuller::HorizonCuller(int bins) : mBins(bins) {
  assert(bins >= 4 && bins % 4 == 0);
  mCos.resize(size_t(bins) + 1);
  mSin.resize(size_t(bins) + 1);
  for (int k = 0; k <= bins; ++k) {
    const double a = kTwoPi * double(k) / double(bins);
    mCos[size_t(k)] = std::cos(a);
    mSin[size_t(k)] = std::sin(a);
    if (k % (bins / 4) == 0) {  // exactly on an axis
      const int quarter = (k / (bins / 4)) % 4;
      mCos[size_t(k)] = quarter == 0 ? 1.0 : quarter == 2 ? -1.0 : 0.0;
      mSin[size_t(k)] = quarter == 1 ? 1.0 : quarter == 3 ? -1.0 : 0.0;
    }
  }
  mHorizon.resize(size_t(bins));
  mPartials.resize(size_t(bins) * 4);
}

bool HorizonCuller::eyeOverDrawnColumn(const ChunkTree& tree, const View& view,
                                       uint32_t node) const {
  const ChunkNode& n = tree.node(node);
  if (mSelected[node]) return true;  // its surface is checked with the others near the eye
  // A box no pixel ray enters, which the eye is outside of: it must be above it.
  if (!boxInFrustum(view, cullingBox(n))) return view.camera.eye.z > n.box.max[2];
  // Split by the selection: every child under the eye decides (a leaf here drew nothing).
  bool over = false;
  for (uint32_t c = n.firstChild; c < n.firstChild + n.childCount; ++c) {
    if (!contains(footprint(tree.node(c)), view.camera.eye)) continue;
    if (!eyeOverDrawnColumn(tree, view, c)) return false;
    over = true;
  }
  return over;
}

static double sourceHeightBound(const ChunkTree& tree, uint32_t node, const Rect& area) {
  const ChunkNode& n = tree.node(node);
  // The node's surface lies within δ of every source sample of its footprint, below its top.
  const double own = n.box.max[2] + tree.levelError(n.level);
  double children = -std::numeric_limits<double>::infinity();
  bool any = false;
  for (uint32_t c = n.firstChild; c < n.firstChild + n.childCount; ++c)
    if (overlaps(footprint(tree.node(c)), area)) {
      children = std::max(children, sourceHeightBound(tree, c, area));
      any = true;
    }
  return any ? std::min(own, children) : own;
}

void HorizonCuller::addGrid(const ChunkTree& tree, const ChunkNode& n, const OccluderGrid& grid,
                            const glm::dvec3& eye) {
  // A cell can raise a bin's horizon only above the lowest horizon of the bins the chunk spans
  // (horizons only rise): the others are left out (which only ever culls less).
  const Rect whole = footprint(n);
  double lowest = -std::numeric_limits<double>::infinity();
  if (!contains(whole, eye)) {
    const double width = kTwoPi / double(mBins);
    const auto [a0, a1] = azimuthRange(whole, eye);
    lowest = std::numeric_limits<double>::infinity();
    for (int64_t k = int64_t(std::floor(a0 / width)); k <= int64_t(std::floor(a1 / width)); ++k)
      lowest = std::min(lowest, mHorizon[size_t(((k % mBins) + mBins) % mBins)]);
  }
  const double lowestSlope = lowest > -0.5 * std::numbers::pi
                                 ? std::tan(lowest)
                                 : -std::numeric_limits<double>::infinity();
  const double sx = tree.spacing()[0], sy = tree.spacing()[1];
  for (uint32_t j = 0; j < grid.cellsY; ++j) {
    const double y0 = n.box.min[1] + grid.rowY(j) * sy, y1 = n.box.min[1] + grid.rowY(j + 1) * sy;
    for (uint32_t i = 0; i < grid.cellsX; ++i) {
      const double top = double(grid.floors[size_t(j) * grid.cellsX + i]);
      if (!(top > n.box.min[2])) continue;  // no better than the chunk's box
      const Rect cell{n.box.min[0] + grid.columnX(i) * sx, y0,
                      n.box.min[0] + grid.columnX(i + 1) * sx, y1};
      // Below the eye a cell's angle is at most atan(dz / its farthest point).
      const double dz = top - eye.z;
      if (dz < 0.0 && !contains(cell, eye) && dz / farthestDistance(cell, eye) <= lowestSlope)
        continue;
      addSolid(cell.x0, cell.y0, cell.x1, cell.y1, top, eye);
    }
  }
}

void HorizonCuller::addOccluders(const ChunkTree& tree, uint32_t node, const glm::dvec3& eye,
                                 const OccluderGrid* grid) {
  const ChunkNode& n = tree.node(node);
  addSolid(n.box.min[0], n.box.min[1], n.box.max[0], n.box.max[1], n.box.min[2], eye);
  if (grid && !grid->empty()) {
    addGrid(tree, n, *grid, eye);
    return;
  }
  // Finer solids under the same surface: over a descendant's footprint the chunk's surface is
  // within 2 δ (morphed to the parent) plus both height steps (<= 3/4 δ) of the source
  // samples there, which are within the descendant's δ of its surface, above its minZ.
  const double below = 2.75 * tree.levelError(n.level);
  mStack.clear();
  for (uint32_t c = n.firstChild; c < n.firstChild + n.childCount; ++c) mStack.push_back(c);
  while (!mStack.empty()) {
    const uint32_t d = mStack.back();
    mStack.pop_back();
    const ChunkNode& m = tree.node(d);
    const double top = m.box.min[2] - tree.levelError(m.level) - below;
    if (top > n.box.min[2])
      addSolid(m.box.min[0], m.box.min[1], m.box.max[0], m.box.max[1], top, eye);
    if (m.level < n.level + kOccluderDepth)
      for (uint32_t c = m.firstChild; c < m.firstChild + m.childCount; ++c) mStack.push_back(c);
  }
}

void HorizonCuller::addSolid(double x0, double y0, double x1, double y1, double top,
                             const glm::dvec3& eye) {
  const Rect r{x0, y0, x1, y1};
  const double dz = top - eye.z;
  const double width = kTwoPi / double(mBins);
  const auto boundary = [&](int64_t k) {
    const size_t i = size_t(((k % mBins) + mBins) % mBins);
    return glm::dvec2(mCos[i], mSin[i]);
  };
  const auto quarterOf = [&](int64_t k) {
    return int(4 * (((k % mBins) + mBins) % mBins) / mBins);
  };
  const auto full = [&](int64_t k) {
    const size_t b = size_t(((k % mBins) + mBins) % mBins);
    mHorizon[b] = std::max(mHorizon[b],
                           occluderAngle(r, eye, dz, quarterOf(k), {boundary(k), boundary(k + 1)}));
  };
  if (contains(r, eye)) {
    for (int64_t k = 0; k < mBins; ++k) full(k);
    return;
  }
  // Every ray between the extreme corners' azimuths hits the footprint: the bins strictly
  // between are covered whole, the two at the ends in part (kept to pair with a neighbour's).
  const auto [a0, a1] = cornerAzimuths(r, eye);
  const int64_t k0 = std::min(int64_t(a0 / width), int64_t(mBins - 1));
  int64_t k1 = std::min(int64_t(a1 / width), int64_t(mBins - 1));
  if (k1 < k0) k1 += mBins;
  if (k1 == k0) return;
  for (int64_t k = k0 + 1; k < k1; ++k) full(k);
  const glm::dvec2 d0{std::cos(a0), std::sin(a0)}, d1{std::cos(a1), std::sin(a1)};
  addPartial(size_t(k0), a0 - double(k0) * width, false,
             occluderAngle(r, eye, dz, quarterOf(k0), {d0, boundary(k0 + 1)}));
  addPartial(size_t(k1 % mBins), a1 - double(k1 % mBins) * width, true,
             occluderAngle(r, eye, dz, quarterOf(k1), {boundary(k1), d1}));
}

void HorizonCuller::addPartial(size_t bin, double offset, bool fromStart, double angle) {
  if (!(angle > -std::numeric_limits<double>::infinity())) return;
  // Covered from the bin's start up to `offset`, or from `offset` to its end; two such parts
  // that meet cover the bin with the lower of their angles.
  Partial* mine = &mPartials[bin * 4 + (fromStart ? 0 : 2)];
  const Partial* other = &mPartials[bin * 4 + (fromStart ? 2 : 0)];
  for (int i = 0; i < 2; ++i)
    if (fromStart ? other[i].offset <= offset : offset <= other[i].offset)
      mHorizon[bin] = std::max(mHorizon[bin], std::min(angle, other[i].angle));
  // Keep the highest and the widest.
  const bool wider = fromStart ? offset > mine[1].offset : offset < mine[1].offset;
  if (angle > mine[0].angle) mine[0] = {offset, angle};
  if (wider) mine[1] = {offset, angle};
}

HorizonCullingStats HorizonCuller::cull(const ChunkTree& tree, const View& view,
                                        std::span<const SelectedChunk> selected, double nearPlane,
                                        std::vector<SelectedChunk>& visible,
                                        std::span<const OccluderGrid> occluders) {
  HorizonCullingStats stats;
  visible.assign(selected.begin(), selected.end());
  if (selected.empty()) return stats;
  const glm::dvec3& eye = view.camera.eye;
  // Skirt bottoms lean out under the neighbour by at most an eighth of a cell.
  const double grow = std::max(tree.spacing()[0], tree.spacing()[1]);

  // Is the eye above the drawn terrain under it, and far enough from every drawn triangle that
  // the first one a ray crosses is beyond the near plane?
  const double clearance = kNearPlanes * nearPlane *
                           std::sqrt(1.0 + view.tanHalfWidth * view.tanHalfWidth +
                                     view.tanHalfHeight * view.tanHalfHeight);
  mSelected.resize(tree.nodes().size(), 0);
  for (const SelectedChunk& s : selected) mSelected[s.node] = 1;
  bool above = false;
  for (uint32_t root = 0; root < tree.rootCount(); ++root) {
    if (!contains(footprint(tree.node(root)), eye)) continue;
    above = eyeOverDrawnColumn(tree, view, root);
    if (!above) break;
  }
  for (const SelectedChunk& s : selected) mSelected[s.node] = 0;
  // Chunks (skirts included) within `clearance` of the eye horizontally must lie that far below
  // it. Their boxes can be much taller than the ground under the eye: their surface there is
  // within 2 δ (morphed to the parent) plus both height steps (<= 3/4 δ) of the source samples,
  // which the finest nodes' boxes bound.
  const double reach = clearance + grow;
  const Rect near{eye.x - reach, eye.y - reach, eye.x + reach, eye.y + reach};
  // (The samples around: the corners of every cell a point of those chunks lies in.)
  const Rect samples{near.x0 - 2 * grow, near.y0 - 2 * grow, near.x1 + 2 * grow,
                     near.y1 + 2 * grow};
  double source = -std::numeric_limits<double>::infinity();
  for (uint32_t root = 0; above && root < tree.rootCount(); ++root)
    if (overlaps(footprint(tree.node(root)), samples))
      source = std::max(source, sourceHeightBound(tree, root, samples));
  for (size_t i = 0; above && i < selected.size(); ++i) {
    const ChunkNode& n = tree.node(selected[i].node);
    if (!overlaps(footprint(n), near)) continue;
    const double top = std::min(n.box.max[2], source + 2.75 * tree.levelError(n.level));
    above = eye.z - top >= clearance;
  }
  if (!above) return stats;
  stats.active = true;

  // Nearest first.
  mOrder.resize(selected.size());
  for (size_t i = 0; i < selected.size(); ++i)
    mOrder[i] = {nearestDistance(footprint(tree.node(selected[i].node), grow), eye), uint32_t(i)};
  std::sort(mOrder.begin(), mOrder.end(), [](const Candidate& a, const Candidate& b) {
    return a.nearest < b.nearest || (a.nearest == b.nearest && a.index < b.index);
  });
  std::fill(mHorizon.begin(), mHorizon.end(), -std::numeric_limits<double>::infinity());
  for (size_t b = 0; b < size_t(mBins); ++b) {
    const double none = -std::numeric_limits<double>::infinity();
    mPartials[b * 4] = mPartials[b * 4 + 1] = {-1.0, none};        // from the start: none
    mPartials[b * 4 + 2] = mPartials[b * 4 + 3] = {kTwoPi, none};  // to the end: none
  }
  mHidden.assign(selected.size(), 0);
  mPending.clear();
  const auto later = [](const Pending& a, const Pending& b) { return a.farthest > b.farthest; };
  const double margin = kMarginPixels / view.pixelsPerRadian;
  const double width = kTwoPi / double(mBins);

  for (const Candidate& c : mOrder) {
    // Occluders wholly nearer than this chunk (and all later ones) join the horizon.
    while (!mPending.empty() && mPending.front().farthest * (1.0 + kDepthMargin) < c.nearest) {
      std::pop_heap(mPending.begin(), mPending.end(), later);
      const uint32_t occluder = mPending.back().node;
      addOccluders(tree, occluder, eye,
                   occluder < occluders.size() ? &occluders[occluder] : nullptr);
      mPending.pop_back();
    }
    const uint32_t node = selected[c.index].node;
    const ChunkNode& n = tree.node(node);
    const Rect r = footprint(n, grow);
    mPending.push_back({farthestDistance(footprint(n), eye), node});
    std::push_heap(mPending.begin(), mPending.end(), later);
    if (!(c.nearest > 0.0)) continue;

    // The steepest ray to the chunk's top, and its steepest ray at all (for the azimuth margin:
    // near the zenith or nadir an angle moves the azimuth more).
    const double top = n.box.max[2] - eye.z;
    const double highest = std::atan(top >= 0.0 ? top / c.nearest : top / farthestDistance(r, eye));
    const double steepest = std::max(std::fabs(top), std::fabs(n.skirtBottom - eye.z)) / c.nearest;
    const double widen = margin * std::sqrt(1.0 + steepest * steepest);
    if (!(widen < 0.25)) continue;
    auto [a0, a1] = azimuthRange(r, eye);
    a0 -= widen;
    a1 += widen;
    if (!(a1 - a0 < std::numbers::pi)) continue;
    bool hidden = true;
    for (int64_t k = int64_t(std::floor(a0 / width));
         hidden && k <= int64_t(std::floor(a1 / width)); ++k)
      hidden = highest + margin < mHorizon[size_t(((k % mBins) + mBins) % mBins)];
    if (!hidden) continue;
    mHidden[c.index] = 1;
    ++stats.culled;
    stats.triangles += n.triangleCount;
    stats.skirtTriangles += n.skirtTriangleCount;
  }

  size_t kept = 0;
  for (size_t i = 0; i < selected.size(); ++i)
    if (!mHidden[i]) visible[kept++] = selected[i];
  visible.resize(kept);
  return stats;
}

}  // namespace terralod
