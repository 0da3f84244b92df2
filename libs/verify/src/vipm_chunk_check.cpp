#include "vipm_chunk_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "terralod/core/sample_raster.h"
#include "terralod/format/texture_decode.h"
#include "terralod/format/tileset_format.h"
#include "terralod/materials/material.h"
#include "terralod/verify/verifier.h"
#include "terralod/vipm/vipm_levels.h"
#include "terralod/vipm/vipm_storage.h"

namespace terralod {
namespace {

using Triangle = std::array<uint16_t, 3>;

// Problems listed per chunk at most (the count still counts them all).
constexpr size_t kProblemsPerChunk = 4;

struct Grid {
  const VipmChunkData& c;
  int32_t x(uint32_t v) const { return c.points[v] % c.width; }
  int32_t y(uint32_t v) const { return c.points[v] / c.width; }
  double z(uint32_t v) const { return c.zBase + double(c.heights[v]) * c.zStep; }
};

void addProblem(VipmChunkCheck& out, std::string text) {
  if (out.problems.size() < kProblemsPerChunk) out.problems.push_back(std::move(text));
}

// The triangles of the level `rename` describes, degenerate ones (removed) left out.
std::vector<Triangle> levelTriangles(const VipmChunkData& c, const std::vector<uint16_t>& rename) {
  std::vector<Triangle> out;
  out.reserve(c.triangleCount());
  for (size_t k = 0; k + 2 < c.indices.size(); k += 3) {
    const Triangle t{rename[c.indices[k]], rename[c.indices[k + 1]], rename[c.indices[k + 2]]};
    if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) out.push_back(t);
  }
  return out;
}

// Barycentric weights of grid point (px, py) in triangle t; false when it is degenerate.
bool weights(const Grid& g, const Triangle& t, double px, double py, std::array<double, 3>& w) {
  const double ax = g.x(t[0]), ay = g.y(t[0]), bx = g.x(t[1]), by = g.y(t[1]);
  const double cx = g.x(t[2]), cy = g.y(t[2]);
  const double area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
  if (area == 0) return false;
  w[0] = ((bx - px) * (cy - py) - (by - py) * (cx - px)) / area;
  w[1] = ((cx - px) * (ay - py) - (cy - py) * (ax - px)) / area;
  w[2] = 1.0 - w[0] - w[1];
  return true;
}

// The current level's triangles: each stored triangle's corners as collapses have renamed
// them, whether it still has an area, and the living triangles at each vertex.
struct LevelMesh {
  std::vector<Triangle> corners;  ///< in stored (index) order
  std::vector<uint8_t> live;
  std::vector<std::vector<uint32_t>> at;  ///< per vertex, living triangles holding it (and dead)

