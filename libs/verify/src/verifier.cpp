#include "terralod/verify/verifier.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <optional>
#include <unordered_map>

#include "terralod/core/parallel.h"
#include "terralod/core/sample_raster.h"
#include "terralod/format/chunk_position.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/materials/terrain_edits.h"
#include "terralod/raster/dem_reader.h"
#include "terralod/raster/void_fill.h"
#include "vipm_verifier.h"

namespace terralod {
namespace {

constexpr double kTolerance = kVerifySlack;

// One point of a chunk side: the drawn top over the morph range and the skirt's depth there.
struct SidePoint {
  int32_t coord;      // along the side
  double top0, top1;  // unmorphed / fully morphed surface height
  double depth;       // skirt depth (0 when the side has no skirt)
};

struct ChunkSides {
  std::array<std::vector<SidePoint>, 4> sides;  // south, east, north, west
};

struct Decoded {
  int64_t x0, y0, side;
  ChunkGeometry geometry;
};

// Heights at the samples of a window, NaN where no triangle reached.
struct Window {
  int64_t x0, y0, w, h;
  std::vector<double> values;
  double& at(int64_t x, int64_t y) { return values[size_t((y - y0) * w + (x - x0))]; }
};

Window makeWindow(int64_t x0, int64_t y0, int64_t x1, int64_t y1) {
  Window win{x0, y0, x1 - x0 + 1, y1 - y0 + 1, {}};
  win.values.assign(size_t(win.w * win.h), std::nan(""));
  return win;
}

// Rasterises a chunk's surface (morph parameter t) into the window.
void rasterizeSurface(const Decoded& d, double t, Window& win) {
  for (const ChunkPart& part : d.geometry.parts) {
    auto vertex = [&](uint32_t i) {
      const ChunkVertex& v = part.vertices[i];
      return SampleVertex{d.x0 + v.x, d.y0 + v.y, chunkVertexHeight(d.geometry, v, t)};
    };
    for (uint32_t k = 0; k < part.surfaceIndexCount; k += 3) {
      rasterizeTriangle(vertex(part.indices[k]), vertex(part.indices[k + 1]),
                        vertex(part.indices[k + 2]), win.x0, win.x0 + win.w - 1, win.y0,
                        win.y0 + win.h - 1,
                        [&](int64_t x, int64_t y, double z) { win.at(x, y) = z; });
    }
  }
}

// The side profiles of a decoded chunk: surface vertices on each side line, with the skirt
// bottoms found among skirt-only vertices at the same points. A chunk split into parts (each
// within its index range) may hold a side vertex in two parts and its skirt in one of them:
// the points and bottoms of all parts are gathered before they are matched.
ChunkSides sideProfiles(const Decoded& d) {
  ChunkSides out;
  for (int s = 0; s < 4; ++s) {
    const bool vertical = s == 1 || s == 3;
    const int64_t line = s == 0 ? 0 : s == 1 ? d.side : s == 2 ? d.side : 0;
    std::unordered_map<int32_t, SidePoint> points;
    std::unordered_map<int32_t, std::pair<double, double>> bottoms;  // unmorphed, morphed
    for (const ChunkPart& part : d.geometry.parts) {
      std::vector<uint8_t> role(part.vertices.size(), 0);  // 1 surface, 2 skirt only
      for (uint32_t k = 0; k < part.indices.size(); ++k)
        role[part.indices[k]] |= k < part.surfaceIndexCount ? 1 : 2;
      for (size_t i = 0; i < part.vertices.size(); ++i) {
        const ChunkVertex& v = part.vertices[i];
        if ((vertical ? v.x : v.y) != line) continue;
        const int32_t along = vertical ? v.y : v.x;
        const double z0 = chunkVertexHeight(d.geometry, v);
        const double z1 = z0 + v.morphDelta * d.geometry.zStep;
        if (role[i] & 1) {
          points[along] = {along, z0, z1, 0.0};
        } else if (role[i] & 2) {
          auto [it, fresh] = bottoms.try_emplace(along, z0, z1);
          if (!fresh)
            it->second = {std::min(it->second.first, z0), std::min(it->second.second, z1)};
        }
      }
    }
    for (auto& [along, p] : points) {
      const auto b = bottoms.find(along);
      // The skirt's depth is the smaller of its unmorphed and fully morphed depths.
      p.depth = b == bottoms.end()
                    ? 0.0
                    : std::max(0.0, std::min(p.top0 - b->second.first, p.top1 - b->second.second));
      out.sides[s].push_back(p);
    }
  }
  for (auto& side : out.sides)
    std::sort(side.begin(), side.end(),
              [](const SidePoint& a, const SidePoint& b) { return a.coord < b.coord; });
  return out;
}

// Linear interpolation of a side profile at `coord`; false when outside it.
// The node table is what a renderer culls and budgets with before it reads a blob: its
// triangle counts and height bounds must describe the decoded chunk. "" when they do.
std::string nodeRecordMismatch(const NodeRecord& n, const ChunkGeometry& g) {
  uint64_t surface = 0, skirt = 0;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const ChunkPart& part : g.parts) {
    surface += part.surfaceIndexCount / 3;
    skirt += (part.indices.size() - part.surfaceIndexCount) / 3;
    for (uint32_t k = 0; k < part.surfaceIndexCount; ++k) {
      const ChunkVertex& v = part.vertices[part.indices[k]];
      for (double t : {0.0, 1.0}) {
        lo = std::min(lo, chunkVertexHeight(g, v, t));
        hi = std::max(hi, chunkVertexHeight(g, v, t));
      }
    }
  }
  if (surface != n.triangleCount || skirt != n.skirtTriangleCount)
    return "node table says " + std::to_string(n.triangleCount) + "+" +
           std::to_string(n.skirtTriangleCount) + " surface+skirt triangles, chunk has " +
           std::to_string(surface) + "+" + std::to_string(skirt);
  if (surface && (lo < double(n.minZ) || hi > double(n.maxZ)))
    return "drawn heights " + std::to_string(lo) + ".." + std::to_string(hi) +
           " m leave the node's bounds " + std::to_string(n.minZ) + ".." + std::to_string(n.maxZ) +
           " m";
  return {};
}

bool interpolate(const std::vector<SidePoint>& side, int32_t coord, SidePoint& out) {
  if (side.empty() || coord < side.front().coord || coord > side.back().coord) return false;
  auto hi = std::lower_bound(side.begin(), side.end(), coord,
                             [](const SidePoint& p, int32_t c) { return p.coord < c; });
  if (hi->coord == coord) {
    out = *hi;
    return true;
  }
  const SidePoint& b = *hi;
  const SidePoint& a = *(hi - 1);
  const double f = double(coord - a.coord) / double(b.coord - a.coord);
  out = {coord, a.top0 + f * (b.top0 - a.top0), a.top1 + f * (b.top1 - a.top1),
         a.depth + f * (b.depth - a.depth)};
  return true;
}

}  // namespace

