#include "terralod/build/vipm_chunk_set.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "terralod/build/chunk_pass.h"
#include "terralod/build/tree_layout.h"
#include "terralod/build/vipm_chunks.h"
#include "terralod/core/parallel.h"
#include "terralod/materials/terrain_edits.h"
#include "vipm_cells.h"
#include "vipm_chunk_reuse.h"

namespace terralod {

namespace {

// A chunk's grid points along one axis: clipped at the data's far edge.
int32_t pointsFrom(int32_t first, int32_t cells, int32_t side) {
  return std::min(side, cells - first) + 1;
}

// The height range of root (rx, ry)'s grid points.
double rootRange(const Heightfield& h, const TreeLayout& layout, int32_t rx, int32_t ry) {
  const int32_t x0 = rx * kRoot, y0 = ry * kRoot;
  const int32_t w = pointsFrom(x0, layout.cellsX, kRoot), hh = pointsFrom(y0, layout.cellsY, kRoot);
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (int32_t y = y0; y < y0 + hh; ++y)
    for (int32_t x = x0; x < x0 + w; ++x) {
      lo = std::min(lo, h(x, y));
      hi = std::max(hi, h(x, y));
    }
  return double(hi) - double(lo);
}

// The tileset's height step for the largest root range, or why there is none.
Result<double> tilesetZStep(const std::vector<double>& rootRanges, double maxError,
                            const std::string& subject) {
  const double range = *std::max_element(rootRanges.begin(), rootRanges.end());
  const double zStep = vipmTilesetZStep(maxError, range);
  if (zStep <= maxError) return zStep;
  // Rounding alone would take half the error budget.
  char text[256];
  std::snprintf(text, sizeof text,
                "--max-error %g m is too fine for 16-bit heights over a root's %.0f m of "
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

// How far each drawn chunk's border strays from the source samples, over all its levels.
struct Deviations {
  int32_t leavesX = 0, leavesY = 0, rootsX = 0, rootsY = 0;
  std::vector<double> leaf, root, rootSeams;

  double leafAt(int32_t x, int32_t y) const {
    if (x < 0 || y < 0 || x >= leavesX || y >= leavesY) return 0.0;
    return leaf[size_t(y) * size_t(leavesX) + size_t(x)];
  }
  double rootAt(int32_t x, int32_t y) const {
    if (x < 0 || y < 0 || x >= rootsX || y >= rootsY) return 0.0;
    return root[size_t(y) * size_t(rootsX) + size_t(x)];
  }
  // A root and its leaves.
  double familyAt(int32_t x, int32_t y) const {
    double d = rootAt(x, y);
    for (int32_t k = 0; k < 4; ++k) d = std::max(d, leafAt(2 * x + (k & 1), 2 * y + (k >> 1)));
    return d;
  }
};

// maxSkirtDepth of every node (docs/format.md "Node fields"): two borders drawn side by side
// are at most their deviations apart, so a flange as deep as its own deviation plus the
// largest of any chunk that can be drawn beside it closes the gap.
void setFlangeDepths(std::vector<NodeRecord>& nodes, const Deviations& d, double zStep) {
  static constexpr int32_t kDx[4] = {1, -1, 0, 0}, kDy[4] = {0, 0, 1, -1};
  for (NodeRecord& n : nodes) {
    if (n.level == 0) continue;
    const int32_t x = int32_t(n.x), y = int32_t(n.y);
    double outside = 0.0;
    for (int k = 0; k < 4; ++k) {
      const int32_t nx = x + kDx[k], ny = y + kDy[k];
      outside = std::max(outside, d.leafAt(nx, ny));
      if ((nx >> 1) != (x >> 1) || (ny >> 1) != (y >> 1))  // another root's
        outside = std::max(outside, d.rootAt(nx >> 1, ny >> 1));
    }
    n.maxSkirtDepth = floatAbove(d.leafAt(x, y) + outside + zStep);
  }
  for (NodeRecord& n : nodes) {
    if (n.level != 0) continue;
    const int32_t x = int32_t(n.x), y = int32_t(n.y);
    double outside = 0.0;
    for (int k = 0; k < 4; ++k) outside = std::max(outside, d.familyAt(x + kDx[k], y + kDy[k]));
    // Its children's shared sides: each side's polyline is within the seam deviation.
    const double seams = 2.0 * d.rootSeams[size_t(y) * size_t(d.rootsX) + size_t(x)];
    double depth = std::max(d.rootAt(x, y) + outside, seams) + zStep;
    for (uint32_t c = 0; c < uint32_t(std::popcount(unsigned(n.childMask))); ++c)
      depth = std::max(depth, double(nodes[n.firstChild + c].maxSkirtDepth));
    n.maxSkirtDepth = floatAbove(depth);
  }
}

}  // namespace

TreeLayout vipmTreeLayout(const DemInfo& info) {
  TreeLayout l;
  l.cellsX = info.columns - 1;
  l.cellsY = info.rows - 1;
  l.leafCells = kLeaf;
  l.depth = 1;
  l.rootCells = kRoot;
  l.rootsX = (l.cellsX + kRoot - 1) / kRoot;
  l.rootsY = (l.cellsY + kRoot - 1) / kRoot;
  return l;
}

struct VipmChunkSetState {
  BuildOptions options;  // options.edits: every stroke applied so far
  DemInfo info;
  TreeLayout layout;
  Heightfield heights;
  MaterialMap materials;
  double zStep = 0.0, rootLevelError = 0.0;
  std::vector<NodeRecord> nodes;
  size_t rootCount = 0;
  std::vector<VipmLeaf> leaves;
  std::vector<VipmRoot> roots;
  std::vector<std::vector<uint8_t>> normalMaps;  // per node: its texture blob
  std::vector<double> rootRanges;                // per root: its grid points' height range
  BuildSummary summary;

  // The grid points of node i: south-west point and size.
  std::array<int32_t, 4> points(size_t i) const {
    const NodeRecord& n = nodes[i];
    const int32_t cells = i < rootCount ? kRoot : kLeaf;
    const int32_t x0 = int32_t(n.x) * cells, y0 = int32_t(n.y) * cells;
    return {x0, y0, pointsFrom(x0, layout.cellsX, cells), pointsFrom(y0, layout.cellsY, cells)};
  }

  // `nodes` as their whole grids, with their normal maps (VipmChunkSet::apply's interim).
  std::vector<VipmInterimNode> interimNodes(const std::vector<uint32_t>& nodes,
                                            unsigned threads) const;

  // Builds the leaves and roots marked in `dirty` (per node; all roots too when the roots'
  // level error changes), keeping what `reuse` has for them where no new stroke reaches, then
  // every node's fields and flange depths.
  void rebuild(std::vector<uint8_t> dirty, const VipmChunkReuse* reuse, unsigned threads,
               Progress& progress);
};

void VipmChunkSetState::rebuild(std::vector<uint8_t> dirty, const VipmChunkReuse* reuse,
                                unsigned threads, Progress& progress) {
  const size_t leafCount = nodes.size() - rootCount;
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
    auto chunk = reuseChunk(std::vector<uint8_t>(old->mesh().begin(), old->mesh().end()), heights,
                            materials, x0, y0, w, h, zStep);
    if (!chunk) return false;
    out = std::move(*chunk);
    normalMaps[i].assign(old->texture().begin(), old->texture().end());
    kept[i] = 1;
    return true;
  };
  const size_t dirtyLeaves = size_t(std::count(dirty.begin() + rootCount, dirty.end(), uint8_t{1}));
  progress.begin("vipm chunks", dirtyLeaves + rootCount);
  parallelFor(leafCount, threads, [&](size_t k, unsigned) {
    const size_t i = rootCount + k;
    if (!dirty[i]) return;
    if (!keep(i, reuseVipmLeaf, leaves[k])) {
      const auto [x0, y0, w, h] = points(i);
      leaves[k] = buildVipmLeaf(heights, materials, x0, y0, w, h, params);
      normalMaps[i] = buildVipmNormalMap(heights, x0, y0, kLeaf, info.spacingX, info.spacingY);
      built[i] = 1;
    }
    progress.advance(1);
  });
  // The roots' level error: at least twice every leaf's coarsest error, so that a leaf draws
  // its coarsest level where its root takes over (and levels stay ordered on flat ground too).
  double largestCoarsest = 0.0;
  for (const VipmLeaf& leaf : leaves)
    largestCoarsest = std::max(largestCoarsest, double(leaf.coarsest.error));
  const double levelError = 2.0 * std::max(largestCoarsest, options.maxError);
  if (levelError != rootLevelError) std::fill(dirty.begin(), dirty.begin() + rootCount, 1);
  rootLevelError = levelError;
  // Roots are kept only while the roots' level error (every root's error floor) is what it
  // was in the earlier build.
  const bool keepRoots = reuse && reuse->rootLevelError() == rootLevelError;
  parallelFor(rootCount, threads, [&](size_t r, unsigned) {
    if (!dirty[r]) return progress.advance(1);
    if (!(keepRoots && keep(r, reuseVipmRoot, roots[r]))) {
      const NodeRecord& n = nodes[r];
      std::vector<const CoarseMesh*> children;
      for (uint32_t c = 0; c < uint32_t(std::popcount(unsigned(n.childMask))); ++c)
        children.push_back(&leaves[n.firstChild + c - rootCount].coarsest);
      const auto [x0, y0, w, h] = points(r);
      roots[r] = buildVipmRoot(heights, materials, children, x0, y0, w, h, zStep, rootLevelError,
                               options.compressionLevel);
      normalMaps[r] = buildVipmNormalMap(heights, x0, y0, kRoot, info.spacingX, info.spacingY);
      built[r] = 1;
    }
    progress.advance(1);
  });
  progress.end();

  // Every node's fields, and the flange depths from every chunk's deviations.
  Deviations d;
  d.leavesX = layout.chunksX(1);
  d.leavesY = layout.chunksY(1);
  d.rootsX = layout.rootsX;
  d.rootsY = layout.rootsY;
  d.leaf.assign(size_t(d.leavesX) * size_t(d.leavesY), 0.0);
  d.root.assign(rootCount, 0.0);
  d.rootSeams.assign(rootCount, 0.0);
  summary.collapses = 0;
  for (size_t k = 0; k < leafCount; ++k) {
    NodeRecord& n = nodes[rootCount + k];
    takeMeshFields(n, leaves[k].node);
    d.leaf[size_t(n.y) * size_t(d.leavesX) + n.x] = leaves[k].borderDeviation;
    summary.collapses += leaves[k].collapses;
  }
  for (size_t r = 0; r < rootCount; ++r) {
    NodeRecord& n = nodes[r];
    takeMeshFields(n, roots[r].node);
    const size_t at = size_t(n.y) * size_t(layout.rootsX) + n.x;
    d.root[at] = roots[r].borderDeviation;
    d.rootSeams[at] = roots[r].seamDeviation;
    summary.collapses += roots[r].collapses;
  }
  setFlangeDepths(nodes, d, zStep);

  std::vector<double> leafSeconds;
  for (size_t k = 0; k < leafCount; ++k)
    if (built[rootCount + k]) leafSeconds.push_back(leaves[k].seconds);
  std::sort(leafSeconds.begin(), leafSeconds.end());
  summary.chunkSecondsMedian = leafSeconds.empty() ? 0.0 : leafSeconds[leafSeconds.size() / 2];
  summary.chunkSecondsMax = leafSeconds.empty() ? 0.0 : leafSeconds.back();
  summary.reusedChunks = uint64_t(std::count(kept.begin(), kept.end(), uint8_t{1}));
}

std::vector<VipmInterimNode> VipmChunkSetState::interimNodes(const std::vector<uint32_t>& list,
                                                             unsigned threads) const {
  std::vector<VipmInterimNode> out(list.size());
  parallelFor(list.size(), threads, [&](size_t k, unsigned) {
    const uint32_t i = list[k];
    const auto [x0, y0, w, h] = points(i);
    const int32_t cells = i < rootCount ? kRoot : kLeaf;
    VipmGridChunk grid =
        buildVipmGridChunk(heights, materials, x0, y0, w, h, zStep, options.compressionLevel);
    VipmInterimNode& n = out[k];
    n.node = i;
    n.record = nodes[i];  // its flange depth covers its neighbours' borders; its own is exact
    takeMeshFields(n.record, grid.node);
    n.bytes.bytes = std::move(grid.blob);
    n.bytes.meshBytes = uint32_t(n.bytes.bytes.size());
    const std::vector<uint8_t> normals =
        buildVipmNormalMap(heights, x0, y0, cells, info.spacingX, info.spacingY);
    n.bytes.bytes.insert(n.bytes.bytes.end(), normals.begin(), normals.end());
  });
  return out;
}

Result<VipmChunkSet> VipmChunkSet::build(const BuildOptions& options, const DemInfo& info,
                                         Heightfield heights, MaterialMap materials,
                                         uint64_t filledVoids, Progress& progress) {
  auto s = std::make_unique<VipmChunkSetState>();
  s->summary.filledVoids = filledVoids;
  s->options = options;
  s->info = info;
  s->layout = vipmTreeLayout(info);
  s->nodes = enumerateNodes(s->layout);
  s->rootCount = size_t(s->layout.rootsX) * size_t(s->layout.rootsY);
  for (size_t r = 0; r < s->rootCount; ++r)
    s->rootRanges.push_back(
        rootRange(heights, s->layout, int32_t(s->nodes[r].x), int32_t(s->nodes[r].y)));
  auto zStep = tilesetZStep(s->rootRanges, options.maxError, info.path);
  if (!zStep) return zStep.error();
  s->zStep = *zStep;
  s->heights = std::move(heights);
  s->materials = std::move(materials);
  s->leaves.resize(s->nodes.size() - s->rootCount);
  s->roots.resize(s->rootCount);
  s->normalMaps.resize(s->nodes.size());
  s->rootLevelError = -1.0;  // none yet: every root is built
  const std::optional<VipmChunkReuse> reuse = VipmChunkReuse::open(options, info, s->zStep);
  const unsigned threads = options.threads ? options.threads : hardwareThreads();
  s->rebuild(std::vector<uint8_t>(s->nodes.size(), 1), reuse ? &*reuse : nullptr, threads,
             progress);
  return VipmChunkSet(std::move(s));
}

Result<std::vector<uint32_t>> VipmChunkSet::apply(std::span<const TerrainEdit> strokes,
                                                  unsigned threads,
                                                  const VipmInterimSink& interim) {
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
  std::vector<double> ranges = s.rootRanges;
  for (size_t r = 0; r < s.rootCount; ++r)
    for (const auto& [w, unused] : saved) {
      const auto [x0, y0, width, height] = s.points(r);
      if (windowMeets(w, x0, y0, width, height, 0))
        ranges[r] = rootRange(s.heights, s.layout, int32_t(s.nodes[r].x), int32_t(s.nodes[r].y));
    }
  auto zStep = tilesetZStep(ranges, s.options.maxError, s.info.path);
  if (!zStep) {
    for (auto it = saved.rbegin(); it != saved.rend(); ++it) {
      size_t k = 0;
      for (int32_t y = it->first.y0; y <= it->first.y1; ++y)
        for (int32_t x = it->first.x0; x <= it->first.x1; ++x) s.heights(x, y) = it->second[k++];
    }
    return zStep.error();
  }
  if (Status ok = applyPaintEdits(list, sx, sy, s.materials, s.info.path); !ok)
    return ok.error();  // not reached: every material was checked above
  s.rootRanges = std::move(ranges);
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
  if (interim && !newStep) interim(s.interimNodes(reached, threads ? threads : hardwareThreads()));
  const std::vector<NodeRecord> before = s.nodes;
  const std::vector<uint8_t> rebuilt = dirty;
  const double rootLevelBefore = s.rootLevelError;
  NullProgress quiet;
  s.rebuild(dirty, nullptr, threads ? threads : hardwareThreads(), quiet);
  std::vector<uint32_t> changed;
  for (size_t i = 0; i < s.nodes.size(); ++i) {
    const bool root = i < s.rootCount;
    if (rebuilt[i] || (root && s.rootLevelError != rootLevelBefore) ||
        s.nodes[i].maxSkirtDepth != before[i].maxSkirtDepth)
      changed.push_back(uint32_t(i));
  }
  return changed;
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
  const std::vector<uint8_t>& mesh =
      node < s.rootCount ? s.roots[node].blob : s.leaves[node - s.rootCount].blob;
  NodeBytes b;
  b.bytes = mesh;
  b.meshBytes = uint32_t(mesh.size());
  b.bytes.insert(b.bytes.end(), s.normalMaps[node].begin(), s.normalMaps[node].end());
  return b;
}

const std::vector<TerrainEdit>& VipmChunkSet::edits() const {
  return mState->options.edits;
}
double VipmChunkSet::zStep() const {
  return mState->zStep;
}
double VipmChunkSet::rootLevelError() const {
  return mState->rootLevelError;
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