  LevelMesh(const VipmChunkData& c) : at(c.vertexCount()) {
    for (size_t k = 0; k + 2 < c.indices.size(); k += 3) {
      const Triangle t{c.indices[k], c.indices[k + 1], c.indices[k + 2]};
      corners.push_back(t);
      live.push_back(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
      if (live.back())
        for (uint16_t v : t) at[v].push_back(uint32_t(corners.size() - 1));
    }
  }
  std::vector<Triangle> living() const {
    std::vector<Triangle> out;
    for (size_t k = 0; k < corners.size(); ++k)
      if (live[k]) out.push_back(corners[k]);
    return out;
  }
};

// The paper's three material rules for collapsing v onto t in `mesh`; the first rule broken
// (1..3), or 0.
int brokenRule(const Grid& g, const LevelMesh& mesh, uint16_t v, uint16_t t) {
  const auto& mat = g.c.materials;
  if (mat[v] != mat[t]) return 1;
  auto onBoundary = [&](uint16_t u) {
    for (uint32_t k : mesh.at[u])
      if (mesh.live[k])
        for (uint16_t w : mesh.corners[k])
          if (mat[w] != mat[u]) return true;
    return false;
  };
  if (onBoundary(v) && !onBoundary(t)) return 2;
  // After the collapse, v's point lies in the triangles of its fan that do not hold t, now
  // with t in v's place; every corner with a non-zero weight there must be of v's material.
  for (uint32_t k : mesh.at[v]) {
    if (!mesh.live[k]) continue;
    Triangle tri = mesh.corners[k];
    if (tri[0] == t || tri[1] == t || tri[2] == t) continue;
    for (uint16_t& w : tri)
      if (w == v) w = t;
    std::array<double, 3> w{};
    if (!weights(g, tri, g.x(v), g.y(v), w)) continue;
    constexpr double kEps = 1e-9;
    if (w[0] < -kEps || w[1] < -kEps || w[2] < -kEps) continue;
    for (int k3 = 0; k3 < 3; ++k3)
      if (w[k3] > kEps && mat[tri[k3]] != mat[v]) return 3;
  }
  return 0;
}

// Grid points [x0, x1] x [y0, y1]; empty while x0 > x1.
struct Box {
  int32_t x0 = std::numeric_limits<int32_t>::max(), y0 = x0, x1 = -1, y1 = -1;
  bool empty() const { return x0 > x1; }
  void add(const Box& b) {
    x0 = std::min(x0, b.x0);
    y0 = std::min(y0, b.y0);
    x1 = std::max(x1, b.x1);
    y1 = std::max(y1, b.y1);
  }
};

// The current level's surface at every grid point, as if all its triangles were drawn in index
// order (a later one wins where two overlap; NaN where none reaches), kept up to date collapse
// by collapse: only the box around the triangles a collapse changed is drawn again, from every
// living triangle reaching it, in index order. Drawing a point does not depend on the window
// (rasterizeTriangle), so the points are those a whole drawing gives. The true error, largest
// height and uncovered points over the grid come from maxima and counts per 8 x 8 tile.
class LevelSurface {
 public:
  LevelSurface(const Grid& g, const LevelMesh& mesh, std::vector<double> source)
      : mG(g),
        mMesh(mesh),
        mW(g.c.width),
        mH(g.c.height),
        mTilesX((mW + kTile - 1) / kTile),
        mTilesY((mH + kTile - 1) / kTile),
        mSource(std::move(source)),
        mHeights(size_t(mW) * mH, std::numeric_limits<double>::quiet_NaN()),
        mTriangles(size_t(mTilesX) * mTilesY),
        mError(mTriangles.size(), 0.0),
        mLargest(mTriangles.size(), 0.0),
        mMissing(mTriangles.size(), 0) {
    for (uint32_t k = 0; k < mesh.corners.size(); ++k)
      if (mesh.live[k]) enter(k);
    draw(Box{0, 0, mW - 1, mH - 1});
  }

  Box boxOf(uint32_t k) const {
    Box b;
    for (uint16_t v : mMesh.corners[k]) b.add(Box{mG.x(v), mG.y(v), mG.x(v), mG.y(v)});
    return b;
  }
  /// Triangle k (living) with its corners as they are now: in the tiles it reaches.
  void enter(uint32_t k) {
    forTiles(boxOf(k), [&](size_t i) { mTriangles[i].push_back(k); });
  }
  /// Triangle k with its corners as they were when it entered: out of its tiles.
  void leave(uint32_t k) {
    forTiles(boxOf(k), [&](size_t i) {
      auto& list = mTriangles[i];
      list.erase(std::find(list.begin(), list.end(), k));
    });
  }

  /// Draws the points of `box` again from the triangles now reaching it.
  void draw(const Box& box) {
    for (int32_t y = box.y0; y <= box.y1; ++y)
      std::fill_n(mHeights.begin() + ptrdiff_t(size_t(y) * mW + size_t(box.x0)),
                  box.x1 - box.x0 + 1, std::numeric_limits<double>::quiet_NaN());
    std::vector<uint32_t> reaching;
    forTiles(box, [&](size_t i) {
      reaching.insert(reaching.end(), mTriangles[i].begin(), mTriangles[i].end());
    });
    std::sort(reaching.begin(), reaching.end());
    reaching.erase(std::unique(reaching.begin(), reaching.end()), reaching.end());
    for (uint32_t k : reaching) {
      const Triangle& t = mMesh.corners[k];
      rasterizeTriangle(SampleVertex{mG.x(t[0]), mG.y(t[0]), mG.z(t[0])},
                        SampleVertex{mG.x(t[1]), mG.y(t[1]), mG.z(t[1])},
                        SampleVertex{mG.x(t[2]), mG.y(t[2]), mG.z(t[2])}, box.x0, box.x1, box.y0,
                        box.y1,
                        [&](int64_t x, int64_t y, double z) { mHeights[size_t(y * mW + x)] = z; });
    }
    forTiles(box, [&](size_t i) { measureTile(i); });
  }

