#include "terralod/build/chunk_mesher.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "terralod/format/rtin_chunk_codec.h"

namespace terralod {
namespace {

constexpr int32_t kDenseLimit = 1024;  // chunks up to this side use a dense vertex index

bool containsPoint(const BinTriangle& t, GridPoint p) {
  const int64_t d1 = orient2d(t.a, t.b, p), d2 = orient2d(t.b, t.apex, p),
                d3 = orient2d(t.apex, t.a, p);
  const bool negative = d1 < 0 || d2 < 0 || d3 < 0;
  const bool positive = d1 > 0 || d2 > 0 || d3 > 0;
  return !(negative && positive);
}

}  // namespace

ChunkMesher::ChunkMesher(const TreeLayout& layout, const ErrorBudget& budget,
                         const ActivationGrid& grid, const HeightSampler& heights)
    : mLayout(layout), mBudget(budget), mGrid(grid), mHeights(&heights) {}

template <typename Height>
uint32_t ChunkMesher::vertexIndex(ChunkMesh& mesh, GridPoint p, Height&& z, const Plane& parent) {
  const int32_t lx = p.x - mOriginX, ly = p.y - mOriginY;
  assert(lx >= 0 && ly >= 0 && lx <= mSide && ly <= mSide);
  const auto next = static_cast<uint32_t>(mesh.vertices.size());
  if (mSide <= kDenseLimit) {
    const int32_t slot = mDenseIndex.findOrAdd(size_t(ly) * (mSide + 1) + lx, int32_t(next));
    if (slot != int32_t(next)) return uint32_t(slot);
  } else {
    const uint64_t key = (uint64_t(ly) << 32) | uint32_t(lx);
    const auto [it, inserted] = mSparseIndex.try_emplace(key, next);
    if (!inserted) return it->second;
  }
  mesh.vertices.push_back({p.x, p.y, z(), parent.at(p)});
  return next;
}

double ChunkMesher::planeHeight(const BinTriangle& t, GridPoint p) const {
  const double area = double(orient2d(t.a, t.b, t.apex));
  const double wa = double(orient2d(t.b, t.apex, p)) / area;
  const double wb = double(orient2d(t.apex, t.a, p)) / area;
  const double wc = 1.0 - wa - wb;
  return wa * mHeights->at(t.a.x, t.a.y) + wb * mHeights->at(t.b.x, t.b.y) +
         wc * mHeights->at(t.apex.x, t.apex.y);
}

double ChunkMesher::surfaceHeight(int32_t level, GridPoint p) {
  const int32_t s = mLayout.chunkCells(level);
  return surfaceHeightIn(level, std::min(p.x / s, mLayout.chunksX(level) - 1),
                         std::min(p.y / s, mLayout.chunksY(level) - 1), p);
}

double ChunkMesher::surfaceHeightIn(int32_t level, int32_t ix, int32_t iy, GridPoint p) {
  if (mCachedParentLevel == level && containsPoint(mCachedParentTriangle, p))
    return planeHeight(mCachedParentTriangle, p);
  const int32_t s = mLayout.chunkCells(level);
  const auto roots = squareTriangles(ix * s, iy * s, s);
  BinTriangle t = containsPoint(roots[0], p) ? roots[0] : roots[1];
  const uint8_t needed = mBudget.activationForLevel(level);
  while (t.splittable()) {
    const GridPoint m = t.hypotenuseMidpoint();
    if (mGrid.get(m.x, m.y) < needed) break;
    t = t.children()[childContaining(t, p)];
  }
  mCachedParentTriangle = t;
  mCachedParentLevel = level;
  return planeHeight(t, p);
}

ChunkMesher::Plane ChunkMesher::planeOf(const BinTriangle& t) const {
  const double za = mHeights->at(t.a.x, t.a.y), zb = mHeights->at(t.b.x, t.b.y),
               zc = mHeights->at(t.apex.x, t.apex.y);
  const double x1 = t.b.x - t.a.x, y1 = t.b.y - t.a.y, z1 = zb - za;
  const double x2 = t.apex.x - t.a.x, y2 = t.apex.y - t.a.y, z2 = zc - za;
  const double det = x1 * y2 - x2 * y1;
  return Plane{t.a, za, (z1 * y2 - z2 * y1) / det, (x1 * z2 - x2 * z1) / det};
}

void ChunkMesher::emitTriangle(ChunkMesh& mesh, const BinTriangle& t, const Plane& parent) {
  const int32_t w = mLayout.cellsX, h = mLayout.cellsY;
  const GridPoint corners[3] = {t.a, t.b, t.apex};
  const int32_t maxX = std::max({t.a.x, t.b.x, t.apex.x}),
                maxY = std::max({t.a.y, t.b.y, t.apex.y});
  const int32_t minX = std::min({t.a.x, t.b.x, t.apex.x}),
                minY = std::min({t.a.y, t.b.y, t.apex.y});
  if (minX >= w || minY >= h) return;  // padding only

  // Triangle (a, b, c) wound counter-clockwise; za() etc. give a vertex's height, called only
  // for a new vertex. New vertices are numbered in the order the index list first names them
  // (fetch order).
  auto addTriangle = [&](GridPoint a, GridPoint b, GridPoint c, auto&& za, auto&& zb, auto&& zc) {
    const int64_t o = orient2d(a, b, c);
    if (o == 0) return;
    const uint32_t i0 = vertexIndex(mesh, a, za, parent);
    const uint32_t i1 = o > 0 ? vertexIndex(mesh, b, zb, parent) : vertexIndex(mesh, c, zc, parent);
    const uint32_t i2 = o > 0 ? vertexIndex(mesh, c, zc, parent) : vertexIndex(mesh, b, zb, parent);
    mesh.surfaceIndices.insert(mesh.surfaceIndices.end(), {i0, i1, i2});
  };

  if (maxX <= w && maxY <= h) {
    // Inside the data: a vertex's height is the data's, read once when the vertex is new.
    auto data = [this](GridPoint p) { return [this, p] { return mHeights->at(p.x, p.y); }; };
    addTriangle(t.a, t.b, t.apex, data(t.a), data(t.b), data(t.apex));
    return;
  }
  ClipVertex poly[8];
  int n = 3;
  for (int i = 0; i < 3; ++i) poly[i] = {corners[i], mHeights->at(corners[i].x, corners[i].y)};
  // Clip to x <= w, then y <= h; heights follow the triangle's plane.
  auto between = [](const ClipVertex& a, const ClipVertex& b, double f) {
    return ClipVertex{{}, a.z + f * (b.z - a.z)};
  };
  if (maxX > w) clipToLine(poly, n, true, w, between);
  if (maxY > h) clipToLine(poly, n, false, h, between);
  auto clipped = [](const ClipVertex& v) { return [&v] { return v.z; }; };
  for (int i = 1; i + 1 < n; ++i)
    addTriangle(poly[0].p, poly[i].p, poly[i + 1].p, clipped(poly[0]), clipped(poly[i]),
                clipped(poly[i + 1]));
}

void ChunkMesher::addSkirts(ChunkMesh& mesh) {
  const int32_t w = mLayout.cellsX, h = mLayout.cellsY;
  const int32_t s = mesh.side;
  for (int side = 0; side < 4; ++side) {
    const bool vertical = side == kEast || side == kWest;
    const int32_t line = side == kSouth   ? mesh.y0
                         : side == kNorth ? mesh.y0 + s
                         : side == kWest  ? mesh.x0
                                          : mesh.x0 + s;
    // No skirt on the data's own boundary (nothing lies beyond) or outside it.
    if (line == 0 || line >= (vertical ? w : h)) continue;
    std::vector<std::pair<int32_t, uint32_t>> onSide;
    for (uint32_t i = 0; i < mesh.surfaceVertexCount; ++i) {
      const MeshVertex& v = mesh.vertices[i];
      if ((vertical ? v.x : v.y) == line) onSide.emplace_back(vertical ? v.y : v.x, i);
    }
    std::sort(onSide.begin(), onSide.end());
    if (onSide.size() < 2) continue;

    // How far above the data can this side be drawn (over its whole morph range)?
    double up = 0.0;
    bool missing = false;  // a height the source could not give: poison the skirt, not hide it
    size_t segment = 0;
    for (int32_t q = onSide.front().first; q <= onSide.back().first; ++q) {
      while (segment + 2 < onSide.size() && onSide[segment + 1].first < q) ++segment;
      const auto& [qa, ia] = onSide[segment];
      const auto& [qb, ib] = onSide[segment + 1];
      const double f = double(q - qa) / double(qb - qa);
      const MeshVertex &va = mesh.vertices[ia], &vb = mesh.vertices[ib];
      const double drawn = va.z + f * (vb.z - va.z);
      // The child refines the parent, so along the side the parent's surface is linear
      // between the child's side vertices too: the fully morphed side.
      const double parent = va.morphTarget + f * (vb.morphTarget - va.morphTarget);
      const GridPoint p = vertical ? GridPoint{line, q} : GridPoint{q, line};
      const double above = std::max(drawn, parent) - mHeights->at(p.x, p.y);
      missing |= std::isnan(above) || std::isnan(drawn) || std::isnan(parent);
      up = std::max(up, above);
    }
    // ...plus how far below the data the coarsest possible neighbour across it can be.
    const int32_t coarsest = mLayout.coarsestLevelOfBorder(line, mesh.level);
    const double neighbour = mBudget.levelError[std::max(coarsest - 1, 0)];
    const double depth = missing
                             ? std::nan("")
                             : up + neighbour + mBudget.zStep[mesh.level] + mBudget.zStep[coarsest];
    mesh.skirtDepth[side] = depth;

    const auto first = static_cast<uint32_t>(mesh.vertices.size());
    for (const auto& [q, i] : onSide) {
      MeshVertex bottom = mesh.vertices[i];
      bottom.z -= depth;
      bottom.morphTarget -= depth;
      mesh.vertices.push_back(bottom);
    }
    // Skirts face outwards (counter-clockwise seen from outside the chunk), like the surface
    // seen from above, so a renderer that culls back faces keeps them. Along increasing q the south
    // and east sides wind that way as (a, a2, b2); the north and west sides need the mirror image.
    const bool mirrored = side == kNorth || side == kWest;
    for (uint32_t k = 0; k + 1 < onSide.size(); ++k) {
      const uint32_t a = onSide[k].second, b = onSide[k + 1].second;
      const uint32_t a2 = first + k, b2 = first + k + 1;
      if (mirrored)
        mesh.skirtIndices.insert(mesh.skirtIndices.end(), {a, b2, a2, a, b, b2});
      else
        mesh.skirtIndices.insert(mesh.skirtIndices.end(), {a, a2, b2, a, b2, b});
    }
  }
}

void ChunkMesher::finishSurface(ChunkMesh& mesh) {
  mesh.surfaceVertexCount = static_cast<uint32_t>(mesh.vertices.size());
  mesh.minZ = std::numeric_limits<double>::infinity();
  mesh.maxZ = -std::numeric_limits<double>::infinity();
  for (const MeshVertex& v : mesh.vertices) {
    mesh.minZ = std::min({mesh.minZ, v.z, v.morphTarget});
    mesh.maxZ = std::max({mesh.maxZ, v.z, v.morphTarget});
  }
  addSkirts(mesh);
}

ChunkSurface surfaceOf(const ChunkMesh& mesh) {
  ChunkSurface surface{mesh.level, mesh.ix, mesh.iy, {}, mesh.method};
  surface.corners.reserve(mesh.surfaceIndices.size());
  for (const uint32_t i : mesh.surfaceIndices) {
    const MeshVertex& v = mesh.vertices[i];
    surface.corners.push_back({v.x, v.y, v.z});
  }
  return surface;
}

void SurfaceStore::add(ChunkSurface surface) {
  const uint64_t k = key(surface.level, surface.ix, surface.iy);
  mByChunk.insert_or_assign(k, std::move(surface));
}

const ChunkSurface* SurfaceStore::find(int32_t level, int32_t ix, int32_t iy) const {
  const auto it = mByChunk.find(key(level, ix, iy));
  return it == mByChunk.end() ? nullptr : &it->second;
}

const ChunkMesher::Surface& ChunkMesher::surfaceOf(int32_t level, int32_t ix, int32_t iy) {
  for (const Surface& s : mSurfaces)
    if (s.level == level && s.ix == ix && s.iy == iy) return s;
  if (mShared)
    if (const ChunkSurface* shared = mShared->find(level, ix, iy)) return *shared;
  const ChunkMesh mesh = build(level, ix, iy);  // greedy levels keep their own surface
  if (!greedyAt(level)) keepSurface(mesh);
  return mSurfaces.back();
}

void ChunkMesher::keepSurface(const ChunkMesh& mesh) {
  std::erase_if(mSurfaces, [&](const Surface& s) {
    return s.level < mesh.level - 1 ||
           (s.level == mesh.level && s.ix == mesh.ix && s.iy == mesh.iy);
  });
  mSurfaces.push_back(terralod::surfaceOf(mesh));
}

std::optional<ChunkMesh> ChunkMesher::buildGreedy(ChunkMesh mesh, const Surface* parent) {
  const int32_t level = mesh.level;
  const int32_t w = std::min(mesh.side, mLayout.cellsX - mesh.x0),
                h = std::min(mesh.side, mLayout.cellsY - mesh.y0);
  const size_t stride = size_t(w) + 1, samples = stride * size_t(h + 1);
  mGreedyHeights.resize(samples);
  for (int32_t y = 0; y <= h; ++y)
    for (int32_t x = 0; x <= w; ++x)
      mGreedyHeights[size_t(y) * stride + x] = mHeights->at(mesh.x0 + x, mesh.y0 + y);
  const bool parentIsRtin = parent && parent->method != MeshMethod::kGreedy;
  if (!parent) {
    greedyRootStart(w, h);
  } else {
    // The parent's surface at every sample (a sample on a parent edge gets the edge's own
    // interpolation, so chunks on either side of a parent border see the same values).
    mGreedyParent.assign(samples, std::nan(""));
    for (size_t k = 0; k + 2 < parent->corners.size(); k += 3) {
      const SurfaceCorner tri[3] = {parent->corners[k], parent->corners[k + 1],
                                    parent->corners[k + 2]};
      rasterizeTriangle(tri, mesh.x0, mesh.y0, mesh.x0 + w, mesh.y0 + h,
                        [&](int32_t x, int32_t y, double z) {
                          mGreedyParent[size_t(y - mesh.y0) * stride + (x - mesh.x0)] = z;
                        });
    }
    // The same triangles in the chunk's own sample coordinates (`parent` is not used after
    // this: keepSurface below may move it).
    mGreedyParentTriangles.assign(parent->corners.begin(), parent->corners.end());
    for (SurfaceCorner& c : mGreedyParentTriangles) {
      c.x -= mesh.x0;
      c.y -= mesh.y0;
    }
  }
  // A root's "parent" is its own heights: its gap and parent bound are its own bound, so the
  // start's edges flip freely within it and its vertices do not morph.
  const double error = mBudget.buildThreshold[level];
  const double gap = level == 0 ? error : kGreedyMorphGap * mBudget.levelError[level - 1];
  // Morph targets are stored on this level's step.
  const double parentError =
      level == 0 ? error : mBudget.levelError[level - 1] - 0.5 * mBudget.zStep[level];
  // Below the root, from the parent's vertices (and a greedy parent's edges between them): no
  // chunk keeps lines for its descendants.
  GreedyMeshInput input{w,           h,        mGreedyHeights, mGreedyParentTriangles,
                        0,           error,    mGreedyParent,  gap,
                        parentError, level > 0};
  // A bintree parent's edges, kept, would hold the chunk to the bintree's pattern.
  input.start = parentIsRtin ? GreedyStart::kParentVertices : GreedyStart::kParentVerticesAndEdges;
  const GreedyMesh m = greedyMesh(input);
  if (m.triangles.empty()) return std::nullopt;
  mesh.vertices.reserve(m.x.size());
  for (size_t i = 0; i < m.x.size(); ++i) {
    const size_t s = size_t(m.y[i]) * stride + size_t(m.x[i]);
    // A root does not morph: its targets are its own heights.
    mesh.vertices.push_back(
        {mesh.x0 + m.x[i], mesh.y0 + m.y[i], m.z[i], level > 0 ? mGreedyParent[s] : m.z[i]});
  }
  mesh.surfaceIndices = m.triangles;
  mesh.method = MeshMethod::kGreedy;
  finishSurface(mesh);
  if (level < mLayout.depth) keepSurface(mesh);
  return mesh;
}

// A root has no parent to start from: it starts from its rectangle's two triangles, and its own
// heights stand for the parent's surface.
void ChunkMesher::greedyRootStart(int32_t w, int32_t h) {
  const size_t stride = size_t(w) + 1;
  mGreedyParent = mGreedyHeights;
  auto corner = [&](int32_t x, int32_t y) {
    return SurfaceCorner{x, y, mGreedyHeights[size_t(y) * stride + size_t(x)]};
  };
  const SurfaceCorner sw = corner(0, 0), se = corner(w, 0), ne = corner(w, h), nw = corner(0, h);
  mGreedyParentTriangles.assign({sw, se, ne, sw, ne, nw});
}

ChunkMesh ChunkMesher::build(int32_t level, int32_t ix, int32_t iy) {
  ChunkMesh mesh;
  mesh.level = level;
  mesh.ix = ix;
  mesh.iy = iy;
  mesh.side = mLayout.chunkCells(level);
  mesh.x0 = ix * mesh.side;
  mesh.y0 = iy * mesh.side;
  mesh.dataX = std::min(mesh.side, mLayout.cellsX - mesh.x0);
  mesh.dataY = std::min(mesh.side, mLayout.cellsY - mesh.y0);
  if (!greedyAt(level)) return buildRtin(std::move(mesh));
  // The parent first (building it, a greedy one, uses the scratch buffers buildGreedy fills).
  const Surface* parent = level > 0 ? &surfaceOf(level - 1, ix >> 1, iy >> 1) : nullptr;
  const bool underGreedy = parent && parent->method == MeshMethod::kGreedy;
  std::optional<ChunkMesh> greedy = buildGreedy(mesh, parent);  // `parent` may move after this
  // Under a greedy parent the greedy mesh (an RTIN child would morph to a bintree the parent
  // does not have). Under an RTIN parent (or at a root), whichever mesh has fewer triangles. An
  // RTIN chunk's morph targets are its RTIN parent's surface, and its children start from its
  // vertices as from any parent's.
  if (greedy && underGreedy) return std::move(*greedy);
  ChunkMesh rtin = buildRtin(std::move(mesh));
  if (greedy && greedy->surfaceIndices.size() < rtin.surfaceIndices.size())
    return std::move(*greedy);
  if (level < mLayout.depth) keepSurface(rtin);  // in the greedy one's place
  return rtin;
}

ChunkMesh ChunkMesher::buildRtin(ChunkMesh mesh) {
  const int32_t level = mesh.level, ix = mesh.ix, iy = mesh.iy;
  mOriginX = mesh.x0;
  mOriginY = mesh.y0;
  mSide = mesh.side;
  if (mSide <= kDenseLimit) {
    mDenseIndex.reserve(size_t(mSide + 1) * (mSide + 1));
  } else {
    mSparseIndex.clear();
  }

  // Walk the chunk's bintree. Alongside, find for every emitted triangle the parent level's
  // triangle it lies in (the child refines the parent, so it is an ancestor or itself): its
  // plane gives the morph targets, with no search.
  const uint8_t needed = mBudget.activationForLevel(level);
  const uint8_t parentNeeds = uint8_t(needed + 1);
  auto splitAt = [&](const BinTriangle& t, uint8_t need) {
    if (!t.splittable()) return false;
    const GridPoint m = t.hypotenuseMidpoint();
    return mGrid.get(m.x, m.y) >= need;
  };
  mStack.clear();
  for (const BinTriangle& root : squareTriangles(mesh.x0, mesh.y0, mesh.side)) {
    Pending item{root, 0, false, {}};
    if (level > 0) {
      // From the parent chunk's triangles down to this root (two bintree levels).
      const int32_t ps = 2 * mesh.side;
      const GridPoint centroid3{root.a.x + root.b.x + root.apex.x,
                                root.a.y + root.b.y + root.apex.y};
      auto contains3 = [&](const BinTriangle& t) {
        const BinTriangle scaled{
            {3 * t.a.x, 3 * t.a.y}, {3 * t.b.x, 3 * t.b.y}, {3 * t.apex.x, 3 * t.apex.y}};
        return containsPoint(scaled, centroid3);
      };
      const auto parentRoots = squareTriangles((ix >> 1) * ps, (iy >> 1) * ps, ps);
      BinTriangle t = contains3(parentRoots[0]) ? parentRoots[0] : parentRoots[1];
      for (int depth = 0; depth < 2 && splitAt(t, parentNeeds); ++depth) {
        const auto kids = t.children();
        t = contains3(kids[0]) ? kids[0] : kids[1];
      }
      if (!splitAt(t, parentNeeds)) {
        item.parentKnown = true;
        item.parent = planeOf(t);
      }
    }
    mStack.push_back(item);
  }
  while (!mStack.empty()) {
    Pending item = mStack.back();
    mStack.pop_back();
    const bool inParent = level > 0 && !item.parentKnown;
    if (level > 0 && !item.parentKnown && !splitAt(item.t, parentNeeds)) {
      item.parentKnown = true;
      item.parent = planeOf(item.t);
    }
    const bool split = splitAt(item.t, needed);
    if (item.t.splittable())
      mesh.rtinDecisions.push_back(
          uint8_t((split ? kRtinSplit : 0) | (inParent ? kRtinInParent : 0) |
                  (inParent && !item.parentKnown ? kRtinParentSplits : 0)));
    if (split) {
      const auto kids = item.t.children();
      // Alternating the child order by depth walks the leaves along a Sierpinski curve:
      // consecutive triangles touch, which the index codec rewards.
      const int first = (item.depth & 1) ? 1 : 0;
      mStack.push_back({kids[1 - first], item.depth + 1, item.parentKnown, item.parent});
      mStack.push_back({kids[first], item.depth + 1, item.parentKnown, item.parent});
      continue;
    }
    // A leaf here is unsplit in the parent too, so its parent triangle is known by now; the
    // roots (level 0) have no parent and morph to themselves.
    assert(level == 0 || item.parentKnown);
    emitTriangle(mesh, item.t, level > 0 ? item.parent : planeOf(item.t));
  }
  finishSurface(mesh);

  mDenseIndex.clear();
  return mesh;
}

}  // namespace terralod