DemOpenOptions tilesetDemOptions(const TilesetReader& tileset) {
  DemOpenOptions dem;
  const TilesetMetadata& metadata = tileset.metadata();
  dem.encoding = parseHeightEncoding(metadata.sourceEncoding).value_or(HeightEncoding::kPlain);
  // The band the heights came from (recorded for multi-band sources only; band 1 before).
  if (dem.encoding == HeightEncoding::kPlain) dem.band = metadata.sourceBand.value_or(1);
  dem.verticalScale = metadata.verticalScale;
  return dem;
}

Result<Heightfield> loadTilesetSource(const TilesetReader& tileset, const std::string& sourcePath) {
  const TilesetHeader& h = tileset.header();
  auto source = DemReader::open(sourcePath, tilesetDemOptions(tileset));
  if (!source) return source.error();
  const DemInfo& info = (*source)->info();
  if (uint32_t(info.columns) != h.sourceColumns || uint32_t(info.rows) != h.sourceRows)
    return makeError(sourcePath,
                     "is " + std::to_string(info.columns) + "x" + std::to_string(info.rows) +
                         " samples but the tileset was built from " +
                         std::to_string(h.sourceColumns) + "x" + std::to_string(h.sourceRows));
  Heightfield heights(info.columns, info.rows);
  if (Status s = (*source)->readWindow(0, 0, info.columns, info.rows, heights.values().data()); !s)
    return s.error();
  if (auto filled = fillVoids(heights, sourcePath); !filled) return filled.error();
  applyHeightEdits(tileset.metadata().edits, info.spacingX, info.spacingY, heights);
  return heights;
}