  const std::vector<double>& heights() const { return mHeights; }
  double error() const { return *std::max_element(mError.begin(), mError.end()); }
  double largest() const { return *std::max_element(mLargest.begin(), mLargest.end()); }
  uint64_t uncovered() const { return mUncovered; }

 private:
  static constexpr int32_t kTile = 8;

  template <class Fn>
  void forTiles(const Box& b, Fn&& fn) const {
    for (int32_t ty = b.y0 / kTile; ty <= b.y1 / kTile; ++ty)
      for (int32_t tx = b.x0 / kTile; tx <= b.x1 / kTile; ++tx) fn(size_t(ty) * mTilesX + tx);
  }

  void measureTile(size_t i) {
    const int32_t tx = int32_t(i % size_t(mTilesX)), ty = int32_t(i / size_t(mTilesX));
    double error = 0, largest = 0;
    uint32_t missing = 0;
    for (int32_t y = ty * kTile; y < std::min(mH, (ty + 1) * kTile); ++y)
      for (int32_t x = tx * kTile; x < std::min(mW, (tx + 1) * kTile); ++x) {
        const size_t p = size_t(y) * mW + x;
        const double z = mHeights[p];
        if (std::isnan(z)) {
          ++missing;
          continue;
        }
        error = std::max(error, std::fabs(z - mSource[p]));
        largest = std::max(largest, std::fabs(z));
      }
    mUncovered = mUncovered - mMissing[i] + missing;
    mError[i] = error;
    mLargest[i] = largest;
    mMissing[i] = missing;
  }

