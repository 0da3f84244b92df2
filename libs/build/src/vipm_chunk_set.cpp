#include "terralod/build/vipm_chunk_set.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

#include "terralod/build/chunk_pass.h"
#include "terralod/build/tree_layout.h"
#include "terralod/build/vipm_chunks.h"
#include "terralod/core/parallel.h"
#include "terralod/materials/terrain_edits.h"
#include "terralod/vipm/collapse_order.h"
#include "vipm_cells.h"
#include "vipm_chunk_reuse.h"

namespace terralod {

namespace {

// A chunk's grid points along one axis: clipped at the data's far edge.
int32_t pointsFrom(int32_t first, int32_t cells, int32_t side) {
  return std::min(side, cells - first) + 1;
}

// The height range (lowest, highest) of the grid points [x0, x0 + width) x [y0, y0 + height).
std::pair<float, float> pointRange(const Heightfield& h, int32_t x0, int32_t y0, int32_t width,
                                   int32_t height) {
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (int32_t y = y0; y < y0 + height; ++y)
    for (int32_t x = x0; x < x0 + width; ++x) {
      lo = std::min(lo, h(x, y));
      hi = std::max(hi, h(x, y));
    }
  return {lo, hi};
}

// The tileset's height step for the largest node range, or why there is none.
Result<double> tilesetZStep(double range, double maxError, const std::string& subject) {
  const double zStep = vipmTilesetZStep(maxError, range);
  if (zStep <= maxError) return zStep;
  // Rounding alone would take half the error budget.
  char text[256];
  std::snprintf(text, sizeof text,
                "--max-error %g m is too fine for 16-bit heights over a node's %.0f m of "
                "relief; use at least %.3g m",
                maxError, range, vipmTilesetZStep(range / 65000.0, range));
  return makeError(subject, text);
}

// A built chunk's mesh fields into its node record.
void takeMeshFields(NodeRecord& n, const NodeRecord& built) {
  n.meshKind = built.meshKind;
  n.minZ = built.minZ;
  n.maxZ = built.maxZ;
  n.vertexCount = built.vertexCount;
  n.triangleCount = built.triangleCount;
}

// How far each chunk's border strays from the source samples, over all its levels, by level
// and place.
class Deviations {
 public:
  explicit Deviations(const TreeLayout& layout) : mLayout(layout) {
    for (int32_t l = 0; l < layout.levelCount(); ++l)
      mLevels.emplace_back(size_t(layout.chunksX(l)) * size_t(layout.chunksY(l)), 0.0);
  }
  double& at(int32_t level, int32_t x, int32_t y) {
    return mLevels[size_t(level)][size_t(y) * size_t(mLayout.chunksX(level)) + size_t(x)];
  }
  double get(int32_t level, int32_t x, int32_t y) const {
    if (x < 0 || y < 0 || x >= mLayout.chunksX(level) || y >= mLayout.chunksY(level)) return 0.0;
    return mLevels[size_t(level)][size_t(y) * size_t(mLayout.chunksX(level)) + size_t(x)];
  }
  // The largest deviation of any chunk that can be drawn beside node n (level, x, y): one
  // across a side, at any level, that is not n's ancestor.
  double beside(int32_t level, int32_t x, int32_t y) const {
    const int64_t c = mLayout.chunkCells(level);
    const int64_t x0 = x * c, y0 = y * c, x1 = x0 + c, y1 = y0 + c;
    double d = 0.0;
    for (int32_t m = 0; m < mLayout.levelCount(); ++m) {
      const int64_t cm = mLayout.chunkCells(m);
      // Along the west and east sides (columns just outside), then the south and north.
      for (const int64_t col : {x0 - 1, x1})
        for (int64_t row = y0 / cm; row * cm < y1; ++row) {
          if (col < 0 || (m <= level && col / cm == x0 / cm)) continue;  // n's ancestor
          d = std::max(d, get(m, int32_t(col / cm), int32_t(row)));
        }
      for (const int64_t row : {y0 - 1, y1})
        for (int64_t col = x0 / cm; col * cm < x1; ++col) {
          if (row < 0 || (m <= level && row / cm == y0 / cm)) continue;
          d = std::max(d, get(m, int32_t(col), int32_t(row / cm)));
        }
    }
    return d;
  }

