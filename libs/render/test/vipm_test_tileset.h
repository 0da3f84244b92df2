#pragma once
// A small VIPM tileset written by hand for the renderer's tests (until `terralod build --kind
// vipm` exists): a 129 x 129 window of Crater Lake's DEM with three materials by height band,
// as four 64-cell VIPM leaves under one root. The root is a coarse stand-in for the builder's
// fallback (every 16th grid point, no collapses); flanges are twice the largest coarsest
// error deep (a border's deviation from the source is at most its level's error, each side).
// Every node has its normal map from the window's heights, as the builder makes them.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "temp_dir.h"
#include "terralod/build/vipm_chunks.h"
#include "terralod/format/tileset_writer.h"
#include "terralod/format/vipm_chunk_codec.h"
#include "terralod/raster/dem_reader.h"
#include "terralod/vipm/progressive_mesh.h"
#include "terralod/vipm/vipm_storage.h"

namespace terralod::test {

inline constexpr int32_t kVipmWindow = 129;

/// Writes the tileset to `path`; returns an error message or "".
inline std::string writeVipmTestTileset(const std::string& path, int32_t x0 = 192,
                                        int32_t y0 = 192) {
  auto dem = DemReader::open(testData("crater_lake_0513.bt"), {});
  if (!dem) return dem.error().message;
  const int32_t n = kVipmWindow;
  std::vector<float> heights(size_t(n) * n);
  if (auto s = (*dem)->readWindow(x0, y0, n, n, heights.data()); !s) return s.error().message;
  auto material = [](float z) -> uint8_t { return z < 1900 ? 0 : z < 2050 ? 1 : 2; };
  const auto [lo, hi] = std::minmax_element(heights.begin(), heights.end());
  auto writer = TilesetWriter::create(path);
  if (!writer) return writer.error().message;
  Heightfield window(n, n);
  for (int32_t y = 0; y < n; ++y)
    for (int32_t x = 0; x < n; ++x) window(x, y) = heights[size_t(y) * n + size_t(x)];
  const double sx = (*dem)->info().spacingX, sy = (*dem)->info().spacingY;

  std::vector<NodeRecord> nodes(5);
  auto append = [&](NodeRecord& r, const VipmChunkData& c) {
    const std::vector<uint8_t> blob = encodeVipmChunk(c, 3);
    r.meshKind = MeshKind::kVipm;
    r.blobOffset = (*writer)->appendBlob(blob).value();
    r.blobBytes = uint32_t(blob.size());
    r.blobCrc = crc32Of(blob);
    const int32_t cells = r.level == 0 ? 128 : 64;
    const std::vector<uint8_t> normals =
        buildVipmNormalMap(window, int32_t(r.x) * cells, int32_t(r.y) * cells, cells, sx, sy);
    (*writer)->appendBlob(normals).value();
    r.flags = kNodeHasTexture;
    r.textureBytes = uint32_t(normals.size());
    const auto [zlo, zhi] = std::minmax_element(c.heights.begin(), c.heights.end());
    r.minZ = std::nextafter(float(c.zBase + *zlo * c.zStep), -1e30f);
    r.maxZ = std::nextafter(float(c.zBase + *zhi * c.zStep), 1e30f);
    r.vertexCount = c.vertexCount();
    r.triangleCount = c.triangleCount();
  };

  // The leaves.
  double coarsest = 0;
  for (int q = 0; q < 4; ++q) {
    GridPatch p;
    p.width = p.height = 65;
    for (int32_t y = 0; y < 65; ++y)
      for (int32_t x = 0; x < 65; ++x) {
        const float z = heights[size_t(y + 64 * (q >> 1)) * n + size_t(x + 64 * (q & 1))];
        p.heights.push_back(z);
        p.materials.push_back(material(z));
      }
    const HeightQuantisation hq = chooseQuantisation(p, 1.0);
    quantiseVertexHeights(p, hq);
    const ProgressiveMesh mesh =
        makeProgressiveMesh(p, buildCollapseOrder(p, MaterialRules::kOn), 1.0);
    if (!mesh.errors.empty()) coarsest = std::max(coarsest, double(mesh.errors.back()));
    NodeRecord& r = nodes[size_t(1 + q)];
    r.level = 1;
    r.x = uint32_t(q & 1);
    r.y = uint32_t(q >> 1);
    r.parent = 0;
    append(r, packChunk(p, mesh, hq));
  }

  // The root: every 16th point of the window, two triangles per square, no collapses.
  VipmChunkData root;
  root.width = root.height = uint8_t(n);
  root.zStep = 1.0 / 64;
  root.zBase = std::floor(*lo / root.zStep) * root.zStep;
  root.finestError = float(coarsest);
  const int32_t stride = 16, side = (n - 1) / stride + 1;
  for (int32_t y = 0; y < side; ++y)
    for (int32_t x = 0; x < side; ++x) {
      const size_t point = size_t(y * stride) * n + size_t(x * stride);
      root.points.push_back(uint16_t(point));
      root.heights.push_back(uint16_t(std::lround((heights[point] - root.zBase) / root.zStep)));
      root.materials.push_back(material(heights[point]));
    }
  for (int32_t y = 0; y + 1 < side; ++y)
    for (int32_t x = 0; x + 1 < side; ++x) {
      const auto v = [&](int32_t dx, int32_t dy) { return uint16_t((y + dy) * side + x + dx); };
      root.indices.insert(root.indices.end(),
                          {v(0, 0), v(1, 0), v(1, 1), v(0, 0), v(1, 1), v(0, 1)});
    }
  for (NodeRecord& r : nodes) r.maxSkirtDepth = float(2 * coarsest + 1.0);
  nodes[0].childMask = 15;
  nodes[0].firstChild = 1;
  append(nodes[0], root);

  TilesetHeader h;
  h.version = 2;
  h.flags = kTilesetTextured;
  h.textureMinTau = 2.0;
  h.meshKind = MeshKind::kVipm;
  h.levelCount = 2;
  h.leafCells = 64;
  h.rootCells = 128;
  h.rootsX = h.rootsY = 1;
  h.sourceColumns = h.sourceRows = uint32_t(n);
  h.spacingX = sx;
  h.spacingY = sy;
  h.leafError = 1.0;
  h.levelError[0] = 2 * coarsest;
  h.levelError[1] = 1.0;
  h.extentMin = {0, 0, *lo};
  h.extentMax = {128 * h.spacingX, 128 * h.spacingY, *hi};
  const std::string metadata =
      R"({"kind": "vipm", "materials": [{"id": 0, "name": "water", "color": "#2050a0"},)"
      R"( {"id": 1, "name": "grass", "color": "#40a030"},)"
      R"( {"id": 2, "name": "rock", "color": "#a09080"}]})";
  if (auto s = (*writer)->finish(h, nodes, metadata); !s) return s.error().message;
  return "";
}

}  // namespace terralod::test