  const Grid& mG;
  const LevelMesh& mMesh;
  int32_t mW, mH, mTilesX, mTilesY;
  std::vector<double> mSource;
  std::vector<double> mHeights;
  std::vector<std::vector<uint32_t>> mTriangles;  ///< per tile, the living triangles reaching it
  std::vector<double> mError, mLargest;
  std::vector<uint32_t> mMissing;
  uint64_t mUncovered = 0;
};

// A part's living triangles as sorted corner triples, sorted.
std::vector<Triangle> canonical(std::span<const uint16_t> indices, uint32_t triangles) {
  std::vector<Triangle> out(triangles);
  for (uint32_t k = 0; k < triangles; ++k) {
    out[k] = {indices[3 * k], indices[3 * k + 1], indices[3 * k + 2]};
    std::sort(out[k].begin(), out[k].end());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Every material's part draws the whole chunk's triangles with a corner of that material (and
// no triangle the whole chunk does not), over active vertices only.
bool partsAgree(const VipmLevels& levels, std::span<const uint8_t> materials) {
  const VipmPart& whole = levels.whole();
  const std::vector<Triangle> all = canonical(whole.indices, levels.drawnTriangles(whole));
  for (const Triangle& t : all)
    if (t[2] >= levels.activeVertices()) return false;
  for (const VipmPart& part : levels.parts()) {
    if (part.material == kWholeChunk) continue;
    std::vector<Triangle> expected;
    for (const Triangle& t : all)
      if (materials[t[0]] == part.material || materials[t[1]] == part.material ||
          materials[t[2]] == part.material)
        expected.push_back(t);
    // A part keeps the triangles that ever had a corner of its material (their weight for it
    // is zero once none has): within the whole chunk's, and holding all that have one now.
    const std::vector<Triangle> drawn = canonical(part.indices, levels.drawnTriangles(part));
    if (!std::includes(all.begin(), all.end(), drawn.begin(), drawn.end()) ||
        !std::includes(drawn.begin(), drawn.end(), expected.begin(), expected.end()))
      return false;
  }
  return true;
}

// The border vertices of each side (south, east, north, west), ordered along it.
std::array<std::vector<uint16_t>, 4> sideVertices(const Grid& g) {
  std::array<std::vector<uint16_t>, 4> sides;
  const int32_t w = g.c.width - 1, h = g.c.height - 1;
  for (uint32_t v = 0; v < g.c.vertexCount(); ++v) {
    if (g.y(v) == 0) sides[0].push_back(uint16_t(v));
    if (g.x(v) == w) sides[1].push_back(uint16_t(v));
    if (g.y(v) == h) sides[2].push_back(uint16_t(v));
    if (g.x(v) == 0) sides[3].push_back(uint16_t(v));
  }
  for (int s = 0; s < 4; ++s)
    std::sort(sides[s].begin(), sides[s].end(), [&](uint16_t a, uint16_t b) {
      return (s % 2 == 0) ? g.x(a) < g.x(b) : g.y(a) < g.y(b);
    });
  return sides;
}

// Widens each side's envelope by the border polyline of the vertices active now (< active).
void widenSides(const Grid& g, const std::array<std::vector<uint16_t>, 4>& sides, uint32_t active,
                std::array<SideEnvelope, 4>& envelopes) {
  for (int s = 0; s < 4; ++s) {
    SideEnvelope& e = envelopes[s];
    int32_t prevCoord = -1;
    double prevZ = 0;
    for (uint16_t v : sides[s]) {
      if (v >= active) continue;
      const int32_t coord = (s % 2 == 0) ? g.x(v) : g.y(v);
      const double z = g.z(v);
      const int32_t from = prevCoord < 0 ? coord : prevCoord;
      for (int32_t k = from; k <= coord; ++k) {
        const double h = k == coord ? z : prevZ + (z - prevZ) * double(k - from) / (coord - from);
        e.low[size_t(k)] = std::min(e.low[size_t(k)], h);
        e.high[size_t(k)] = std::max(e.high[size_t(k)], h);
      }
      prevCoord = coord;
      prevZ = z;
    }
  }
}

constexpr int32_t kLeafPoints = int32_t(kVipmLeafCells) + 1;

// Each quarter's surface from the triangles inside it (see VipmChunkCheck::quarters).
std::array<std::vector<double>, 4> quarterSurfaces(const Grid& g,
                                                   const std::vector<Triangle>& triangles) {
  std::array<std::vector<double>, 4> out;
  const int32_t cells = int32_t(kVipmLeafCells);
  for (int q = 0; q < 4; ++q) {
    const int32_t qx = (q & 1) * cells, qy = (q >> 1) * cells;
    out[q].assign(size_t(kLeafPoints) * kLeafPoints, std::numeric_limits<double>::quiet_NaN());
    auto inside = [&](uint16_t v) {
      return g.x(v) >= qx && g.x(v) <= qx + cells && g.y(v) >= qy && g.y(v) <= qy + cells;
    };
    for (const Triangle& t : triangles) {
      if (!inside(t[0]) || !inside(t[1]) || !inside(t[2])) continue;
      rasterizeTriangle(
          SampleVertex{g.x(t[0]) - qx, g.y(t[0]) - qy, g.z(t[0])},
          SampleVertex{g.x(t[1]) - qx, g.y(t[1]) - qy, g.z(t[1])},
          SampleVertex{g.x(t[2]) - qx, g.y(t[2]) - qy, g.z(t[2])}, 0, cells, 0, cells,
          [&](int64_t x, int64_t y, double z) { out[q][size_t(y * kLeafPoints + x)] = z; });
    }
  }
  return out;
}

// The two sides' polylines on a root's interior lines x or y = 64 (the children's shared
// sides), widened level by level: per line, per side (west or south of it: 0), per grid point
// along it, the lowest and highest height.
struct SeamEnvelopes {
  std::array<std::array<SideEnvelope, 2>, 2> lines;  // [x = 64, y = 64][side]
  std::array<bool, 2> present{false, false};

  SeamEnvelopes(const Grid& g) {
    const int32_t c = int32_t(kVipmLeafCells);
    present = {g.c.width - 1 > c, g.c.height - 1 > c};
    for (int l = 0; l < 2; ++l)
      for (SideEnvelope& e : lines[l]) {
        const size_t length = size_t(l == 0 ? g.c.height : g.c.width);
        e.low.assign(length, std::numeric_limits<double>::infinity());
        e.high.assign(length, -std::numeric_limits<double>::infinity());
      }
  }

  void widen(const Grid& g, const std::vector<Triangle>& triangles) {
    const int32_t c = int32_t(kVipmLeafCells);
    for (const Triangle& t : triangles)
      for (int k = 0; k < 3; ++k) {
        const uint16_t a = t[k], b = t[(k + 1) % 3], o = t[(k + 2) % 3];
        for (int l = 0; l < 2; ++l) {
          auto across = [&](uint16_t v) { return l == 0 ? g.x(v) : g.y(v); };
          auto along = [&](uint16_t v) { return l == 0 ? g.y(v) : g.x(v); };
          if (!present[l] || across(a) != c || across(b) != c) continue;
          SideEnvelope& e = lines[l][across(o) < c ? 0 : 1];
          const int32_t pa = along(a), pb = along(b);
          for (int32_t p = std::min(pa, pb); p <= std::max(pa, pb); ++p) {
            const double z = g.z(a) + (g.z(b) - g.z(a)) * double(p - pa) / double(pb - pa);
            e.low[size_t(p)] = std::min(e.low[size_t(p)], z);
            e.high[size_t(p)] = std::max(e.high[size_t(p)], z);
          }
        }
      }
  }

  double gap() const {
    double worst = 0;
    for (const auto& line : lines)
      for (size_t p = 0; p < line[0].low.size(); ++p)
        if (std::isfinite(line[0].low[p]) && std::isfinite(line[1].low[p]))
          worst =
              std::max({worst, line[0].high[p] - line[1].low[p], line[1].high[p] - line[0].low[p]});
    return worst;
  }
};

}  // namespace

VipmChunkCheck checkVipmChunk(const VipmChunkData& c, int64_t x0, int64_t y0,
                              const Heightfield& source, const MaterialMap* materials,
                              MaterialRules promised) {
  VipmChunkCheck out;
  const Grid g{c};
  const uint32_t n = c.vertexCount(), collapses = c.collapseCount();
  const int32_t w = c.width, h = c.height;
  auto sourceAt = [&](int32_t x, int32_t y) {
    return double(source.at(int32_t(x0 + x), int32_t(y0 + y)));
  };

  if (materials)
    for (uint32_t v = 0; v < n; ++v)
      if (c.materials[v] != materials->at(int32_t(x0 + g.x(v)), int32_t(y0 + g.y(v))))
        ++out.materialMismatches;
  if (out.materialMismatches)
    addProblem(out, std::to_string(out.materialMismatches) +
                        " vertices have another material than the source's");

  for (int s = 0; s < 4; ++s) {
    const size_t length = size_t(s % 2 == 0 ? w : h);
    out.sides[s].low.assign(length, std::numeric_limits<double>::infinity());
    out.sides[s].high.assign(length, -std::numeric_limits<double>::infinity());
  }
  const auto sides = sideVertices(g);

  // The reconstruction's parts, compared at the finest, a middle and the coarsest level.
  auto unpacked = unpackChunk(c);
  auto levels = VipmLevels::reconstruct(unpacked.mesh, unpacked.materials);
  if (!levels) addProblem(out, "does not reconstruct: " + levels.error().message);
  const std::array<uint32_t, 3> partLevels{0, collapses / 2, collapses};

  const bool root = w > kLeafPoints || h > kLeafPoints;
  SeamEnvelopes seams(g);

  // Each level from the one before: a collapse changes only the triangles holding its vertex.
  LevelMesh mesh(c);
  std::vector<double> sourceHeights(size_t(w) * h);
  for (int32_t y = 0; y < h; ++y)
    for (int32_t x = 0; x < w; ++x) sourceHeights[size_t(y) * w + x] = sourceAt(x, y);
  LevelSurface surface(g, mesh, std::move(sourceHeights));
  std::vector<Triangle> changed = mesh.living();  // at the finest level, all
  for (uint32_t j = 0; j <= collapses; ++j) {
    const double error = surface.error(), largest = surface.largest();
    out.samples += uint64_t(w) * uint64_t(h);
    out.uncovered += surface.uncovered();
    const double recorded = j == 0 ? c.finestError : double(c.errors[j - 1]) * c.errorStep;
    if (j == 0) out.finestError = error;
    out.worstMargin = std::min(out.worstMargin, recorded - error);
    if (error > recorded + kVerifySlack + kVipmFloatSlack * largest)
      addProblem(out, "level " + std::to_string(j) + ": true error " + std::to_string(error) +
                          " m > recorded " + std::to_string(recorded) + " m");
    ++out.levels;
    widenSides(g, sides, n - j, out.sides);
    // The seams' envelopes widen by every triangle of every level: those a collapse changed.
    if (root) seams.widen(g, changed);
    if (j == 0) {
      out.finestHeights = surface.heights();
      if (root) out.quarters = quarterSurfaces(g, changed);
    }
    if (levels && std::find(partLevels.begin(), partLevels.end(), j) != partLevels.end()) {
      levels->setApplied(j);
      ++out.partLevelsChecked;
      if (!partsAgree(*levels, unpacked.materials))
        addProblem(out, "level " + std::to_string(j) +
                            ": the material parts are not the whole chunk's triangles");
    }
    if (j == collapses) {
      out.coarsestHeights = surface.heights();
      break;
    }
    const uint16_t v = uint16_t(n - 1 - j), t = c.targets[j];
    ++out.collapsesChecked;
    if (const int rule = brokenRule(g, mesh, v, t); rule != 0) {
      ++out.ruleViolations;
      if (promised == MaterialRules::kOn)
        addProblem(
            out, "collapse " + std::to_string(j) + " breaks material rule " + std::to_string(rule));
    }
    // v becomes t in the triangles holding it; those that lose their area die.
    Box box;
    changed.clear();
    std::vector<uint32_t> fan;
    fan.swap(mesh.at[v]);
    for (uint32_t k : fan) {
      if (!mesh.live[k]) continue;
      box.add(surface.boxOf(k));
      surface.leave(k);
      Triangle& corners = mesh.corners[k];
      for (uint16_t& corner : corners)
        if (corner == v) corner = t;
      if (corners[0] == corners[1] || corners[1] == corners[2] || corners[0] == corners[2]) {
        mesh.live[k] = 0;
        continue;
      }
      surface.enter(k);
      box.add(surface.boxOf(k));
      mesh.at[t].push_back(k);
      changed.push_back(corners);
    }
    if (!box.empty()) surface.draw(box);
  }
  if (out.uncovered)
    addProblem(out, std::to_string(out.uncovered) + " samples are not covered at some level");
  out.seamGap = seams.gap();
  return out;
}

NormalMapCheck checkVipmNormalMap(const TextureLayer& layer, int64_t x0, int64_t y0,
                                  const Heightfield& source, double spacingX, double spacingY,
                                  int64_t stride) {
  NormalMapCheck out;
  const uint32_t size = layer.size;
  const std::vector<uint8_t> stored =
      layer.mips.empty() ? std::vector<uint8_t>{} : decodeBc5Rg(layer.mips[0], size);
  if (stored.empty()) {
    out.problem = "its normal map's level 0 does not decode";
    return out;
  }
  // True (n + 1) / 2 per texel and channel, in 8-bit units.
  std::vector<double> truth(size_t(size) * size * 2);
  // On the grid at the map's stride: its points' heights (the nearest inside the data).
  auto h = [&](int64_t x, int64_t y) {
    return double(source.at(int32_t(x * stride), int32_t(y * stride)));
  };
  for (uint32_t j = 0; j < size; ++j)
    for (uint32_t i = 0; i < size; ++i) {
      const int64_t gx = x0 / stride + i, gy = y0 / stride + j;
      const double dx = (h(gx + 1, gy) - h(gx - 1, gy)) / (2.0 * spacingX * double(stride));
      const double dy = (h(gx, gy + 1) - h(gx, gy - 1)) / (2.0 * spacingY * double(stride));
      const double len = std::sqrt(dx * dx + dy * dy + 1.0);
      double* t = truth.data() + (size_t(j) * size + i) * 2;
      t[0] = (-dx / len + 1.0) * 0.5 * 255.0;
      t[1] = (-dy / len + 1.0) * 0.5 * 255.0;
    }
  for (uint32_t by = 0; by < size; by += 4)
    for (uint32_t bx = 0; bx < size; bx += 4)
      for (uint32_t ch = 0; ch < 2; ++ch) {
        double lo = 1e30, hi = -1e30;
        for (uint32_t j = by; j < std::min(by + 4, size); ++j)
          for (uint32_t i = bx; i < std::min(bx + 4, size); ++i) {
            lo = std::min(lo, truth[(size_t(j) * size + i) * 2 + ch]);
            hi = std::max(hi, truth[(size_t(j) * size + i) * 2 + ch]);
          }
        const double tolerance = (hi - lo) / 7.0 + 2.0;
        for (uint32_t j = by; j < std::min(by + 4, size); ++j)
          for (uint32_t i = bx; i < std::min(bx + 4, size); ++i) {
            const size_t k = (size_t(j) * size + i) * 2 + ch;
            const double off = std::fabs(double(stored[k]) - truth[k]);
            ++out.texels;
            out.worst = std::max(out.worst, off * 2.0 / 255.0);
            if (off > tolerance && out.problem.empty()) {
              char text[200];
              std::snprintf(text, sizeof text,
                            "its normal map's texel (%u, %u) has %c = %.4f, not the source's "
                            "%.4f (BC5 allows %.4f)",
                            i, j, ch ? 'y' : 'x', stored[k] * 2.0 / 255.0 - 1.0,
                            truth[k] * 2.0 / 255.0 - 1.0, tolerance * 2.0 / 255.0);
              out.problem = text;
            }
          }
      }
  out.texels /= 2;
  return out;
}

VipmChunkCheck checkVipmUpperNode(const VipmChunkData& chunk, int64_t x0, int64_t y0,
                                  const Heightfield& source) {
  VipmChunkCheck out;
  const Grid g{chunk};
  const uint32_t n = chunk.vertexCount(), r = chunk.collapseCount();
  const int32_t w = chunk.width, h = chunk.height;
  auto recorded = [&](uint32_t j) {  // the error after j collapses, as stored
    return j == 0 ? double(chunk.finestError) : double(chunk.errors[j - 1]) * chunk.errorStep;
  };
  // The levels rasterised, ascending.
  std::vector<uint32_t> checked;
  for (uint32_t k = 0; k < kVipmUpperLevelsVerified; ++k)
    checked.push_back(uint32_t(uint64_t(r) * k / (kVipmUpperLevelsVerified - 1)));
  checked.erase(std::unique(checked.begin(), checked.end()), checked.end());
  std::vector<uint16_t> rename(n);
  for (uint32_t v = 0; v < n; ++v) rename[v] = uint16_t(v);
  auto resolve = [&](uint16_t v) {
    while (rename[v] != v) v = rename[v];
    return v;
  };
  std::vector<bool> covered(size_t(w) * size_t(h));
  uint32_t applied = 0;
  for (uint32_t j : checked) {
    for (; applied < j; ++applied) rename[n - 1 - applied] = chunk.targets[applied];
    std::vector<uint16_t> now(n);
    for (uint32_t v = 0; v < n; ++v) now[v] = resolve(uint16_t(v));
    std::fill(covered.begin(), covered.end(), false);
    double worst = 0.0;
    const std::vector<Triangle> triangles = levelTriangles(chunk, now);
    for (const Triangle& t : triangles) {
      const int64_t ax = g.x(t[0]), ay = g.y(t[0]), bx = g.x(t[1]), by = g.y(t[1]);
      const int64_t cx = g.x(t[2]), cy = g.y(t[2]);
      const int64_t area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
      if (area <= 0) {
        addProblem(out, "a triangle is not counter-clockwise at level " + std::to_string(j));
        continue;
      }
      const double za = g.z(t[0]), zb = g.z(t[1]), zc = g.z(t[2]);
      for (int64_t py = std::min({ay, by, cy}); py <= std::max({ay, by, cy}); ++py)
        for (int64_t px = std::min({ax, bx, cx}); px <= std::max({ax, bx, cx}); ++px) {
          // Integer edge functions: points on an edge are inside.
          const int64_t w0 = (bx - px) * (cy - py) - (by - py) * (cx - px);
          const int64_t w1 = (cx - px) * (ay - py) - (cy - py) * (ax - px);
          const int64_t w2 = area - w0 - w1;
          if (w0 < 0 || w1 < 0 || w2 < 0) continue;
          const double z = (double(w0) * za + double(w1) * zb + double(w2) * zc) / double(area);
          worst = std::max(worst, std::abs(double(source(int32_t(x0 + px), int32_t(y0 + py))) - z));
          covered[size_t(py) * size_t(w) + size_t(px)] = true;
        }
    }
    const uint64_t missed = uint64_t(std::count(covered.begin(), covered.end(), false));
    out.uncovered += missed;
    out.samples += covered.size();
    ++out.levels;
    if (j == 0) out.finestError = worst;
    out.worstMargin = std::min(out.worstMargin, recorded(j) - worst);
    if (worst > recorded(j) + kVerifySlack)
      addProblem(out, "level " + std::to_string(j) + "'s error " + std::to_string(worst) +
                          " m is over its recorded " + std::to_string(recorded(j)) + " m");
    if (missed > 0)
      addProblem(out, "level " + std::to_string(j) + " leaves " + std::to_string(missed) +
                          " samples uncovered");
    auto points = [&](std::vector<std::array<double, 3>>& to) {
      std::vector<bool> used(n);
      for (const Triangle& t : triangles)
        for (uint16_t v : t) used[v] = true;
      for (uint32_t v = 0; v < n; ++v)
        if (used[v]) to.push_back({double(x0 + g.x(v)), double(y0 + g.y(v)), g.z(v)});
      std::sort(to.begin(), to.end());
    };
    if (j == 0) points(out.finestPoints);
    if (j == r) points(out.coarsestPoints);
  }
  // Sides at every level: the active vertices on each, joined as collapses remove them.
  for (int s = 0; s < 4; ++s) {
    const int32_t length = s % 2 == 0 ? w : h;
    auto position = [&](uint32_t v) -> int32_t {  // along side s, or -1
      const int32_t x = g.x(v), y = g.y(v);
      switch (s) {
        case 0:
          return y == 0 ? x : -1;
        case 1:
          return x == w - 1 ? y : -1;
        case 2:
          return y == h - 1 ? x : -1;
        default:
          return x == 0 ? y : -1;
      }
    };
    std::vector<int32_t> active(size_t(length), -1);
    for (uint32_t v = 0; v < n; ++v)
      if (const int32_t p = position(v); p >= 0) active[size_t(p)] = int32_t(v);
    SideEnvelope& e = out.sides[size_t(s)];
    e.low.assign(size_t(length), std::numeric_limits<double>::infinity());
    e.high.assign(size_t(length), -std::numeric_limits<double>::infinity());
    auto segment = [&](int32_t a, int32_t b) {
      const double za = g.z(uint32_t(active[size_t(a)])), zb = g.z(uint32_t(active[size_t(b)]));
      for (int32_t p = a; p <= b; ++p) {
        const double z = b == a ? za : za + (zb - za) * double(p - a) / double(b - a);
        e.low[size_t(p)] = std::min(e.low[size_t(p)], z);
        e.high[size_t(p)] = std::max(e.high[size_t(p)], z);
      }
    };
    for (int32_t p = 0, previous = -1; p < length; ++p) {
      if (active[size_t(p)] < 0) continue;
      if (previous >= 0) segment(previous, p);
      previous = p;
    }
    if (active.front() < 0 || active.back() < 0) {
      addProblem(out, "a corner of its square is not a vertex");
      continue;
    }
    for (uint32_t j = 0; j < r; ++j) {
      const int32_t p = position(n - 1 - j);
      if (p < 0) continue;
      active[size_t(p)] = -1;
      int32_t a = p, b = p;
      while (a > 0 && active[size_t(a)] < 0) --a;
      while (b + 1 < length && active[size_t(b)] < 0) ++b;
      if (active[size_t(a)] < 0 || active[size_t(b)] < 0) {
        addProblem(out, "a corner of its square collapses");
        break;
      }
      segment(a, b);
    }
  }
  return out;
}

}  // namespace terralod
