#include "terralod/build/vipm_chunks.h"

#include <time.h>
#include <algorithm>
#include <array>

#include <cassert>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

#include "terralod/build/texel_tile.h"
#include "terralod/build/texture_encoder.h"
#include "terralod/vipm/vipm_fans.h"
#include "terralod/vipm/vipm_storage.h"
#include "vipm_cells.h"

namespace terralod {
namespace {

// CPU time of the calling thread (wall time would count other builds on a shared machine).
double threadSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

uint16_t findRoot(std::vector<uint16_t>& rep, uint16_t v) {
  while (rep[v] != v) v = rep[v] = rep[rep[v]];
  return v;
}

// The coarsest level of `mesh` (every collapse applied), in DEM grid coordinates.
CoarseMesh coarsestLevel(const ProgressiveMesh& mesh, const VipmChunkData& stored, int32_t x0,
                         int32_t y0) {
  const uint32_t n = mesh.vertexCount(), r = mesh.collapseCount();
  auto removals = triangleRemovals(mesh);
  assert(removals.ok());  // the collapser's own order is consistent
  std::vector<uint16_t> rep(n);
  std::iota(rep.begin(), rep.end(), uint16_t{0});
  for (uint32_t j = 0; j < r; ++j) rep[n - 1 - j] = mesh.targets[j];
  CoarseMesh c;
  const uint32_t kept = n - r;  // the active vertices [0, kept) keep their indices
  for (uint32_t v = 0; v < kept; ++v) {
    c.gridX.push_back(uint32_t(x0) + mesh.points[v] % uint32_t(mesh.width));
    c.gridY.push_back(uint32_t(y0) + mesh.points[v] / uint32_t(mesh.width));
    c.heights.push_back(stored.zBase + double(stored.heights[v]) * stored.zStep);
    c.materials.push_back(stored.materials[v]);
  }
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (removals.ok() && (*removals)[t] != r) continue;
    // Each triangle from its lowest corner (the blob codec may rotate corners, so a chunk
    // read back from its blob gives the same level as the one that was encoded).
    std::array<uint32_t, 3> corners;
    for (int k = 0; k < 3; ++k) corners[k] = findRoot(rep, mesh.triangles[t][k]);
    const int first = int(std::min_element(corners.begin(), corners.end()) - corners.begin());
    for (int k = 0; k < 3; ++k) c.indices.push_back(corners[(first + k) % 3]);
  }
  return c;
}

// The source's heights and materials over a chunk's points.
GridPatch sourcePatch(const Heightfield& heights, const MaterialMap& materials, int32_t x0,
                      int32_t y0, int32_t width, int32_t height) {
  GridPatch patch;
  patch.width = width;
  patch.height = height;
  patch.heights.reserve(patch.pointCount());
  patch.materials.reserve(patch.pointCount());
  for (int32_t y = 0; y < height; ++y)
    for (int32_t x = 0; x < width; ++x) {
      patch.heights.push_back(heights(x0 + x, y0 + y));
      patch.materials.push_back(materials.at(x0 + x, y0 + y));
    }
  return patch;
}

// A dense patch's source heights by grid point.
std::function<double(int32_t, int32_t)> denseSource(const GridPatch& patch) {
  return [&patch](int32_t x, int32_t y) { return double(patch.heightAt(x, y)); };
}

// The source patch with its vertex heights rounded to the tileset's step, as a chunk is built
// from (a base on that step at or below every sample).
GridPatch quantisedPatch(const Heightfield& heights, const MaterialMap& materials, int32_t x0,
                         int32_t y0, int32_t width, int32_t height, double zStep,
                         HeightQuantisation& q) {
  GridPatch patch = sourcePatch(heights, materials, x0, y0, width, height);
  const float lowest = *std::min_element(patch.heights.begin(), patch.heights.end());
  q = {std::floor(double(lowest) / zStep) * zStep, zStep};
  quantiseVertexHeights(patch, q);
  return patch;
}

// A stored chunk's node fields (meshKind, minZ, maxZ, counts) and its vertices' heights.
NodeRecord storedNode(const VipmChunkData& stored, std::vector<double>& vertexHeights) {
  vertexHeights.clear();
  for (uint16_t z : stored.heights)
    vertexHeights.push_back(stored.zBase + double(z) * stored.zStep);
  const auto [lo, hi] = std::minmax_element(vertexHeights.begin(), vertexHeights.end());
  NodeRecord node;
  node.meshKind = MeshKind::kVipm;
  node.minZ = floatBelow(*lo);
  node.maxZ = floatAbove(*hi);
  node.vertexCount = stored.vertexCount();
  node.triangleCount = stored.triangleCount();
  return node;
}

// The error of a stored chunk's coarsest level, as a reader unpacks it.
float coarsestError(const VipmChunkData& stored) {
  if (stored.errors.empty()) return stored.finestError;
  const UnpackedChunk u = unpackChunk(stored);
  return u.mesh.errors.back();
}

// Whether a root of width x height points holds its children's shared sides.
bool hasSeams(int32_t width, int32_t height) {
  return width > kLeaf + 1 || height > kLeaf + 1;
}

// The source heights by grid point of a node whose south-west point is (x0, y0).
std::function<double(int32_t, int32_t)> windowSource(const Heightfield& heights, int32_t x0,
                                                     int32_t y0) {
  return [&heights, x0, y0](int32_t x, int32_t y) { return double(heights(x0 + x, y0 + y)); };
}

// Closes the cracks of a joined mesh: its children's coarsest levels meet on their shared
// sides with T-junctions (each side simplified on its own), and so do their own children's
// inside them. Each open edge on a grid line inside the patch is split at the points the
// other side has on it, by a fan from its triangle's opposite corner (as fan stitching draws
// it, the edge on the finest line first where a triangle has two): afterwards both sides hold
// the union of their points, and the mesh is a manifold whose only open edges are on the
// patch's sides.
void closeCracks(const GridPatch& patch, std::vector<std::array<uint16_t, 3>>& triangles) {
  auto key = [](uint16_t a, uint16_t b) {
    return (uint32_t(std::min(a, b)) << 16) | std::max(a, b);
  };
  auto inside = [&](int32_t c, int32_t size) { return c > 0 && c < size - 1; };
  // The points on each line x = c (axis 0, by y) and y = c (axis 1, by x).
  std::unordered_map<uint64_t, std::vector<std::pair<int32_t, uint16_t>>> lines;
  for (uint32_t v = 0; v < patch.pointCount(); ++v) {
    const int32_t x = patch.xOf(v), y = patch.yOf(v);
    if (inside(x, patch.width)) lines[uint64_t(x) << 1].push_back({y, uint16_t(v)});
    if (inside(y, patch.height)) lines[(uint64_t(y) << 1) | 1].push_back({x, uint16_t(v)});
  }
  for (auto& [unused, points] : lines) std::sort(points.begin(), points.end());
  bool changed = true;
  while (changed) {
    changed = false;
    std::unordered_map<uint32_t, int> uses;
    for (const auto& t : triangles)
      for (int k = 0; k < 3; ++k) ++uses[key(t[size_t(k)], t[size_t(k + 1) % 3])];
    std::vector<std::array<uint16_t, 3>> out;
    out.reserve(triangles.size());
    std::vector<uint16_t> between, at;  // the chosen edge's points, a candidate's
    for (const auto& t : triangles) {
      // The open edge to split first: on the finest line, as fan stitching cuts a corner
      // (stitchLineOrder; a line inside the node has as many trailing zero bits locally as
      // in the map, the node's corner being a multiple of its cells).
      int chosen = -1;
      uint32_t chosenOrder = 0;
      between.clear();
      for (int k = 0; k < 3; ++k) {
        const uint16_t a = t[size_t(k)], b = t[size_t(k + 1) % 3];
        if (uses[key(a, b)] != 1) continue;
        const int32_t ax = patch.xOf(a), ay = patch.yOf(a), bx = patch.xOf(b), by = patch.yOf(b);
        StitchLine line;
        int32_t from, to;
        if (ax == bx && inside(ax, patch.width)) {
          line = {0, ax};
          from = ay;
          to = by;
        } else if (ay == by && inside(ay, patch.height)) {
          line = {1, ay};
          from = ax;
          to = bx;
        } else {
          continue;
        }
        const auto found = lines.find((uint64_t(line.at) << 1) | line.axis);
        if (found == lines.end()) continue;
        at.clear();
        for (const auto& [along, v] : found->second)
          if (along > std::min(from, to) && along < std::max(from, to)) at.push_back(v);
        if (at.empty()) continue;
        if (from > to) std::reverse(at.begin(), at.end());
        if (chosen < 0 || stitchLineOrder(line) < chosenOrder) {
          chosen = k;
          chosenOrder = stitchLineOrder(line);
          between.swap(at);
        }
      }
      if (chosen < 0) {
        out.push_back(t);
        continue;
      }
      const uint16_t a = t[size_t(chosen)], b = t[size_t(chosen + 1) % 3],
                     c = t[size_t(chosen + 2) % 3];
      uint16_t previous = a;
      for (uint16_t p : between) {
        out.push_back({previous, p, c});
        previous = p;
      }
      out.push_back({previous, b, c});
      changed = true;
    }
    triangles = std::move(out);
  }
}

// A root's or upper node's fields from its stored form: `mesh` is `stored` unpacked (the
// coarsest level is read from it, triangles in stored order, so a node built and one kept
// give the same), `source` the source heights by grid point, `seams` whether it holds its
// children's shared sides (their deviation is its coarsest error).
VipmRoot storedRoot(std::vector<uint8_t> blob, const VipmChunkData& stored,
                    const ProgressiveMesh& mesh,
                    const std::function<double(int32_t, int32_t)>& source, int32_t x0, int32_t y0,
                    bool seams) {
  VipmRoot root;
  root.blob = std::move(blob);
  std::vector<double> vertexHeights;
  root.node = storedNode(stored, vertexHeights);
  root.borderDeviation = borderDeviation(mesh, source, vertexHeights);
  root.seamDeviation = seams ? coarsestError(stored) : 0.0;
  root.collapses = stored.collapseCount();
  root.coarsest = coarsestLevel(mesh, stored, x0, y0);
  root.coarsest.error = coarsestError(stored);
  return root;
}

// A stored chunk decoded and unpacked, with the patch it was built from.
struct Stored {
  VipmChunkData data;
  ProgressiveMesh mesh;
  GridPatch patch;
  std::vector<double> vertexHeights;
  NodeRecord node;
};

Result<Stored> readStored(const std::vector<uint8_t>& blob, const Heightfield& heights,
                          const MaterialMap& materials, int32_t x0, int32_t y0, int32_t width,
                          int32_t height, double zStep) {
  auto decoded = decodeVipmChunk(blob, "reused chunk");
  if (!decoded) return decoded.error();
  Stored s;
  s.data = std::move(*decoded);
  if (s.data.width != width || s.data.height != height || s.data.zStep != zStep)
    return Error{"reused chunk: not the chunk it replaces"};
  s.mesh = unpackChunk(s.data).mesh;
  HeightQuantisation q;
  s.patch = quantisedPatch(heights, materials, x0, y0, width, height, zStep, q);
  s.node = storedNode(s.data, s.vertexHeights);
  return s;
}

}  // namespace

