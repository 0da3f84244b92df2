#include "terralod/vegetation/tileset_corner_heights.h"

#include <algorithm>
#include <cmath>

#include <glm/vec3.hpp>

#include "terralod/format/chunk_position.h"
#include "terralod/vipm/vipm_blob.h"

namespace terralod::veg {
namespace {

// The full-detail surface triangles of a finest chunk, world metres, three points each.
Result<std::vector<glm::dvec3>> leafTriangles(const TilesetReader& tileset, uint32_t node) {
  const TilesetHeader& header = tileset.header();
  const NodeRecord& record = tileset.nodes()[node];
  std::vector<glm::dvec3> points;
  if (record.meshKind == MeshKind::kVipm) {
    auto bytes = tileset.readNode(node);
    if (!bytes) return bytes.error();
    auto loaded = loadVipmChunk(bytes->mesh(), tileset.name() + " chunk " + std::to_string(node));
    if (!loaded) return loaded.error();
    const auto [x0, y0] = chunkCellOrigin(header, record);
    const VipmPart& whole = loaded->levels.whole();
    for (uint32_t k = 0; k < loaded->levels.drawnTriangles(whole) * 3; ++k) {
      const uint16_t v = whole.indices[k];
      points.push_back({double(x0 + int64_t(loaded->unpacked.positions[v][0])) * header.spacingX,
                        double(y0 + int64_t(loaded->unpacked.positions[v][1])) * header.spacingY,
                        loaded->data.zBase + double(loaded->data.heights[v]) * loaded->data.zStep});
    }
    return points;
  }
  auto geometry = tileset.readChunk(node);
  if (!geometry) return geometry.error();
  for (const ChunkPart& part : geometry->parts)
    for (uint32_t k = 0; k < part.surfaceIndexCount; ++k) {
      const auto p = chunkWorldPosition(header, record, *geometry, part.vertices[part.indices[k]]);
      points.push_back({p[0], p[1], p[2]});
    }
  return points;
}

bool contains(const Box& box, double x, double y) {
  return x >= box.min[0] && x <= box.max[0] && y >= box.min[1] && y <= box.max[1];
}

}  // namespace

TilesetCornerHeights::TilesetCornerHeights(const TilesetReader& tileset, const ChunkTree& tree,
                                           double tileSize, uint64_t budgetBytes,
                                           std::function<void(const std::string&)> log)
    : mTileset(tileset),
      mTree(tree),
      mTileSize(tileSize),
      mBudget(budgetBytes),
      mLog(std::move(log)) {}

std::optional<std::array<float, 4>> TilesetCornerHeights::tileCorners(uint32_t x, uint32_t y) {
  std::array<float, 4> h{};
  const int64_t i = x, j = y;
  const std::array<std::array<int64_t, 2>, 4> corners = {
      {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}}};  // SW, SE, NE, NW
  for (size_t k = 0; k < 4; ++k) {
    const auto c = corner(corners[k][0], corners[k][1]);
    if (!c) return std::nullopt;
    h[k] = *c;
  }
  return h;
}

uint32_t TilesetCornerHeights::leafAt(double x, double y) const {
  uint32_t found = kNoNode;
  for (uint32_t r = 0; r < mTree.rootCount() && found == kNoNode; ++r)
    if (contains(mTree.node(r).box, x, y)) found = r;
  while (found != kNoNode && mTree.node(found).childCount > 0) {
    const ChunkNode& n = mTree.node(found);
    uint32_t next = kNoNode;
    for (uint32_t c = n.firstChild; c < n.firstChild + n.childCount && next == kNoNode; ++c)
      if (contains(mTree.node(c).box, x, y)) next = c;
    if (next == kNoNode) break;  // on no child's footprint: the node itself is the finest
    found = next;
  }
  return found;
}

