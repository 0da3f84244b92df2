#include "terralod/measure/vipm_quality.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "terralod/core/parallel.h"
#include "terralod/format/chunk_position.h"
#include "terralod/format/vipm_chunk_codec.h"
#include "terralod/render/vipm_chunk_kind.h"
#include "terralod/vipm/vipm_blob.h"

namespace terralod {
namespace {

// Calls visit(x, y, z) at every integer sample (x, y) inside triangle abc (closed; vertices
// may be fractional while geomorphing) with x in [minX, maxX], y in [minY, maxY], both
// multiples of `stride`, and the linearly interpolated height there.
template <typename Visit>
void rasterizeReal(const std::array<std::array<double, 3>, 3>& v, int64_t minX, int64_t maxX,
                   int64_t minY, int64_t maxY, int64_t stride, Visit&& visit) {
  const auto &a = v[0], &b = v[1], &c = v[2];
  const double area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  if (std::fabs(area) < 1e-12) return;
  constexpr double kEps = 1e-9;
  auto firstMultiple = [&](double lo, int64_t clamp) {
    const int64_t i = std::max(clamp, int64_t(std::ceil(lo - kEps)));
    return (i + stride - 1) / stride * stride;  // i >= 0
  };
  const int64_t y0 = firstMultiple(std::min({a[1], b[1], c[1]}), minY);
  const int64_t y1 = std::min(maxY, int64_t(std::floor(std::max({a[1], b[1], c[1]}) + kEps)));
  const int64_t x0 = firstMultiple(std::min({a[0], b[0], c[0]}), minX);
  const int64_t x1 = std::min(maxX, int64_t(std::floor(std::max({a[0], b[0], c[0]}) + kEps)));
  for (int64_t y = y0; y <= y1; y += stride)
    for (int64_t x = x0; x <= x1; x += stride) {
      const double px = double(x), py = double(y);
      const double wa = ((b[0] - px) * (c[1] - py) - (b[1] - py) * (c[0] - px)) / area;
      const double wb = ((c[0] - px) * (a[1] - py) - (c[1] - py) * (a[0] - px)) / area;
      const double wc = 1.0 - wa - wb;
      if (wa < -kEps || wb < -kEps || wc < -kEps) continue;
      visit(x, y, wa * a[2] + wb * b[2] + wc * c[2]);
    }
}

// The heights a surface shows at one sample: the lowest and highest of its layers there (two
// where a seam is drawn from both sides, e.g. a root's children's sides that do not match,
// or where a surface folds; one elsewhere).
struct Layers {
  double low = 0.0, high = 0.0;
};

// A surface's layers at the measured samples of its chunk's rectangle (the multiples of the
// stride in [x0, maxX] x [y0, maxY]), in a grid (low and high of each cell in turn; NaN where
// it covers none): a chunk's surface covers most of them. The grid's storage is handed in and
// back, so the next frame's reuses it.
class SampleLayers {
 public:
  SampleLayers(int64_t x0, int64_t y0, int64_t maxX, int64_t maxY, int64_t stride,
               std::vector<double> storage)
      : mStride(stride),
        mX0(roundUp(x0, stride)),
        mY0(roundUp(y0, stride)),
        mColumns(maxX >= mX0 ? (maxX - mX0) / stride + 1 : 0),
        mRows(maxY >= mY0 ? (maxY - mY0) / stride + 1 : 0),
        mCells(std::move(storage)) {
    mCells.assign(size_t(2 * mColumns * mRows), kNone);
  }

  // (x, y): a measured sample inside the rectangle.
  void keep(int64_t x, int64_t y, double z) {
    double* l = &mCells[2 * size_t((y - mY0) / mStride * mColumns + (x - mX0) / mStride)];
    if (std::isnan(l[0])) {
      l[0] = l[1] = z;
    } else {
      l[0] = std::min(l[0], z);
      l[1] = std::max(l[1], z);
    }
  }
  // Its layers at the measured sample (x, y) (false where it covers none).
  bool find(int64_t x, int64_t y, Layers& out) const {
    if (x < mX0 || y < mY0) return false;
    const int64_t i = (x - mX0) / mStride, j = (y - mY0) / mStride;
    if (i >= mColumns || j >= mRows) return false;
    const double* l = &mCells[2 * size_t(j * mColumns + i)];
    if (std::isnan(l[0])) return false;
    out = {l[0], l[1]};
    return true;
  }
  // Calls visit(x, y) at every sample it covers.
  template <typename Visit>
  void forEach(Visit&& visit) const {
    for (int64_t j = 0; j < mRows; ++j)
      for (int64_t i = 0; i < mColumns; ++i)
        if (!std::isnan(mCells[2 * size_t(j * mColumns + i)]))
          visit(mX0 + i * mStride, mY0 + j * mStride);
  }
  std::vector<double> release() { return std::move(mCells); }

