#include "vipm_verifier.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <unordered_map>

#include "terralod/core/parallel.h"
#include "terralod/format/chunk_position.h"
#include "terralod/format/vipm_chunk_codec.h"
#include "terralod/materials/dem_classification.h"
#include "terralod/materials/material_raster.h"
#include "terralod/materials/terrain_edits.h"
#include "terralod/vipm/collapse_order.h"
#include "vipm_chunk_check.h"

namespace terralod {
namespace {

// What the cross-chunk checks need of a checked chunk.
struct Checked {
  bool ok = false;
  int64_t x0 = 0, y0 = 0;
  int32_t width = 0, height = 0;
  std::array<SideEnvelope, 4> sides;  // south, east, north, west
  std::vector<double> finest, coarsest;
  std::array<std::vector<double>, 4> quarters;  // roots: their finest LOD's
  double lastError = 0;                         // recorded error of its coarsest LOD
  // Nodes above the roots: their finest level's points; every node but leaves: its coarsest's.
  std::vector<std::array<double, 3>> finestPoints, coarsestPoints;
  bool geomorphs = false;  // it has collapses (its last one geomorphs)
};

// The source's materials as the tileset's metadata says they were made; nullopt when they
// came from a raster verify was not given.
Result<std::optional<MaterialMap>> sourceMaterials(const TilesetReader& tileset,
                                                   const std::string& sourcePath,
                                                   const VerifyOptions& options) {
  const std::string& from = tileset.metadata().materialsSource;
  if (from != "classification" && options.materialsPath.empty())
    return std::optional<MaterialMap>{};
  auto dem = DemReader::open(sourcePath, tilesetDemOptions(tileset));
  if (!dem) return dem.error();
  auto map = from == "classification"
                 ? classifyDem(**dem)
                 : readMaterialRaster(options.materialsPath, **dem, {options.palettePath});
  if (!map) return map.error();
  const DemInfo& info = (*dem)->info();
  if (Status s = applyPaintEdits(tileset.metadata().edits, info.spacingX, info.spacingY, *map,
                                 tileset.name());
      !s)
    return s.error();
  return std::optional<MaterialMap>(std::move(*map));
}

// Side s's line (the fixed coordinate) and first coordinate along it.
std::pair<int64_t, int64_t> sideLine(const Checked& c, int s) {
  switch (s) {
    case 0:
      return {c.y0, c.x0};
    case 1:
      return {c.x0 + c.width - 1, c.y0};
    case 2:
      return {c.y0 + c.height - 1, c.x0};
    default:
      return {c.x0, c.y0};
  }
}

// The coarsest level's vertices of a chunk (grid x, grid y, stored height), sorted: what the
// node above it joins.
std::vector<std::array<double, 3>> coarsestLevelPoints(const VipmChunkData& c, int64_t x0,
                                                       int64_t y0) {
  const uint32_t n = c.vertexCount(), r = c.collapseCount();
  std::vector<uint32_t> to(n);
  for (uint32_t v = 0; v < n; ++v) to[v] = v;
  for (uint32_t j = 0; j < r; ++j) to[n - 1 - j] = c.targets[j];
  auto resolve = [&](uint32_t v) {
    while (to[v] != v) v = to[v];
    return v;
  };
  std::vector<bool> used(n);
  for (size_t k = 0; k + 2 < c.indices.size(); k += 3) {
    const uint32_t a = resolve(c.indices[k]), b = resolve(c.indices[k + 1]),
                   d = resolve(c.indices[k + 2]);
    if (a == b || b == d || a == d) continue;
    used[a] = used[b] = used[d] = true;
  }
  std::vector<std::array<double, 3>> out;
  for (uint32_t v = 0; v < n; ++v)
    if (used[v])
      out.push_back({double(x0 + int64_t(c.points[v] % c.width)),
                     double(y0 + int64_t(c.points[v] / c.width)),
                     c.zBase + double(c.heights[v]) * c.zStep});
  std::sort(out.begin(), out.end());
  return out;
}

uint64_t key(uint32_t level, int64_t x, int64_t y) {
  return (uint64_t(level) << 60) | (uint64_t(x & 0x3FFFFFFF) << 30) | uint64_t(y & 0x3FFFFFFF);
}

}  // namespace

Status verifyVipmTileset(const TilesetReader& tileset, const Heightfield& heights,
                         const std::string& sourcePath, const VerifyOptions& options,
                         Progress& progress, VerifyReport& report) {
  const TilesetHeader& h = tileset.header();
  const auto& nodes = tileset.nodes();
  // The leaves, the 128-cell roots above them, and any levels above those.
  const uint32_t leafLevel = h.levelCount - 1, rootLevel = leafLevel - 1;
  auto materials = sourceMaterials(tileset, sourcePath, options);
  if (!materials) return materials.error();
  const MaterialMap* map = *materials ? &**materials : nullptr;
  const MaterialRules promised =
      tileset.metadata().materialRules ? MaterialRules::kOn : MaterialRules::kOff;

  VipmVerifyStats stats;
  stats.rulesPromised = promised == MaterialRules::kOn;
  stats.materialsFromSource = map != nullptr;
  stats.worstErrorMargin = std::numeric_limits<double>::infinity();
  stats.worstFlangeMargin = std::numeric_limits<double>::infinity();
  std::mutex mutex;
  auto addFailure = [&](const std::string& text) {
    std::lock_guard lock(mutex);
    ++report.failureCount;
    if (report.failures.size() < options.maxListedFailures) report.failures.push_back(text);
  };
  auto name = [&](uint32_t i) {
    const NodeRecord& n = nodes[i];
    return tileset.name() + ": chunk " + std::to_string(i) + " (level " + std::to_string(n.level) +
           ", " + std::to_string(n.x) + "," + std::to_string(n.y) + ")";
  };

  // The node record against its blob.
  auto checkRecord = [&](uint32_t i, const VipmChunkData& chunk) {
    const NodeRecord& n = nodes[i];
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (uint16_t z : chunk.heights) {
      lo = std::min(lo, chunk.zBase + z * chunk.zStep);
      hi = std::max(hi, chunk.zBase + z * chunk.zStep);
    }
    if (n.minZ > lo || n.maxZ < hi || n.vertexCount != chunk.vertexCount() ||
        n.triangleCount != chunk.triangleCount() || n.skirtTriangleCount != 0)
      addFailure(name(i) + ": the node record does not match its blob");
  };

  // A checked chunk's normal map and level figures (under `mutex`).
  auto addCounts = [&](const NodeRecord& n, const VipmChunkData& chunk, const VipmChunkCheck& c,
                       bool normals, const NormalMapCheck& normalCheck) {
    stats.normalMapsChecked += normals ? 1 : 0;
    stats.normalTexels += normalCheck.texels;
    stats.worstNormalDeviation = std::max(stats.worstNormalDeviation, normalCheck.worst);
    LevelCheck& level = report.levels[n.level];
    level.maxError = std::max(level.maxError, c.finestError);
    level.samples += uint64_t(chunk.width) * chunk.height;
    level.uncovered += c.uncovered;
    level.heightStep = std::max(level.heightStep, chunk.zStep);
  };

  std::vector<Checked> checked(nodes.size());
  const unsigned threads = options.threads ? options.threads : hardwareThreads();
  progress.begin("verifying VIPM chunks", nodes.size());
  parallelFor(nodes.size(), threads, [&](size_t index, unsigned) {
    progress.advance();
    const uint32_t i = uint32_t(index);
    const NodeRecord& n = nodes[i];
    auto bytes = tileset.readNode(i);
    if (!bytes) return addFailure(bytes.error().message);
    auto chunk = decodeVipmChunk(bytes->mesh(), name(i));
    if (!chunk) return addFailure(chunk.error().message);
    const auto [x0, y0] = chunkCellOrigin(h, n);
    // Its normal map: one BC5 layer, the source's central differences (not the mesh's).
    const uint32_t cells = uint32_t(h.chunkCells(n.level));
    auto normals = decodeVipmNormalMap(bytes->texture(), cells, name(i));
    NormalMapCheck normalCheck;
    if (!normals)
      addFailure(normals.error().message);
    else {
      normalCheck = checkVipmNormalMap(*normals, x0, y0, heights, h.spacingX, h.spacingY,
                                       cells / vipmNormalMapCells(cells));
      if (!normalCheck.problem.empty()) addFailure(name(i) + ": " + normalCheck.problem);
    }
    if (n.level < rootLevel) {
      // Above the roots: sampled levels against every sample, its sides at every level.
      VipmChunkCheck c = checkVipmUpperNode(*chunk, x0, y0, heights);
      for (const std::string& p : c.problems) addFailure(name(i) + ": " + p);
      Checked& out = checked[i];
      out.ok = true;
      out.x0 = x0;
      out.y0 = y0;
      out.width = chunk->width;
      out.height = chunk->height;
      out.sides = std::move(c.sides);
      out.finestPoints = std::move(c.finestPoints);
      out.coarsestPoints = std::move(c.coarsestPoints);
      out.lastError = chunk->collapseCount() ? double(chunk->errors.back()) * chunk->errorStep
                                             : double(chunk->finestError);
      out.geomorphs = chunk->collapseCount() != 0;
      if (chunk->collapseCount() != 0 &&
          double(chunk->errors.front()) * chunk->errorStep < h.levelError[n.level])
        addFailure(name(i) + ": its first collapse's error is below its level's error " +
                   std::to_string(h.levelError[n.level]) + " m");
      checkRecord(i, *chunk);
      std::lock_guard lock(mutex);
      stats.lods += c.levels;
      ++stats.upperNodes;
      stats.worstErrorMargin = std::min(stats.worstErrorMargin, c.worstMargin);
      addCounts(n, *chunk, c, normals.ok(), normalCheck);
      return;
    }
    // Roots are blot chunks: simplified without the material rules.
    VipmChunkCheck c = checkVipmChunk(*chunk, x0, y0, heights, map,
                                      n.level == rootLevel ? MaterialRules::kOff : promised);
    for (const std::string& p : c.problems) addFailure(name(i) + ": " + p);
    Checked& out = checked[i];
    std::vector<std::array<double, 3>> coarsestPoints;
    if (n.level == rootLevel && rootLevel > 0) coarsestPoints = coarsestLevelPoints(*chunk, x0, y0);
    out = {true,
           x0,
           y0,
           chunk->width,
           chunk->height,
           std::move(c.sides),
           std::move(c.finestHeights),
           std::move(c.coarsestHeights),
           std::move(c.quarters),
           chunk->collapseCount() ? double(chunk->errors.back()) * chunk->errorStep
                                  : double(chunk->finestError),
           {},
           std::move(coarsestPoints),
           chunk->collapseCount() != 0};
    checkRecord(i, *chunk);
    // A root draws its children's coarsest LODs until its allowance passes its level error.
    if (n.level == rootLevel && chunk->collapseCount() != 0 &&
        double(chunk->errors.front()) * chunk->errorStep < h.levelError[rootLevel])
      addFailure(name(i) + ": its first collapse's error is below the roots' level error " +
                 std::to_string(h.levelError[rootLevel]) + " m");
    if (n.level == rootLevel && c.seamGap > double(n.maxSkirtDepth) + kVerifySlack)
      addFailure(name(i) + ": its flanges (" + std::to_string(n.maxSkirtDepth) +
                 " m) do not close the gap between its children's sides (" +
                 std::to_string(c.seamGap) + " m)");
    if (n.level == leafLevel && chunk->finestError > h.leafError + kVerifySlack)
      addFailure(name(i) + ": finest LOD's error " + std::to_string(chunk->finestError) +
                 " m is over --max-error " + std::to_string(h.leafError) + " m");
    std::lock_guard lock(mutex);
    stats.lods += c.levels;
    stats.worstErrorMargin = std::min(stats.worstErrorMargin, c.worstMargin);
    if (n.level == leafLevel) {  // the material rules apply to leaves
      stats.collapsesChecked += c.collapsesChecked;
      stats.ruleViolations += c.ruleViolations;
    }
    stats.materialMismatches += c.materialMismatches;
    stats.partLevelsChecked += c.partLevelsChecked;
    if (n.level == rootLevel && c.seamGap > 0)
      stats.worstFlangeMargin = std::min(stats.worstFlangeMargin, n.maxSkirtDepth - c.seamGap);
    addCounts(n, *chunk, c, normals.ok(), normalCheck);
  });

  std::unordered_map<uint64_t, uint32_t> byPlace;
  for (uint32_t i = 0; i < nodes.size(); ++i)
    byPlace[key(nodes[i].level, nodes[i].x, nodes[i].y)] = i;
  auto find = [&](uint32_t level, int64_t x, int64_t y) -> std::optional<uint32_t> {
    if (x < 0 || y < 0) return std::nullopt;
    const auto it = byPlace.find(key(level, x, y));
    return it == byPlace.end() ? std::nullopt : std::optional(it->second);
  };

  const double slack = kVerifySlack + kVipmFloatSlack * std::max(std::fabs(h.extentMin[2]),
                                                                 std::fabs(h.extentMax[2]));
  for (uint32_t i = 0; i < nodes.size(); ++i) {
    const NodeRecord& n = nodes[i];
    const Checked& a = checked[i];
    if (!a.ok) continue;
    // A root's finest LOD is its children's coarsest LODs joined; its error bound covers them.
    if (n.level == leafLevel && a.lastError > h.levelError[rootLevel] / 2 + slack)
      addFailure(name(i) + ": coarsest LOD's error " + std::to_string(a.lastError) +
                 " m is over half the roots' level error");
    // A node above the roots: its finest level holds exactly its children's coarsest levels'
    // points (joined, their cracks closed), and each child's coarsest level is within this
    // level's error, so it is what the child draws where this node takes over.
    if (n.level < rootLevel) {
      std::vector<std::array<double, 3>> children;
      bool all = true;
      for (uint32_t k = 0; k < uint32_t(std::popcount(unsigned(n.childMask))); ++k) {
        const uint32_t c = n.firstChild + k;
        all = all && checked[c].ok;
        if (!checked[c].ok) continue;
        children.insert(children.end(), checked[c].coarsestPoints.begin(),
                        checked[c].coarsestPoints.end());
        if (checked[c].lastError > h.levelError[n.level] + slack)
          addFailure(name(c) + ": coarsest LOD's error " + std::to_string(checked[c].lastError) +
                     " m is over its parent level's error " +
                     std::to_string(h.levelError[n.level]) + " m");
        // Its last collapse finishes geomorphing at kMorphSpan times its error: by then its
        // parent takes over, or the child still slides where the parent stands still.
        else if (checked[c].geomorphs &&
                 checked[c].lastError > h.levelError[n.level] / kMorphSpan + slack)
          addFailure(name(c) + ": last collapse's error " + std::to_string(checked[c].lastError) +
                     " m is over its parent level's error over the geomorph's span (" +
                     std::to_string(h.levelError[n.level] / kMorphSpan) +
                     " m): it would still be geomorphing where its parent takes over");
        if (nodes[c].maxSkirtDepth > n.maxSkirtDepth)
          addFailure(name(i) + ": its flanges are shallower than child " + std::to_string(c) +
                     "'s");
      }
      std::sort(children.begin(), children.end());
      children.erase(std::unique(children.begin(), children.end()), children.end());
      if (all && children != a.finestPoints)
        addFailure(name(i) + ": its finest level's points are not its children's coarsest");
      else if (all)
        ++stats.upperJoins;
    }
    if (n.level == rootLevel)
      for (int q = 0; q < 4; ++q) {
        const auto child = find(leafLevel, 2 * int64_t(n.x) + (q & 1), 2 * int64_t(n.y) + (q >> 1));
        if (!child || !checked[*child].ok) continue;
        const Checked& c = checked[*child];
        // A root no wider than a leaf has one child, drawn whole.
        const bool whole = a.quarters[size_t(q)].empty();
        const std::vector<double>& quarter = whole ? a.finest : a.quarters[size_t(q)];
        const int32_t stride = whole ? a.width : int32_t(kVipmLeafCells + 1);
        if (nodes[*child].maxSkirtDepth > n.maxSkirtDepth)
          addFailure(name(i) + ": its flanges are shallower than child " + std::to_string(*child) +
                     "'s");
        double worst = 0;
        for (int32_t y = 0; y < c.height; ++y)
          for (int32_t x = 0; x < c.width; ++x) {
            const double d =
                std::fabs(quarter[size_t(y * stride + x)] - c.coarsest[size_t(y * c.width + x)]);
            worst = std::max(worst, std::isnan(d) ? std::numeric_limits<double>::infinity() : d);
            ++stats.fallbackSamples;
          }
        stats.fallbackMismatch = std::max(stats.fallbackMismatch, worst);
        if (worst > slack)
          addFailure(name(i) + ": differs from child " + std::to_string(*child) +
                     "'s coarsest LOD by " + std::to_string(worst) + " m");
      }
    // Flanges: every chunk that can be drawn beside this one, at any of its LODs: across
    // each side, at every level, but its own ancestors.
    for (int s = 0; s < 4; ++s) {
      std::vector<uint32_t> others;
      const int64_t c = h.chunkCells(n.level), x0 = int64_t(n.x) * c, y0 = int64_t(n.y) * c;
      // A grid point just outside side s, and the run along it.
      const int64_t outX = s == 1 ? x0 + c : s == 3 ? x0 - 1 : x0;
      const int64_t outY = s == 0 ? y0 - 1 : s == 2 ? y0 + c : y0;
      const bool alongX = s % 2 == 0;
      for (uint32_t m = 0; m < h.levelCount; ++m) {
        const int64_t cm = h.chunkCells(m);
        if (outX < 0 || outY < 0) break;
        for (int64_t k = 0; k * cm < c; ++k) {
          const int64_t px = alongX ? x0 + k * cm : outX, py = alongX ? outY : y0 + k * cm;
          if (m <= n.level && (alongX ? py / cm == y0 / cm : px / cm == x0 / cm)) continue;
          if (auto o = find(m, px / cm, py / cm))
            if (std::find(others.begin(), others.end(), *o) == others.end()) others.push_back(*o);
          if (m <= n.level) break;  // one node of a level as coarse or coarser
        }
      }
      const auto [line, start] = sideLine(a, s);
      for (uint32_t o : others) {
        const Checked& b = checked[o];
        if (!b.ok) continue;
        const int opposite = (s + 2) % 4;
        const auto [otherLine, otherStart] = sideLine(b, opposite);
        if (otherLine != line) continue;
        const SideEnvelope& mine = a.sides[s];
        const SideEnvelope& theirs = b.sides[opposite];
        const int64_t from = std::max(start, otherStart);
        const int64_t to =
            std::min(start + int64_t(mine.high.size()), otherStart + int64_t(theirs.low.size()));
        if (from >= to) continue;
        double gap = 0;
        for (int64_t k = from; k < to; ++k)
          gap = std::max(gap, mine.high[size_t(k - start)] - theirs.low[size_t(k - otherStart)]);
        const double margin = double(n.maxSkirtDepth) - gap;
        ++stats.flangePairs;
        report.skirtSamples += uint64_t(to - from);
        stats.worstFlangeMargin = std::min(stats.worstFlangeMargin, margin);
        if (margin < -slack)
          addFailure(name(i) + ": its flange (" + std::to_string(n.maxSkirtDepth) +
                     " m) does not reach chunk " + std::to_string(o) + " (gap " +
                     std::to_string(gap) + " m)");
      }
    }
  }
  report.skirtPairs = stats.flangePairs;
  report.worstSkirtMargin = stats.worstFlangeMargin;
  report.vipm = stats;
  return {};
}

}  // namespace terralod