std::optional<float> TilesetCornerHeights::corner(int64_t i, int64_t j) {
  const double x = double(i) * mTileSize, y = double(j) * mTileSize;
  const uint32_t leaf = leafAt(x, y);
  if (leaf == kNoNode) return std::nullopt;
  const Page* p = page(leaf);
  if (!p) return std::nullopt;
  const int64_t c = i - p->i0, r = j - p->j0;
  if (c < 0 || r < 0 || c >= p->columns || r >= p->rows) return std::nullopt;
  const float h = p->heights[size_t(r) * size_t(p->columns) + size_t(c)];
  if (std::isnan(h)) return std::nullopt;
  return h;
}

const TilesetCornerHeights::Page* TilesetCornerHeights::page(uint32_t leaf) {
  if (auto it = mPages.find(leaf); it != mPages.end()) {
    mLru.splice(mLru.begin(), mLru, it->second.lru);
    return &it->second;
  }
  if (mFailed.count(leaf)) return nullptr;
  auto triangles = leafTriangles(mTileset, leaf);
  if (!triangles) {
    mFailed[leaf] = true;
    if (mLog) mLog(triangles.error().message);
    return nullptr;
  }
  ++mChunksRead;
  const Box& box = mTree.node(leaf).box;
  Page p;
  p.i0 = int64_t(std::ceil(box.min[0] / mTileSize));
  p.j0 = int64_t(std::ceil(box.min[1] / mTileSize));
  p.columns = int(std::max<int64_t>(0, int64_t(std::floor(box.max[0] / mTileSize)) - p.i0 + 1));
  p.rows = int(std::max<int64_t>(0, int64_t(std::floor(box.max[1] / mTileSize)) - p.j0 + 1));
  p.heights.assign(size_t(p.columns) * size_t(p.rows), NAN);
  // Each triangle sets the lattice points it covers (edges shared: the last one wins, and
  // neighbours agree there).
  const std::vector<glm::dvec3>& t = *triangles;
  for (size_t k = 0; k + 2 < t.size(); k += 3) {
    const glm::dvec3 &a = t[k], &b = t[k + 1], &c = t[k + 2];
    const double area = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    if (std::abs(area) < 1e-12) continue;
    const auto lo = [&](double v, int64_t o) { return int64_t(std::ceil(v / mTileSize)) - o; };
    const auto hi = [&](double v, int64_t o) { return int64_t(std::floor(v / mTileSize)) - o; };
    const int64_t c0 = std::max<int64_t>(0, lo(std::min({a.x, b.x, c.x}), p.i0));
    const int64_t c1 = std::min<int64_t>(p.columns - 1, hi(std::max({a.x, b.x, c.x}), p.i0));
    const int64_t r0 = std::max<int64_t>(0, lo(std::min({a.y, b.y, c.y}), p.j0));
    const int64_t r1 = std::min<int64_t>(p.rows - 1, hi(std::max({a.y, b.y, c.y}), p.j0));
    for (int64_t r = r0; r <= r1; ++r)
      for (int64_t col = c0; col <= c1; ++col) {
        const double x = double(p.i0 + col) * mTileSize, y = double(p.j0 + r) * mTileSize;
        const double wa = ((b.x - x) * (c.y - y) - (c.x - x) * (b.y - y)) / area;
        const double wb = ((c.x - x) * (a.y - y) - (a.x - x) * (c.y - y)) / area;
        const double wc = 1.0 - wa - wb;
        constexpr double kEdge = -1e-9;
        if (wa < kEdge || wb < kEdge || wc < kEdge) continue;
        p.heights[size_t(r) * size_t(p.columns) + size_t(col)] =
            float(wa * a.z + wb * b.z + wc * c.z);
      }
  }
  const uint64_t bytes = sizeof(Page) + p.heights.size() * sizeof(float);
  while (!mLru.empty() && mResidentBytes + bytes > mBudget) {
    const uint32_t victim = mLru.back();
    mLru.pop_back();
    const Page& v = mPages.at(victim);
    mResidentBytes -= sizeof(Page) + v.heights.size() * sizeof(float);
    mPages.erase(victim);
  }
  mLru.push_front(leaf);
  p.lru = mLru.begin();
  mResidentBytes += bytes;
  return &mPages.emplace(leaf, std::move(p)).first->second;
}

}  // namespace terralod::veg