 private:
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  static int64_t roundUp(int64_t v, int64_t stride) {
    return (std::max<int64_t>(v, 0) + stride - 1) / stride * stride;
  }
  int64_t mStride, mX0, mY0, mColumns, mRows;
  std::vector<double> mCells;
};

// The layers of several surfaces at (x, y) (false if none covers it).
bool layersAt(std::span<const SampleLayers* const> surfaces, int64_t x, int64_t y, Layers& out) {
  bool covered = false;
  for (const SampleLayers* samples : surfaces)
    if (Layers l; samples->find(x, y, l)) {
      out = covered ? Layers{std::min(out.low, l.low), std::max(out.high, l.high)} : l;
      covered = true;
    }
  return covered;
}

// Whether `a` and `b` are the same node or one is an ancestor of the other.
bool sameBranch(const ChunkTree& tree, uint32_t a, uint32_t b) {
  auto isAncestorOrSelf = [&](uint32_t up, uint32_t n) {
    for (; n != kNoNode; n = tree.node(n).parent)
      if (n == up) return true;
    return false;
  };
  return isAncestorOrSelf(a, b) || isAncestorOrSelf(b, a);
}

}  // namespace

VipmQuality::VipmQuality(const TilesetReader& tileset, const ChunkTree& tree,
                         const Heightfield& source, int stride, unsigned threads, Geomorph geomorph,
                         VipmStitch stitch)
    : mTileset(tileset),
      mTree(tree),
      mSource(source),
      mStride(std::max(stride, 1)),
      mThreads(std::max(threads, 1u)),
      mGeomorph(geomorph),
      mStitch(stitch) {}

std::vector<VipmQuality::Drawn> VipmQuality::drawn(const ChunkTree& tree, const View& view,
                                                   double tau,
                                                   std::span<const SelectedChunk> selection) {
  std::vector<Drawn> out;
  out.reserve(selection.size());
  for (const SelectedChunk& s : selection) {
    const double theta = vipmDrawnTheta(tree, view, tau, s);
    out.push_back({s.node, theta, theta});
  }
  return out;
}

std::vector<VipmQuality::Drawn> VipmQuality::geomorphedFor(
    const ChunkTree& tree, const View& view, const SelectionOptions& options,
    std::span<const SelectedChunk> previousSelection, std::span<const Drawn> previous) {
  std::vector<Drawn> out(previous.begin(), previous.end());
  for (size_t k = 0; k < out.size() && k < previousSelection.size(); ++k) {
    SelectedChunk now = previousSelection[k];
    now.morph = morphParameter(tree, view, options, now.node);
    out[k].morphTheta = vipmDrawnTheta(tree, view, options.tau, now);
  }
  return out;
}

Result<VipmQuality::Chunk*> VipmQuality::chunk(uint32_t node) {
  auto it = mChunks.find(node);
  if (it != mChunks.end()) return &it->second;
  const std::string subject = "chunk " + std::to_string(node);
  auto bytes = mTileset.readNode(node);
  if (!bytes) return bytes.error();
  auto loaded = loadVipmChunk(bytes->mesh(), subject);
  if (!loaded) return loaded.error();
  Chunk c;
  c.levels = std::move(loaded->levels);
  c.zBase = loaded->data.zBase;
  c.own = positionsAboveBase(*loaded);  // as the kind holds them
  UnpackedChunk& unpacked = loaded->unpacked;
  c.mesh = std::move(unpacked.mesh);
  c.materials = std::move(unpacked.materials);
  const TilesetHeader& h = mTileset.header();
  const NodeRecord& record = mTileset.nodes()[node];
  const auto [x0, y0] = chunkCellOrigin(h, record);
  c.x0 = x0;
  c.y0 = y0;
  c.where = {x0,
             y0,
             c.zBase,
             c.mesh.width,
             c.mesh.height,
             vipmSeamStep(uint32_t(h.chunkCells(record.level))),
             uint32_t(h.chunkCells(0))};
  if (mStitch == VipmStitch::kFans) c.stitcher = VipmStitcher(c.mesh, c.where);
  c.maxX = std::min<int64_t>(x0 + h.chunkCells(record.level), mSource.columns() - 1);
  c.maxY = std::min<int64_t>(y0 + h.chunkCells(record.level), mSource.rows() - 1);
  c.truthMin = 1e300;
  c.truthMax = -1e300;
  for (int64_t y = c.y0; y <= c.maxY; ++y)
    for (int64_t x = c.x0; x <= c.maxX; ++x) {
      const double z = mSource(int32_t(x), int32_t(y));
      c.truthMin = std::min(c.truthMin, z);
      c.truthMax = std::max(c.truthMax, z);
    }
  return &mChunks.emplace(node, std::move(c)).first->second;
}

std::vector<std::array<float, 3>> VipmQuality::drawnPositions(Chunk& c, const Drawn& d) {
  // What VipmGpuChunk::update draws for θ (the collapses θ chooses, geomorphed at morphTheta).
  const MorphWindow window = morphWindow(c.mesh.errors, d.theta, d.morphTheta, mGeomorph);
  c.levels.setApplied(window.applied);
  std::vector<std::array<float, 3>> drawn = c.own;
  if (window.morphing > window.applied) {
    morphPositions(c.mesh, window, d.morphTheta, c.own, drawn);
    const uint32_t n = c.mesh.vertexCount();
    for (uint32_t j = window.applied; j < window.morphing; ++j)
      roundStitchPoint(drawn[n - 1 - j], c.where);
  }
  return drawn;
}

std::vector<VipmQuality::Triangle> VipmQuality::triangles(
    const Chunk& c, std::span<const std::array<float, 3>> drawn, const StitchFans* fans) const {
  const VipmPart& whole = c.levels.whole();
  const uint32_t count = c.levels.drawnTriangles(whole);
  const uint32_t n = c.mesh.vertexCount();
  auto at = [&](uint32_t v) -> const std::array<float, 3>& {
    return v < n ? drawn[v] : fans->positions[v - n];
  };
  std::vector<Triangle> out;
  out.reserve(count + (fans ? fans->triangles.size() : 0));
  auto add = [&](uint32_t a, uint32_t b, uint32_t e) {
    Triangle t;
    const uint32_t corners[3] = {a, b, e};
    for (int j = 0; j < 3; ++j) {
      const std::array<float, 3>& p = at(corners[j]);
      t.v[size_t(j)] = {double(c.x0) + p[0], double(c.y0) + p[1], c.zBase + double(p[2])};
    }
    out.push_back(t);
  };
  size_t next = 0;
  for (uint32_t t = 0; t < count; ++t) {
    if (fans && next < fans->replaced.size() && fans->replaced[next] == t) {
      ++next;
      continue;
    }
    add(whole.indices[3 * t], whole.indices[3 * t + 1], whole.indices[3 * t + 2]);
  }
  if (fans)
    for (const auto& f : fans->triangles) add(f[0], f[1], f[2]);
  return out;
}

bool VipmQuality::inView(const View& view, int64_t x, int64_t y, double z) const {
  const glm::dvec3 p{double(x) * mTree.spacing()[0], double(y) * mTree.spacing()[1], z};
  for (const glm::dvec4& plane : view.planes)
    if (glm::dot(glm::dvec3(plane), p) + plane.w < 0.0) return false;
  return true;
}

template <typename Visit>
void VipmQuality::rasterize(const Chunk& c, std::span<const Triangle> triangles, const View& view,
                            Visit&& visit) const {
  const auto spacing = mTree.spacing();
  // Samples are in view at their true heights: none where the box of those lies outside a
  // plane, every one where it lies inside all (then not tested one by one).
  Box truth;
  truth.min = {double(c.x0) * spacing[0], double(c.y0) * spacing[1], c.truthMin};
  truth.max = {double(c.maxX) * spacing[0], double(c.maxY) * spacing[1], c.truthMax};
  if (!boxInFrustum(view, truth)) return;
  const bool allInView = boxWithinFrustum(view, truth);
  for (const Triangle& t : triangles) {
    Box box;
    box.min = {std::min({t.v[0][0], t.v[1][0], t.v[2][0]}) * spacing[0],
               std::min({t.v[0][1], t.v[1][1], t.v[2][1]}) * spacing[1],
               std::min({t.v[0][2], t.v[1][2], t.v[2][2], c.truthMin})};
    box.max = {std::max({t.v[0][0], t.v[1][0], t.v[2][0]}) * spacing[0],
               std::max({t.v[0][1], t.v[1][1], t.v[2][1]}) * spacing[1],
               std::max({t.v[0][2], t.v[1][2], t.v[2][2], c.truthMax})};
    if (!boxInFrustum(view, box)) continue;
    rasterizeReal(t.v, c.x0, c.maxX, c.y0, c.maxY, mStride, [&](int64_t x, int64_t y, double z) {
      if (allInView || inView(view, x, y, mSource(int32_t(x), int32_t(y)))) visit(x, y, z);
    });
  }
}

Result<std::vector<VipmQuality::Surface>> VipmQuality::surfaces(std::span<const Drawn> chunks) {
  std::vector<Chunk*> states;
  std::vector<std::vector<std::array<float, 3>>> positions;
  for (const Drawn& d : chunks) {
    auto c = chunk(d.node);
    if (!c) return c.error();
    states.push_back(*c);
    positions.push_back(drawnPositions(**c, d));
  }
  // With fans: every chunk's border points, then each chunk's fans, as the kind makes them.
  const bool fanned = mStitch == VipmStitch::kFans;
  StitchTable table;
  std::vector<std::array<uint8_t, kMaxMaterials>> noWeights;
  if (fanned) {
    for (size_t i = 0; i < states.size(); ++i) {
      noWeights.assign(positions[i].size(), {});
      states[i]->stitcher.addPoints(table, states[i]->levels.activeVertices(), positions[i],
                                    noWeights, states[i]->materials);
    }
    table.finish();
  }
  std::vector<Surface> out;
  out.reserve(states.size());
  StitchFans fans;
  for (size_t i = 0; i < states.size(); ++i) {
    const Chunk& c = *states[i];
    if (fanned) {
      const VipmPart& whole = c.levels.whole();
      c.stitcher.fan(table,
                     std::span(whole.indices).first(size_t(c.levels.drawnTriangles(whole)) * 3),
                     positions[i], fans);
    }
    out.push_back({&c, triangles(c, positions[i], fanned ? &fans : nullptr)});
  }
  return out;
}

Result<double> VipmQuality::maxErrorPixels(const View& view, std::span<const Drawn> chunks) {
  // Surfaces on this thread (the chunks' level state is not thread-safe), measured in parallel.
  auto made = surfaces(chunks);
  if (!made) return made.error();
  const std::vector<Surface>& surfaces = *made;
  std::atomic<double> found{0.0};
  const auto spacing = mTree.spacing();
  parallelFor(surfaces.size(), mThreads, [&](size_t i, unsigned) {
    double worst = 0.0;
    rasterize(*surfaces[i].chunk, surfaces[i].triangles, view, [&](int64_t x, int64_t y, double z) {
      const double truth = mSource(int32_t(x), int32_t(y));
      const glm::dvec3 p{double(x) * spacing[0], double(y) * spacing[1], truth};
      worst = std::max(
          worst, screenSpaceError(view, std::fabs(z - truth), glm::length(p - view.camera.eye)));
    });
    double seen = found.load(std::memory_order_relaxed);
    while (worst > seen && !found.compare_exchange_weak(seen, worst)) {
    }
  });
  return found.load();
}

Result<double> VipmQuality::maxPopPixels(const View& view, std::span<const Drawn> previous,
                                         std::span<const Drawn> current) {
  // Chunks drawn alike in both frames show the same surface: left out.
  auto same = [&](const Drawn& a, const Drawn& b) -> Result<bool> {
    auto c = chunk(a.node);
    if (!c) return c.error();
    const MorphWindow wa = morphWindow((*c)->mesh.errors, a.theta, a.morphTheta, mGeomorph);
    const MorphWindow wb = morphWindow((*c)->mesh.errors, b.theta, b.morphTheta, mGeomorph);
    return wa.applied == wb.applied && wa.morphing == wb.morphing &&
           (wa.morphing == wa.applied || a.morphTheta == b.morphTheta);
  };
  std::unordered_map<uint32_t, const Drawn*> before;
  for (const Drawn& d : previous) before.emplace(d.node, &d);
  std::vector<const Drawn*> changed;
  std::unordered_map<uint32_t, bool> unchanged;
  for (const Drawn& d : current) {
    auto it = before.find(d.node);
    if (it != before.end()) {
      auto alike = same(*it->second, d);
      if (!alike) return alike.error();
      if (*alike) {
        unchanged[d.node] = true;
        continue;
      }
    }
    changed.push_back(&d);
  }
  if (changed.empty()) return 0.0;
  // Each changed chunk's samples are compared between what covered them before and now from
  // the same place in the tree: before, the chunks on its branch (itself, or the ancestor or
  // descendants it replaced); now, the chunks on those chunks' branches (it and its siblings
  // where a parent split). A neighbour's border is left out: chunks at different levels need
  // not agree on a shared border (flanges hide the gap), so the neighbour's height there is
  // not what this chunk's samples showed. A seam drawn from both sides inside one branch (a
  // root's children's sides, which need not match) has two layers before and after: the
  // lowest and the highest are compared.
  // Both frames' surfaces as drawn (with fans, each frame's fans, made from its own chunks),
  // rasterised where needed.
  auto earlier = surfaces(previous);
  if (!earlier) return earlier.error();
  auto later = surfaces(current);
  if (!later) return later.error();
  auto layersOf = [&](std::unordered_map<uint32_t, SampleLayers>& cache,
                      const std::vector<Surface>& made, std::span<const Drawn> frame,
                      const Drawn& d) -> const SampleLayers* {
    if (const auto it = cache.find(d.node); it != cache.end()) return &it->second;
    const Surface& surface = made[size_t(&d - frame.data())];
    const Chunk& c = *surface.chunk;
    std::vector<double> storage;
    if (!mSpareGrids.empty()) {
      storage = std::move(mSpareGrids.back());
      mSpareGrids.pop_back();
    }
    SampleLayers& mine =
        cache.try_emplace(d.node, c.x0, c.y0, c.maxX, c.maxY, int64_t(mStride), std::move(storage))
            .first->second;
    rasterize(c, surface.triangles, view,
              [&](int64_t x, int64_t y, double z) { mine.keep(x, y, z); });
    return &mine;
  };
  std::unordered_map<uint32_t, SampleLayers> earlierSurfaces, laterSurfaces;
  double worst = 0.0;
  const auto spacing = mTree.spacing();
  for (const Drawn* d : changed) {
    std::vector<const SampleLayers*> then, now;
    for (const Drawn& e : previous) {
      if (unchanged.count(e.node) || !sameBranch(mTree, e.node, d->node)) continue;
      then.push_back(layersOf(earlierSurfaces, *earlier, previous, e));
      for (const Drawn& n : current) {
        if (!sameBranch(mTree, n.node, e.node)) continue;
        const SampleLayers* layers = layersOf(laterSurfaces, *later, current, n);
        if (std::find(now.begin(), now.end(), layers) == now.end()) now.push_back(layers);
      }
    }
    if (then.empty()) continue;  // newly in view: nothing it replaced
    const SampleLayers* mine = layersOf(laterSurfaces, *later, current, *d);
    mine->forEach([&](int64_t x, int64_t y) {
      Layers was, is;
      if (!layersAt(then, x, y, was) || !layersAt(now, x, y, is)) return;
      const double moved = std::max(std::fabs(is.low - was.low), std::fabs(is.high - was.high));
      const glm::dvec3 p{double(x) * spacing[0], double(y) * spacing[1], is.high};
      worst = std::max(worst, screenSpaceError(view, moved, glm::length(p - view.camera.eye)));
    });
  }
  for (auto* cache : {&earlierSurfaces, &laterSurfaces})
    for (auto& [node, layers] : *cache) mSpareGrids.push_back(layers.release());
  return worst;
}

}  // namespace terralod