 private:
  const TreeLayout& mLayout;
  std::vector<std::vector<double>> mLevels;
};

// maxSkirtDepth of every node (docs/format.md "Node fields"): two borders drawn side by side
// are at most their deviations apart, so a flange as deep as its own deviation plus the
// largest of any chunk that can be drawn beside it closes the gap. A node over seams (its
// children's shared sides) covers both sides of them, and is at least as deep as its
// children. Nodes are in level order, so children come after their parents.
void setFlangeDepths(std::vector<NodeRecord>& nodes, const Deviations& d,
                     const std::vector<double>& seams, double zStep) {
  for (size_t i = nodes.size(); i-- > 0;) {
    NodeRecord& n = nodes[i];
    const int32_t level = n.level, x = int32_t(n.x), y = int32_t(n.y);
    double depth = std::max(d.get(level, x, y) + d.beside(level, x, y), 2.0 * seams[i]) + zStep;
    for (uint32_t c = 0; c < uint32_t(std::popcount(unsigned(n.childMask))); ++c)
      depth = std::max(depth, double(nodes[n.firstChild + c].maxSkirtDepth));
    n.maxSkirtDepth = floatAbove(depth);
  }
}

// Why a level `above` the roots could not be built.
std::string tooDenseNodes(int32_t above) {
  return "its nodes of " + std::to_string(kRoot << above) + " cells would keep more than " +
         std::to_string(kVipmMaxNodeVertices) +
         " vertices (the terrain simplifies too little above the roots)";
}

}  // namespace

TreeLayout vipmTreeLayout(const DemInfo& info, int32_t upperLevels) {
  TreeLayout l;
  l.cellsX = info.columns - 1;
  l.cellsY = info.rows - 1;
  l.leafCells = kLeaf;
  const int32_t roots = (std::max(l.cellsX, l.cellsY) + kRoot - 1) / kRoot;
  if (upperLevels == kVipmUpperLevelsBySize) {
    const int64_t flatRoots =
        int64_t((l.cellsX + kRoot - 1) / kRoot) * int64_t((l.cellsY + kRoot - 1) / kRoot);
    upperLevels = flatRoots > kVipmFlatRootsMax ? kVipmUpperLevelsAuto : 0;
  }
  if (upperLevels == kVipmUpperLevelsAuto) {
    upperLevels = 0;
    while ((int64_t{1} << upperLevels) < roots && upperLevels < kVipmMaxUpperLevels) ++upperLevels;
  }
  l.depth = 1 + upperLevels;
  l.rootCells = kRoot << upperLevels;
  l.rootsX = (l.cellsX + l.rootCells - 1) / l.rootCells;
  l.rootsY = (l.cellsY + l.rootCells - 1) / l.rootCells;
  return l;
}

struct VipmChunkSetState {
  BuildOptions options;  // options.edits: every stroke applied so far
  DemInfo info;
  TreeLayout layout;
  Heightfield heights;
  MaterialMap materials;
  double zStep = 0.0;
  std::vector<double> levelErrors;  // per level; all negative before the first build
  std::vector<NodeRecord> nodes;
  size_t innerCount = 0;         // nodes [0, innerCount) are above the leaves (level order)
  std::vector<VipmLeaf> leaves;  // per leaf, node innerCount + k
  std::vector<VipmRoot> inner;   // per node above the leaves
  std::vector<std::vector<uint8_t>> normalMaps;  // per node: its texture blob
  std::vector<uint32_t> bytesVersion;            // per node: times made again since the build
  std::vector<std::pair<float, float>> bounds;   // per inner node: its points' heights
  BuildSummary summary;