Result<VipmLeaf> reuseVipmLeaf(std::vector<uint8_t> blob, const Heightfield& heights,
                               const MaterialMap& materials, int32_t x0, int32_t y0, int32_t width,
                               int32_t height, double zStep) {
  auto s = readStored(blob, heights, materials, x0, y0, width, height, zStep);
  if (!s) return s.error();
  VipmLeaf leaf;
  leaf.blob = std::move(blob);
  leaf.node = s->node;
  leaf.coarsest = coarsestLevel(s->mesh, s->data, x0, y0);
  leaf.coarsest.error = coarsestError(s->data);
  leaf.borderDeviation = borderDeviation(s->mesh, denseSource(s->patch), s->vertexHeights);
  leaf.collapses = s->data.collapseCount();
  return leaf;
}

Result<VipmRoot> reuseVipmRoot(std::vector<uint8_t> blob, const Heightfield& heights,
                               const MaterialMap& materials, int32_t x0, int32_t y0, int32_t width,
                               int32_t height, double zStep) {
  auto s = readStored(blob, heights, materials, x0, y0, width, height, zStep);
  if (!s) return s.error();
  return storedRoot(std::move(blob), s->data, s->mesh, denseSource(s->patch), x0, y0,
                    hasSeams(width, height));
}

Result<VipmRoot> reuseVipmUpperNode(std::vector<uint8_t> blob, const Heightfield& heights,
                                    int32_t x0, int32_t y0, int32_t width, int32_t height,
                                    double zStep) {
  auto decoded = decodeVipmChunk(blob, "reused chunk");
  if (!decoded) return decoded.error();
  const VipmChunkData& data = *decoded;
  if (data.width != width || data.height != height || data.zStep != zStep)
    return Error{"reused chunk: not the chunk it replaces"};
  // No seams: its cracks are closed.
  return storedRoot(std::move(blob), data, unpackChunk(data).mesh, windowSource(heights, x0, y0),
                    x0, y0, false);
}