Result<VerifyReport> verifyTileset(const std::string& tilesetPath, const std::string& sourcePath,
                                   const VerifyOptions& options, Progress& progress) {
  auto opened = TilesetReader::openPathOrUrl(tilesetPath);  // a path or an http(s):// URL
  if (!opened) return opened.error();
  const TilesetReader& tileset = **opened;
  const TilesetHeader& h = tileset.header();
  const auto& nodes = tileset.nodes();
  auto loaded = loadTilesetSource(tileset, sourcePath);
  if (!loaded) return loaded.error();
  const Heightfield& heights = *loaded;
  const int32_t columns = heights.columns(), rows = heights.rows();

  const int64_t cellsX = columns - 1, cellsY = rows - 1;
  VerifyReport report;
  report.levels.resize(h.levelCount);
  for (uint32_t l = 0; l < h.levelCount; ++l) report.levels[l].bound = h.levelError[l];
  report.morphGap = tileset.metadata().morphGap;
  report.chunks = nodes.size();
  if (h.meshKind == MeshKind::kVipm) {
    if (Status s = verifyVipmTileset(tileset, heights, sourcePath, options, progress, report); !s)
      return s.error();
    return report;
  }
  report.worstSkirtMargin = std::numeric_limits<double>::infinity();

  std::mutex mutex;
  auto addFailure = [&](const std::string& text) {
    std::lock_guard lock(mutex);
    ++report.failureCount;
    if (report.failures.size() < options.maxListedFailures) report.failures.push_back(text);
  };
  auto decode = [&](uint32_t i) -> Result<Decoded> {
    const NodeRecord& n = nodes[i];
    auto g = tileset.readChunkData(i);  // geometry and, when textured, the texture
    if (!g) return g.error();
    // (A chunk that inherits its texture draws its ancestor's: it has none of its own.)
    if (h.textured() && !n.inheritsTexture() &&
        (!g->texture || !g->texture->colourSource() ||
         !g->texture->find(TextureLayerKind::kNormal)))
      return makeError(tileset.name(),
                       "chunk " + std::to_string(i) + " lacks its colour or normal texture");
    const auto [x0, y0] = chunkCellOrigin(h, n);
    return Decoded{x0, y0, h.chunkCells(n.level), std::move(g->geometry)};
  };
  auto name = [&](uint32_t i) {
    const NodeRecord& n = nodes[i];
    return "chunk " + std::to_string(i) + " (level " + std::to_string(n.level) + ", " +
           std::to_string(n.x) + "," + std::to_string(n.y) + ")";
  };

  std::vector<ChunkSides> sides(nodes.size());
  const unsigned threads = options.threads ? options.threads : hardwareThreads();
  progress.begin("verifying chunks", nodes.size());
  // Each worker keeps the last parent it decoded: siblings come in a row, so most children
  // find theirs decoded.
  struct Kept {
    uint32_t node = ~0u;
    std::optional<Decoded> decoded;
  };
  std::vector<Kept> lastParent(std::max(threads, 1u));
  parallelFor(nodes.size(), threads, [&](size_t index, unsigned worker) {
    progress.advance();
    const uint32_t i = uint32_t(index);
    auto self = decode(i);
    if (!self) return addFailure(self.error().message);
    const NodeRecord& n = nodes[i];
    if (std::string problem = nodeRecordMismatch(n, self->geometry); !problem.empty())
      addFailure(name(i) + ": " + problem);
    sides[i] = sideProfiles(*self);
    const int64_t x1 = std::min(self->x0 + self->side, cellsX),
                  y1 = std::min(self->y0 + self->side, cellsY);

    // Error and coverage of the unmorphed surface against the source.
    Window surface = makeWindow(self->x0, self->y0, x1, y1);
    rasterizeSurface(*self, 0.0, surface);
    double maxError = 0;
    uint64_t uncovered = 0;
    for (int64_t y = surface.y0; y < surface.y0 + surface.h; ++y)
      for (int64_t x = surface.x0; x < surface.x0 + surface.w; ++x) {
        const double z = surface.at(x, y);
        if (std::isnan(z)) {
          ++uncovered;
          continue;
        }
        maxError = std::max(maxError, std::fabs(z - double(heights(int32_t(x), int32_t(y)))));
      }
    if (maxError > h.levelError[n.level] + kTolerance)
      addFailure(name(i) + ": error " + std::to_string(maxError) + " m exceeds its level's bound " +
                 std::to_string(h.levelError[n.level]) + " m");
    if (uncovered)
      addFailure(name(i) + ": " + std::to_string(uncovered) +
                 " samples not covered by its triangles");

    // The fully morphed surface must be the parent's surface.
    double mismatch = 0, tolerance = 0;
    if (n.level > 0) {
      Kept& kept = lastParent[worker];
      if (kept.node != n.parent) {
        auto decoded = decode(n.parent);
        if (!decoded) return addFailure(decoded.error().message);
        kept = {n.parent, std::move(decoded).value()};
      }
      const Decoded* parent = &*kept.decoded;
      Window target = makeWindow(self->x0, self->y0, x1, y1);
      rasterizeSurface(*parent, 0.0, target);
      Window morphed = makeWindow(self->x0, self->y0, x1, y1);
      rasterizeSurface(*self, 1.0, morphed);
      for (size_t k = 0; k < morphed.values.size(); ++k)
        if (!std::isnan(morphed.values[k]) && !std::isnan(target.values[k]))
          mismatch = std::max(mismatch, std::fabs(morphed.values[k] - target.values[k]));
      // While it geomorphs the chunk stands in for its parent: the parent level's bound holds.
      double morphedError = 0;
      for (int64_t y = morphed.y0; y < morphed.y0 + morphed.h; ++y)
        for (int64_t x = morphed.x0; x < morphed.x0 + morphed.w; ++x)
          if (const double z = morphed.at(x, y); !std::isnan(z))
            morphedError =
                std::max(morphedError, std::fabs(z - double(heights(int32_t(x), int32_t(y)))));
      if (morphedError > h.levelError[n.level - 1] + kTolerance)
        addFailure(name(i) + ": fully morphed, error " + std::to_string(morphedError) +
                   " m exceeds its parent level's bound " +
                   std::to_string(h.levelError[n.level - 1]) + " m");
      // Both surfaces are rounded to their own height steps; see LevelCheck::morphTolerance.
      tolerance = 0.5 * (self->geometry.zStep + parent->geometry.zStep) + kTolerance +
                  tileset.metadata().morphGap * h.levelError[n.level - 1];
      if (mismatch > tolerance)
        addFailure(name(i) + ": fully morphed surface is " + std::to_string(mismatch) +
                   " m off its parent's (allowed " + std::to_string(tolerance) + " m)");
    }
    std::lock_guard lock(mutex);
    LevelCheck& level = report.levels[n.level];
    level.maxError = std::max(level.maxError, maxError);
    level.samples += uint64_t(surface.w * surface.h);
    level.uncovered += uncovered;
    level.maxMorphMismatch = std::max(level.maxMorphMismatch, mismatch);
    level.morphTolerance = std::max(level.morphTolerance, tolerance);
    level.heightStep = std::max(level.heightStep, self->geometry.zStep);
  });
  progress.end();

  // Cracks: every chunk against every chunk across each of its sides, at every level.
  std::unordered_map<uint64_t, uint32_t> byPosition;
  auto key = [](uint64_t level, uint64_t x, uint64_t y) { return (level << 58) | (x << 29) | y; };
  for (uint32_t i = 0; i < nodes.size(); ++i)
    byPosition[key(nodes[i].level, nodes[i].x, nodes[i].y)] = i;
  progress.begin("verifying skirts", nodes.size());
  std::atomic<uint64_t> pairs{0}, samples{0};
  parallelFor(nodes.size(), threads, [&](size_t index, unsigned) {
    progress.advance();
    const uint32_t i = uint32_t(index);
    const NodeRecord& n = nodes[i];
    const int64_t s = h.chunkCells(n.level), x0 = int64_t(n.x) * s, y0 = int64_t(n.y) * s;
    double worst = std::numeric_limits<double>::infinity();
    for (int side = 0; side < 4; ++side) {
      const bool vertical = side == 1 || side == 3;
      const int64_t line = side == 0 ? y0 : side == 1 ? x0 + s : side == 2 ? y0 + s : x0;
      const int64_t limit = vertical ? cellsX : cellsY;
      if (line <= 0 || line >= limit) continue;  // data boundary: nothing across
      const int64_t from = vertical ? y0 : x0;
      const int64_t to = std::min(from + s, vertical ? cellsY : cellsX);
      const int opposite = (side + 2) % 4;
      for (uint32_t level = 0; level < h.levelCount; ++level) {
        const int64_t ls = h.chunkCells(int32_t(level));
        if (line % ls != 0) continue;
        const int64_t across = (side == 1 || side == 2) ? line / ls : line / ls - 1;
        for (int64_t k = from / ls; k * ls < to; ++k) {
          const auto found = byPosition.find(vertical ? key(level, uint64_t(across), uint64_t(k))
                                                      : key(level, uint64_t(k), uint64_t(across)));
          if (found == byPosition.end()) continue;
          ++pairs;
          const int64_t lo = std::max(from, k * ls), hi = std::min(to, (k + 1) * ls);
          for (int64_t q = lo; q <= hi; ++q) {
            SidePoint mine, theirs;
            if (!interpolate(sides[i].sides[side], int32_t(q - from), mine) ||
                !interpolate(sides[found->second].sides[opposite], int32_t(q - k * ls), theirs))
              continue;
            ++samples;
            const double step = std::max(mine.top0, mine.top1) - std::min(theirs.top0, theirs.top1);
            const double margin = mine.depth - step;
            worst = std::min(worst, margin);
            if (margin < -kTolerance) {
              addFailure(name(i) + ": crack of " + std::to_string(-margin) + " m against " +
                         name(found->second) + " at grid " +
                         (vertical ? std::to_string(line) + "," + std::to_string(q)
                                   : std::to_string(q) + "," + std::to_string(line)) +
                         " not covered by its skirt");
              break;
            }
          }
        }
      }
    }
    std::lock_guard lock(mutex);
    report.worstSkirtMargin = std::min(report.worstSkirtMargin, worst);
  });
  progress.end();
  report.skirtPairs = pairs;
  report.skirtSamples = samples;
  if (!std::isfinite(report.worstSkirtMargin)) report.worstSkirtMargin = 0;
  return report;
}

}  // namespace terralod