  int32_t leafLevel() const { return layout.depth; }
  int32_t cells(size_t i) const { return layout.chunkCells(nodes[i].level); }
  // The grid points of node i: south-west point and size.
  std::array<int32_t, 4> points(size_t i) const {
    const NodeRecord& n = nodes[i];
    const int32_t c = cells(i);
    const int32_t x0 = int32_t(n.x) * c, y0 = int32_t(n.y) * c;
    return {x0, y0, pointsFrom(x0, layout.cellsX, c), pointsFrom(y0, layout.cellsY, c)};
  }
  // The children's coarsest levels, which node i (above the leaves) joins.
  std::vector<const CoarseMesh*> childMeshes(size_t i) const {
    const NodeRecord& n = nodes[i];
    std::vector<const CoarseMesh*> children;
    for (uint32_t c = 0; c < uint32_t(std::popcount(unsigned(n.childMask))); ++c) {
      const size_t k = n.firstChild + c;
      children.push_back(k >= innerCount ? &leaves[k - innerCount].coarsest : &inner[k].coarsest);
    }
    return children;
  }
  // The height bounds of every node above the leaves: measured for the 128-cell ones whose
  // `measure` mark is set, joined upward for the rest; the largest range of any of them.
  double updateBounds(const std::vector<uint8_t>& measure) {
    for (size_t i = innerCount; i-- > 0;) {
      if (nodes[i].level == leafLevel() - 1) {
        if (!measure[i]) continue;
        const auto [x0, y0, w, h] = points(i);
        bounds[i] = pointRange(heights, x0, y0, w, h);
        continue;
      }
      const NodeRecord& n = nodes[i];
      bounds[i] = {std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()};
      for (uint32_t c = 0; c < uint32_t(std::popcount(unsigned(n.childMask))); ++c) {
        bounds[i].first = std::min(bounds[i].first, bounds[n.firstChild + c].first);
        bounds[i].second = std::max(bounds[i].second, bounds[n.firstChild + c].second);
      }
    }
    double range = 0.0;
    for (size_t i = 0; i < innerCount; ++i)
      range = std::max(range, double(bounds[i].second) - double(bounds[i].first));
    return range;
  }

  // `nodes` as their whole grids, with their normal maps (VipmChunkSet::apply's interim).
  std::vector<VipmInterimNode> interimNodes(const std::vector<uint32_t>& nodes,
                                            unsigned threads) const;

  // Builds the chunks marked in `dirty` (per node; all of a level too when its level error
  // changes) from the leaves up to level `top`, keeping what `reuse` has for them where no
  // new stroke reaches, then every node's fields and flange depths.
  // Fails (tooDenseLevel set) where a node above the roots would join more vertices than a
  // node can hold.
  Status rebuild(std::vector<uint8_t> dirty, const VipmChunkReuse* reuse, unsigned threads,
                 Progress& progress, int32_t top = 0);
  int32_t tooDenseLevel = -1;  // the level whose join was too large in the last rebuild

  // The nodes whose record or bytes differ from `before` (records, level errors): rebuilt
  // (`rebuilt`), on a level whose error moved, or with another flange depth.
  std::vector<uint32_t> changedSince(const std::vector<NodeRecord>& before,
                                     const std::vector<double>& levelErrorsBefore,
                                     const std::vector<uint8_t>& rebuilt) const;