double vipmTilesetZStep(double maxError, double range) {
  double step = std::exp2(std::floor(std::log2(std::max(maxError, 1e-6) / 8.0)));
  while (range / step > 65000.0) step *= 2.0;
  return step;
}

float floatBelow(double v) {
  float f = float(v);
  if (double(f) > v) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

float floatAbove(double v) {
  float f = float(v);
  if (double(f) < v) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

double borderDeviation(const ProgressiveMesh& mesh,
                       const std::function<double(int32_t, int32_t)>& source,
                       const std::vector<double>& stored) {
  const int32_t w = mesh.width, h = mesh.height;
  // Sides: south, north (along x), west, east (along y). active[side][pos]: vertex or -1.
  struct Side {
    std::vector<int32_t> active;
    std::vector<double> source;
  };
  Side sides[4];
  for (int s = 0; s < 4; ++s) {
    const int32_t length = s < 2 ? w : h;
    sides[s].active.assign(size_t(length), -1);
    for (int32_t pos = 0; pos < length; ++pos) {
      const int32_t x = s < 2 ? pos : (s == 2 ? 0 : w - 1);
      const int32_t y = s < 2 ? (s == 0 ? 0 : h - 1) : pos;
      sides[s].source.push_back(source(x, y));
    }
  }
  auto sideAndPos = [&](uint32_t vertex, int s) -> int32_t {
    const int32_t x = int32_t(mesh.points[vertex] % uint32_t(w));
    const int32_t y = int32_t(mesh.points[vertex] / uint32_t(w));
    switch (s) {
      case 0:
        return y == 0 ? x : -1;
      case 1:
        return y == h - 1 ? x : -1;
      case 2:
        return x == 0 ? y : -1;
      default:
        return x == w - 1 ? y : -1;
    }
  };
  for (uint32_t v = 0; v < mesh.vertexCount(); ++v)
    for (int s = 0; s < 4; ++s)
      if (const int32_t pos = sideAndPos(v, s); pos >= 0) sides[s].active[size_t(pos)] = int32_t(v);

  double deviation = 0.0;
  auto segment = [&](const Side& side, int32_t a, int32_t b) {
    const double ha = stored[size_t(side.active[size_t(a)])];
    const double hb = stored[size_t(side.active[size_t(b)])];
    for (int32_t pos = a; pos <= b; ++pos) {
      const double line = b == a ? ha : ha + (hb - ha) * double(pos - a) / double(b - a);
      deviation = std::max(deviation, std::abs(side.source[size_t(pos)] - line));
    }
  };
  for (const Side& side : sides) {  // the finest level
    int32_t previous = -1;
    for (int32_t pos = 0; pos < int32_t(side.active.size()); ++pos) {
      if (side.active[size_t(pos)] < 0) continue;
      if (previous >= 0) segment(side, previous, pos);
      previous = pos;
    }
  }
  // Each collapse of a side vertex (along its side) joins the segments beside it.
  const uint32_t n = mesh.vertexCount();
  for (uint32_t j = 0; j < mesh.collapseCount(); ++j) {
    const uint32_t v = n - 1 - j;
    for (Side& side : sides) {
      const int s = int(&side - sides);
      const int32_t pos = sideAndPos(v, s);
      if (pos < 0) continue;
      side.active[size_t(pos)] = -1;
      int32_t a = pos, b = pos;
      while (a > 0 && side.active[size_t(a)] < 0) --a;
      while (b + 1 < int32_t(side.active.size()) && side.active[size_t(b)] < 0) ++b;
      // Corners never collapse, so both ends exist.
      if (side.active[size_t(a)] >= 0 && side.active[size_t(b)] >= 0) segment(side, a, b);
    }
  }
  return deviation;
}

VipmLeaf buildVipmLeaf(const Heightfield& heights, const MaterialMap& materials, int32_t x0,
                       int32_t y0, int32_t width, int32_t height, const VipmLeafParams& params) {
  const double start = threadSeconds();
  HeightQuantisation q;
  GridPatch patch = quantisedPatch(heights, materials, x0, y0, width, height, params.zStep, q);
  CollapseStart from;
  from.bakedError = floatBelow(params.maxError);
  CollapseOrder order = buildCollapseOrder(patch, params.rules, from);
  while (!order.collapses.empty() && double(order.collapses.back().error) > params.coarsestError)
    order.collapses.pop_back();
  const ProgressiveMesh mesh = makeProgressiveMesh(patch, order, params.maxError);
  const VipmChunkData stored = packChunk(patch, mesh, q);

  VipmLeaf leaf;
  leaf.blob = encodeVipmChunk(stored, params.compressionLevel);
  std::vector<double> vertexHeights;
  leaf.node = storedNode(stored, vertexHeights);
  // From the chunk as stored (its triangles in stored order), as reuseVipmLeaf gets it, so
  // that the root joined from it is the same whether the leaf was built or kept.
  leaf.coarsest = coarsestLevel(unpackChunk(stored).mesh, stored, x0, y0);
  leaf.coarsest.error = coarsestError(stored);
  leaf.borderDeviation = borderDeviation(mesh, denseSource(patch), vertexHeights);
  leaf.collapses = stored.collapseCount();
  leaf.seconds = threadSeconds() - start;
  return leaf;
}

VipmGridChunk buildVipmGridChunk(const Heightfield& heights, const MaterialMap& materials,
                                 int32_t x0, int32_t y0, int32_t width, int32_t height,
                                 double zStep, int compressionLevel) {
  HeightQuantisation q;
  const GridPatch patch = quantisedPatch(heights, materials, x0, y0, width, height, zStep, q);
  CollapseOrder grid;  // no collapses
  grid.gridTriangles = gridTriangulation(width, height);
  const VipmChunkData stored = packChunk(patch, makeProgressiveMesh(patch, grid, 0.0), q);
  VipmGridChunk chunk;
  chunk.blob = encodeVipmChunk(stored, compressionLevel);
  std::vector<double> vertexHeights;
  chunk.node = storedNode(stored, vertexHeights);
  return chunk;
}

VipmChunkData joinCoarsest(const std::vector<const CoarseMesh*>& children, int32_t x0, int32_t y0,
                           int32_t width, int32_t height, double zStep) {
  assert(width >= 2 && height >= 2 && width <= int32_t(kVipmMaxGridPoints) &&
         height <= int32_t(kVipmMaxGridPoints));
  VipmChunkData d;
  d.width = uint8_t(width);
  d.height = uint8_t(height);
  d.zStep = zStep;
  d.errorStep = 1.0f;
  double lowest = std::numeric_limits<double>::infinity();
  for (const CoarseMesh* c : children) {
    d.finestError = std::max(d.finestError, c->error);
    for (double z : c->heights) lowest = std::min(lowest, z);
  }
  d.zBase = std::floor(lowest / zStep) * zStep;
  std::vector<int32_t> slot(size_t(width) * size_t(height), -1);
  for (const CoarseMesh* c : children)
    for (uint32_t v : c->indices) {
      const int32_t x = int32_t(c->gridX[v]) - x0, y = int32_t(c->gridY[v]) - y0;
      assert(x >= 0 && y >= 0 && x < width && y < height);
      const size_t point = size_t(y) * size_t(width) + size_t(x);
      if (slot[point] < 0) {
        slot[point] = int32_t(d.points.size());
        d.points.push_back(uint16_t(point));
        const double z = (c->heights[v] - d.zBase) / zStep;
        assert(z == std::round(z) && z >= 0 && z <= 65535);  // children share the zStep
        d.heights.push_back(uint16_t(z));
        d.materials.push_back(c->materials[v]);
      }
      d.indices.push_back(uint16_t(slot[point]));
    }
  return d;
}

VipmRoot buildVipmRoot(const Heightfield& heights, const MaterialMap& materials,
                       const std::vector<const CoarseMesh*>& children, int32_t x0, int32_t y0,
                       int32_t width, int32_t height, double zStep, double levelError,
                       double lastError, int compressionLevel) {
  const double start = threadSeconds();
  const VipmChunkData joined = joinCoarsest(children, x0, y0, width, height, zStep);
  // The children's stored heights are round(h / zStep) zStep on the tileset's step; the
  // patch's base keeps them (and bounds every point's rounding).
  HeightQuantisation q;
  GridPatch patch = quantisedPatch(heights, materials, x0, y0, width, height, zStep, q);
  CollapseStart from;
  // A root's points (<= 129 x 129) are its dense patch's ids.
  auto id = [&](size_t i) { return uint16_t(joined.points[joined.indices[i]]); };
  for (size_t i = 0; i + 2 < joined.indices.size(); i += 3)
    from.triangles.push_back({id(i), id(i + 1), id(i + 2)});
  for (size_t v = 0; v < joined.points.size(); ++v)
    assert(patch.vertexHeight(joined.points[v]) ==
           float(joined.zBase + double(joined.heights[v]) * zStep));
  from.seamX = width > kLeaf + 1 ? kLeaf : -1;
  from.seamY = height > kLeaf + 1 ? kLeaf : -1;
  assert(hasSeams(width, height) == (from.seamX >= 0 || from.seamY >= 0));
  // Every collapse waits for the root to take over (θ >= levelError).
  from.errorFloor = floatAbove(levelError);
  from.lastError = floatBelow(lastError);
  CollapseOrder order = buildCollapseOrder(patch, MaterialRules::kOff, from);
  const ProgressiveMesh mesh = makeProgressiveMesh(patch, order, 0.0);  // none applied
  const VipmChunkData stored = packChunk(patch, mesh, q);

  VipmRoot root =
      storedRoot(encodeVipmChunk(stored, compressionLevel), stored, unpackChunk(stored).mesh,
                 denseSource(patch), x0, y0, hasSeams(width, height));
  root.seconds = threadSeconds() - start;
  return root;
}

int32_t vipmUpperSampleStep(int32_t cells) {
  return std::max(1, cells / 128);
}

std::optional<VipmRoot> buildVipmUpperNode(const Heightfield& heights,
                                           const std::vector<const CoarseMesh*>& children,
                                           int32_t x0, int32_t y0, int32_t cells, int32_t width,
                                           int32_t height, double zStep, double levelError,
                                           double lastError, int compressionLevel) {
  const double start = threadSeconds();
  // The children's coarsest levels joined: points by grid coordinates (first use first), their
  // stored heights as the vertices' (all on the tileset's step); nothing if they are more than
  // a node can index.
  GridPatch patch;
  patch.width = width;
  patch.height = height;
  CollapseStart from;
  std::unordered_map<uint64_t, uint16_t> slot;
  for (const CoarseMesh* c : children)
    for (size_t i = 0; i + 2 < c->indices.size(); i += 3) {
      std::array<uint16_t, 3> t;
      for (size_t k = 0; k < 3; ++k) {
        const uint32_t v = c->indices[i + k];
        const int32_t x = int32_t(c->gridX[v]) - x0, y = int32_t(c->gridY[v]) - y0;
        assert(x >= 0 && y >= 0 && x < width && y < height);
        const auto [at, fresh] = slot.try_emplace(uint64_t(y) * uint64_t(width) + uint64_t(x),
                                                  uint16_t(patch.pointX.size()));
        if (fresh) {
          if (patch.pointX.size() == kVipmMaxNodeVertices) return std::nullopt;
          patch.pointX.push_back(x);
          patch.pointY.push_back(y);
          patch.heights.push_back(heights(x0 + x, y0 + y));
          patch.vertexHeights.push_back(float(c->heights[v]));
          patch.materials.push_back(c->materials[v]);
        }
        t[k] = at->second;
      }
      from.triangles.push_back(t);
    }
  patch.samples = makeSampleBlocks(width, height, vipmUpperSampleStep(cells),
                                   [&](int32_t x, int32_t y) { return heights(x0 + x, y0 + y); });
  // Without cracks inside, its vertices move freely but for its own sides'.
  closeCracks(patch, from.triangles);
  from.errorFloor = floatAbove(levelError);
  from.lastError = floatBelow(lastError);
  const CollapseOrder order = buildCollapseOrder(patch, MaterialRules::kOff, from);
  const ProgressiveMesh mesh = makeProgressiveMesh(patch, order, 0.0);  // none applied
  const float lowest = *std::min_element(patch.vertexHeights.begin(), patch.vertexHeights.end());
  const HeightQuantisation q{std::floor(double(lowest) / zStep) * zStep, zStep};
  const VipmChunkData stored = packChunk(patch, mesh, q);

  // No seams: its cracks are closed.
  VipmRoot node =
      storedRoot(encodeVipmChunk(stored, compressionLevel), stored, unpackChunk(stored).mesh,
                 windowSource(heights, x0, y0), x0, y0, false);
  node.seconds = threadSeconds() - start;
  return node;
}

std::vector<uint8_t> buildVipmNormalMap(const Heightfield& heights, int32_t x0, int32_t y0,
                                        int32_t cells, double spacingX, double spacingY) {
  // As a static tileset's normal layers are made (BlockTexels::normals), on the grid at the
  // map's stride.
  const int32_t n = int32_t(vipmNormalMapCells(uint32_t(cells))), stride = cells / n;
  const TexelTile tile = centralDifferenceNormals(
      x0 / stride, y0 / stride, n, spacingX * stride, spacingY * stride,
      [&](int32_t gx, int32_t gy) { return heights.at(gx * stride, gy * stride); });
  ChunkTexture texture;
  texture.layers.push_back(encodeNormalLayer(tile, kTextureSourceLimited));
  return encodeRawTexture(texture);
}

}  // namespace terralod