  // Node i's record and bytes, as handed to a drawing thread.
  VipmInterimNode handover(uint32_t i) const;
};

Status VipmChunkSetState::rebuild(std::vector<uint8_t> dirty, const VipmChunkReuse* reuse,
                                  unsigned threads, Progress& progress, int32_t top) {
  tooDenseLevel = -1;
  const size_t leafCount = nodes.size() - innerCount;
  VipmLeafParams params;
  params.zStep = zStep;
  params.maxError = options.maxError;
  params.rules = options.materialRules;
  params.coarsestError = options.blotError.leafError(options.maxError);
  params.compressionLevel = options.compressionLevel;
  std::vector<uint8_t> kept(nodes.size(), 0), built(nodes.size(), 0);
  // Node i from the earlier build, when no new stroke reaches it.
  auto keep = [&](size_t i, auto&& reuseChunk, auto& out) {
    const auto [x0, y0, w, h] = points(i);
    auto old = reuse ? reuse->clean(uint32_t(i), x0, y0, w, h) : std::nullopt;
    if (!old) return false;
    auto chunk =
        reuseChunk(std::vector<uint8_t>(old->mesh().begin(), old->mesh().end()), x0, y0, w, h);
    if (!chunk) return false;
    out = std::move(*chunk);
    normalMaps[i].assign(old->texture().begin(), old->texture().end());
    kept[i] = 1;
    return true;
  };
  auto reuseLeaf = [&](std::vector<uint8_t> blob, int32_t x0, int32_t y0, int32_t w, int32_t h) {
    return reuseVipmLeaf(std::move(blob), heights, materials, x0, y0, w, h, zStep);
  };
  const size_t dirtyLeaves =
      size_t(std::count(dirty.begin() + innerCount, dirty.end(), uint8_t{1}));
  const size_t innerBuilt =
      size_t(std::count_if(nodes.begin(), nodes.begin() + ptrdiff_t(innerCount),
                           [&](const NodeRecord& n) { return int32_t(n.level) >= top; }));
  progress.begin("vipm chunks", dirtyLeaves + innerBuilt);
  parallelFor(leafCount, threads, [&](size_t k, unsigned) {
    const size_t i = innerCount + k;
    if (!dirty[i]) return;
    ++bytesVersion[i];
    if (!keep(i, reuseLeaf, leaves[k])) {
      const auto [x0, y0, w, h] = points(i);
      leaves[k] = buildVipmLeaf(heights, materials, x0, y0, w, h, params);
      normalMaps[i] = buildVipmNormalMap(heights, x0, y0, kLeaf, info.spacingX, info.spacingY);
      built[i] = 1;
    }
    progress.advance(1);
  });
  // Level by level up from the leaves. The 128-cell nodes' error is twice the leaves' largest
  // coarsest error (at least twice --max-error, so that levels stay ordered on flat ground
  // too); each level above has twice the error of the one below, whose nodes stop collapsing
  // there, so that a child draws its coarsest level where its parent takes over (a level's
  // error is at least its children's coarsest errors, which may start above it).
  levelErrors.resize(size_t(layout.levelCount()), -1.0);
  levelErrors[size_t(leafLevel())] = options.maxError;
  for (int32_t level = leafLevel() - 1; level >= top; --level) {
    double largestCoarsest = 0.0;
    std::vector<size_t> members;
    for (size_t i = 0; i < nodes.size(); ++i) {
      if (nodes[i].level == level + 1)
        largestCoarsest =
            std::max(largestCoarsest, double(i >= innerCount ? leaves[i - innerCount].coarsest.error
                                                             : inner[i].coarsest.error));
      if (nodes[i].level == level) members.push_back(i);
    }
    const double below = levelErrors[size_t(level) + 1];
    const double levelError = level + 1 == leafLevel() ? 2.0 * std::max(largestCoarsest, below)
                                                       : std::max(largestCoarsest, 2.0 * below);
    // Where this level's nodes stop: their parents' error (twice theirs) over the geomorph's
    // span, so that their last collapses have finished geomorphing (at kMorphSpan times their
    // error) where the parent takes over with its finest level, their coarsest; the top goes
    // on.
    const double lastError =
        level > 0 ? 2.0 * levelError / kMorphSpan : std::numeric_limits<double>::infinity();
    if (levelError != levelErrors[size_t(level)])
      for (size_t i : members) dirty[i] = 1;
    levelErrors[size_t(level)] = levelError;
    // Kept only while the level's error (every node's error floor) is what it was in the
    // earlier build.
    const bool keepLevel = reuse && reuse->levelError(level) == levelError;
    const bool roots = level == leafLevel() - 1;
    auto reuseNode = [&](std::vector<uint8_t> blob, int32_t x0, int32_t y0, int32_t w, int32_t h) {
      return roots ? reuseVipmRoot(std::move(blob), heights, materials, x0, y0, w, h, zStep)
                   : reuseVipmUpperNode(std::move(blob), heights, x0, y0, w, h, zStep);
    };
    std::atomic<bool> tooDense{false};
    parallelFor(members.size(), threads, [&](size_t k, unsigned) {
      const size_t i = members[k];
      if (!dirty[i] || tooDense) return progress.advance(1);
      ++bytesVersion[i];
      if (!(keepLevel && keep(i, reuseNode, inner[i]))) {
        const auto [x0, y0, w, h] = points(i);
        const int32_t c = cells(i);
        if (roots) {
          inner[i] = buildVipmRoot(heights, materials, childMeshes(i), x0, y0, w, h, zStep,
                                   levelError, lastError, options.compressionLevel);
        } else if (auto node =
                       buildVipmUpperNode(heights, childMeshes(i), x0, y0, c, w, h, zStep,
                                          levelError, lastError, options.compressionLevel)) {
          inner[i] = std::move(*node);
        } else {
          tooDense = true;
          return progress.advance(1);
        }
        normalMaps[i] = buildVipmNormalMap(heights, x0, y0, c, info.spacingX, info.spacingY);
        built[i] = 1;
      }
      progress.advance(1);
    });
    if (tooDense) {
      progress.end();
      tooDenseLevel = level;
      const int32_t above = leafLevel() - 1 - level;  // this level's place above the roots
      return makeError(info.path, tooDenseNodes(above) + "; build with --upper-levels " +
                                      std::to_string(above - 1) + " or fewer");
    }
  }
  progress.end();

  // Every node's fields, and the flange depths from every chunk's deviations.
  Deviations d(layout);
  std::vector<double> seams(nodes.size(), 0.0);
  summary.collapses = 0;
  for (size_t i = 0; i < nodes.size(); ++i) {
    NodeRecord& n = nodes[i];
    const bool leaf = i >= innerCount;
    takeMeshFields(n, leaf ? leaves[i - innerCount].node : inner[i].node);
    d.at(n.level, int32_t(n.x), int32_t(n.y)) =
        leaf ? leaves[i - innerCount].borderDeviation : inner[i].borderDeviation;
    if (!leaf) seams[i] = inner[i].seamDeviation;
    summary.collapses += leaf ? leaves[i - innerCount].collapses : inner[i].collapses;
  }
  setFlangeDepths(nodes, d, seams, zStep);

  std::vector<double> leafSeconds;
  for (size_t k = 0; k < leafCount; ++k)
    if (built[innerCount + k]) leafSeconds.push_back(leaves[k].seconds);
  std::sort(leafSeconds.begin(), leafSeconds.end());
  summary.chunkSecondsMedian = leafSeconds.empty() ? 0.0 : leafSeconds[leafSeconds.size() / 2];
  summary.chunkSecondsMax = leafSeconds.empty() ? 0.0 : leafSeconds.back();
  summary.reusedChunks = uint64_t(std::count(kept.begin(), kept.end(), uint8_t{1}));
  return {};
}

std::vector<VipmInterimNode> VipmChunkSetState::interimNodes(const std::vector<uint32_t>& list,
                                                             unsigned threads) const {
  std::vector<VipmInterimNode> out(list.size());
  parallelFor(list.size(), threads, [&](size_t k, unsigned) {
    const uint32_t i = list[k];
    const auto [x0, y0, w, h] = points(i);
    const int32_t c = cells(i);
    VipmGridChunk grid =
        buildVipmGridChunk(heights, materials, x0, y0, w, h, zStep, options.compressionLevel);
    VipmInterimNode& n = out[k];
    n.node = i;
    n.record = nodes[i];  // its flange depth covers its neighbours' borders; its own is exact
    takeMeshFields(n.record, grid.node);
    n.bytes.bytes = std::move(grid.blob);
    n.bytes.meshBytes = uint32_t(n.bytes.bytes.size());
    const std::vector<uint8_t> normals =
        buildVipmNormalMap(heights, x0, y0, c, info.spacingX, info.spacingY);
    n.bytes.bytes.insert(n.bytes.bytes.end(), normals.begin(), normals.end());
  });
  return out;
}

std::vector<uint32_t> VipmChunkSetState::changedSince(const std::vector<NodeRecord>& before,
                                                      const std::vector<double>& levelErrorsBefore,
                                                      const std::vector<uint8_t>& rebuilt) const {
  std::vector<uint32_t> changed;
  for (size_t i = 0; i < nodes.size(); ++i) {
    const size_t level = nodes[i].level;
    if (rebuilt[i] || levelErrors[level] != levelErrorsBefore[level] ||
        nodes[i].maxSkirtDepth != before[i].maxSkirtDepth)
      changed.push_back(uint32_t(i));
  }
  return changed;
}

VipmInterimNode VipmChunkSetState::handover(uint32_t i) const {
  const std::vector<uint8_t>& mesh = i < innerCount ? inner[i].blob : leaves[i - innerCount].blob;
  VipmInterimNode n;
  n.node = i;
  n.record = nodes[i];
  n.bytes.bytes = mesh;
  n.bytes.meshBytes = uint32_t(mesh.size());
  n.bytes.bytes.insert(n.bytes.bytes.end(), normalMaps[i].begin(), normalMaps[i].end());
  return n;
}

Result<VipmChunkSet> VipmChunkSet::build(const BuildOptions& options, const DemInfo& info,
                                         Heightfield heights, MaterialMap materials,
                                         uint64_t filledVoids, Progress& progress,
                                         const std::function<void(const std::string&)>& warn) {
  auto s = std::make_unique<VipmChunkSetState>();
  s->summary.filledVoids = filledVoids;
  s->options = options;
  s->info = info;
  s->layout = vipmTreeLayout(info, options.vipmUpperLevels);
  s->nodes = enumerateNodes(s->layout);
  s->innerCount = size_t(std::count_if(s->nodes.begin(), s->nodes.end(), [&](const NodeRecord& n) {
    return n.level < s->layout.depth;
  }));
  s->heights = std::move(heights);
  s->bounds.resize(s->innerCount);
  auto zStep = tilesetZStep(s->updateBounds(std::vector<uint8_t>(s->innerCount, 1)),
                            options.maxError, info.path);
  if (!zStep) return zStep.error();
  s->zStep = *zStep;
  s->materials = std::move(materials);
  s->leaves.resize(s->nodes.size() - s->innerCount);
  s->inner.resize(s->innerCount);
  s->normalMaps.resize(s->nodes.size());
  s->bytesVersion.assign(s->nodes.size(), 0);
  // No level errors yet: every node is built.
  const std::optional<VipmChunkReuse> reuse =
      VipmChunkReuse::open(options, info, s->layout, s->zStep);
  const unsigned threads = options.threads ? options.threads : hardwareThreads();
  Status built = s->rebuild(std::vector<uint8_t>(s->nodes.size(), 1), reuse ? &*reuse : nullptr,
                            threads, progress);
  const bool chosen = options.vipmUpperLevels == kVipmUpperLevelsAuto ||
                      options.vipmUpperLevels == kVipmUpperLevelsBySize;
  if (!built && chosen && s->tooDenseLevel >= 0) {
    // Levels chosen by size: as many as the terrain allows, the too dense one and those above
    // it left out (everything is built again, leaves too: the tree's levels change, and this
    // happens only on terrain too rough for them).
    BuildOptions fewer = options;
    fewer.vipmUpperLevels = s->layout.depth - 2 - s->tooDenseLevel;
    warn(info.path + ": " + tooDenseNodes(fewer.vipmUpperLevels + 1) + "; building with " +
         std::to_string(fewer.vipmUpperLevels) + " levels above the roots instead");
    return build(fewer, info, std::move(s->heights), std::move(s->materials), filledVoids, progress,
                 warn);
  }
  if (!built) return built.error();
  s->bytesVersion.assign(s->nodes.size(), 0);
  return VipmChunkSet(std::move(s));
}

Result<std::vector<uint32_t>> VipmChunkSet::apply(std::span<const TerrainEdit> strokes,
                                                  unsigned threads, const VipmInterimSink& interim,
                                                  const VipmNearSink& near) {
  VipmChunkSetState& s = *mState;
  const std::vector<TerrainEdit> list(strokes.begin(), strokes.end());
  const double sx = s.info.spacingX, sy = s.info.spacingY;
  // Refused paint leaves the set as it was.
  if (Status ok = checkPaintMaterials(list, s.materials, s.info.path); !ok) return ok.error();
  // The heights the strokes touch, to put back if the relief outgrows the height step.
  std::vector<std::pair<GridWindow, std::vector<float>>> saved;
  for (const TerrainEdit& e : list) {
    const GridWindow w = editWindow(e, sx, sy, s.heights.columns(), s.heights.rows());
    std::vector<float> before;
    for (int32_t y = w.y0; y <= w.y1; ++y)
      for (int32_t x = w.x0; x <= w.x1; ++x) before.push_back(s.heights(x, y));
    saved.emplace_back(w, std::move(before));
  }
  applyHeightEdits(list, sx, sy, s.heights);
  const std::vector<std::pair<float, float>> boundsBefore = s.bounds;
  std::vector<uint8_t> measure(s.innerCount, 0);
  for (size_t i = 0; i < s.innerCount; ++i)
    for (const auto& [w, unused] : saved) {
      const auto [x0, y0, width, height] = s.points(i);
      if (windowMeets(w, x0, y0, width, height, 0)) measure[i] = 1;
    }
  auto zStep = tilesetZStep(s.updateBounds(measure), s.options.maxError, s.info.path);
  if (!zStep) {
    for (auto it = saved.rbegin(); it != saved.rend(); ++it) {
      size_t k = 0;
      for (int32_t y = it->first.y0; y <= it->first.y1; ++y)
        for (int32_t x = it->first.x0; x <= it->first.x1; ++x) s.heights(x, y) = it->second[k++];
    }
    s.bounds = boundsBefore;
    return zStep.error();
  }
  if (Status ok = applyPaintEdits(list, sx, sy, s.materials, s.info.path); !ok)
    return ok.error();  // not reached: every material was checked above
  s.options.edits.insert(s.options.edits.end(), list.begin(), list.end());

  // What the strokes reach: a chunk's grid points grown by one (its normal map's central
  // differences); everything when the height step changes.
  const bool newStep = *zStep != s.zStep;
  std::vector<uint8_t> dirty(s.nodes.size(), newStep ? 1 : 0);
  s.zStep = *zStep;
  std::vector<uint32_t> reached;
  for (size_t i = 0; i < s.nodes.size(); ++i)
    for (const auto& [w, unused] : saved) {
      const auto [x0, y0, width, height] = s.points(i);
      if (windowMeets(w, x0, y0, width, height, 1)) {
        dirty[i] = 1;
        reached.push_back(uint32_t(i));
        break;
      }
    }
  if (interim && !newStep) {
    // Nodes above the 128-cell ones keep their old meshes meanwhile (their whole grids would
    // be millions of points).
    std::vector<uint32_t> grids;
    for (uint32_t i : reached)
      if (s.nodes[i].level >= s.leafLevel() - 1) grids.push_back(i);
    interim(s.interimNodes(grids, threads ? threads : hardwareThreads()));
  }
  const unsigned workers = threads ? threads : hardwareThreads();
  NullProgress quiet;
  // The nodes above the roots take seconds (their collapses are measured over thousands of
  // cells each); with `near`, the leaves and roots are made and handed over first.
  const int32_t rootLevel = s.leafLevel() - 1;
  const bool twoStages = near && rootLevel > 0;
  std::vector<NodeRecord> before = s.nodes;
  std::vector<double> levelErrorsBefore = s.levelErrors;
  if (twoStages) {
    std::vector<uint8_t> nearDirty = dirty;
    for (size_t i = 0; i < s.innerCount; ++i)
      if (int32_t(s.nodes[i].level) < rootLevel) nearDirty[i] = 0;
    if (Status ok = s.rebuild(nearDirty, nullptr, workers, quiet, rootLevel); !ok)
      return ok.error();
    std::vector<VipmInterimNode> made;
    for (uint32_t i : s.changedSince(before, levelErrorsBefore, nearDirty))
      made.push_back(s.handover(i));
    near(std::move(made), s.levelErrors);
    for (size_t i = 0; i < s.nodes.size(); ++i)
      if (int32_t(s.nodes[i].level) >= rootLevel) dirty[i] = 0;
    before = s.nodes;
    levelErrorsBefore = s.levelErrors;
  }
  const std::vector<uint8_t> rebuilt = dirty;
  if (Status ok = s.rebuild(dirty, nullptr, workers, quiet); !ok) return ok.error();
  return s.changedSince(before, levelErrorsBefore, rebuilt);
}

VipmChunkSet::VipmChunkSet(std::unique_ptr<VipmChunkSetState> state) : mState(std::move(state)) {}
VipmChunkSet::VipmChunkSet(VipmChunkSet&&) noexcept = default;
VipmChunkSet& VipmChunkSet::operator=(VipmChunkSet&&) noexcept = default;
VipmChunkSet::~VipmChunkSet() = default;

const std::vector<NodeRecord>& VipmChunkSet::nodes() const {
  return mState->nodes;
}

NodeBytes VipmChunkSet::nodeBytes(uint32_t node) const {
  const VipmChunkSetState& s = *mState;
  return s.handover(node).bytes;
}

uint32_t VipmChunkSet::bytesVersion(uint32_t node) const {
  return mState->bytesVersion[node];
}

const std::vector<TerrainEdit>& VipmChunkSet::edits() const {
  return mState->options.edits;
}
double VipmChunkSet::zStep() const {
  return mState->zStep;
}
const std::vector<double>& VipmChunkSet::levelErrors() const {
  return mState->levelErrors;
}
const TreeLayout& VipmChunkSet::layout() const {
  return mState->layout;
}
const MaterialMap& VipmChunkSet::materials() const {
  return mState->materials;
}
const BuildOptions& VipmChunkSet::options() const {
  return mState->options;
}
const DemInfo& VipmChunkSet::info() const {
  return mState->info;
}
const BuildSummary& VipmChunkSet::summary() const {
  return mState->summary;
}

}  // namespace terralod
