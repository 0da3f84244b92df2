#include "terralod/vegetation/tileset_materials.h"

#include <algorithm>
#include <array>

#include "terralod/format/chunk_position.h"
#include "terralod/format/vipm_chunk_codec.h"
#include "terralod/materials/material_raster.h"

namespace terralod::veg {
namespace {

// Every grid point under the chunk's full-detail triangles takes the material of the triangle's
// corner it is nearest to (largest barycentric weight; what splatting shows most of there). The
// finest level is simplified within the leaf error, so its vertices alone miss grid points.
void paintTriangles(const VipmChunkData& data, std::array<int64_t, 2> origin, MaterialMap& map) {
  const auto at = [&](uint16_t v) {
    return std::array<int64_t, 2>{origin[0] + data.points[v] % data.width,
                                  origin[1] + data.points[v] / data.width};
  };
  for (size_t k = 0; k + 2 < data.indices.size(); k += 3) {
    const std::array<uint16_t, 3> v = {data.indices[k], data.indices[k + 1], data.indices[k + 2]};
    const std::array<std::array<int64_t, 2>, 3> p = {at(v[0]), at(v[1]), at(v[2])};
    const int64_t area =
        (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
    if (area == 0) continue;
    const int64_t xa = std::max<int64_t>(0, std::min({p[0][0], p[1][0], p[2][0]}));
    const int64_t xb = std::min<int64_t>(map.columns - 1, std::max({p[0][0], p[1][0], p[2][0]}));
    const int64_t ya = std::max<int64_t>(0, std::min({p[0][1], p[1][1], p[2][1]}));
    const int64_t yb = std::min<int64_t>(map.rows - 1, std::max({p[0][1], p[1][1], p[2][1]}));
    for (int64_t y = ya; y <= yb; ++y)
      for (int64_t x = xa; x <= xb; ++x) {
        // Twice the signed areas opposite each corner, in integers: exact on the edges.
        std::array<int64_t, 3> w{};
        for (int c = 0; c < 3; ++c) {
          const auto& q = p[size_t((c + 1) % 3)];
          const auto& r = p[size_t((c + 2) % 3)];
          w[size_t(c)] = ((q[0] - x) * (r[1] - y) - (r[0] - x) * (q[1] - y)) * (area > 0 ? 1 : -1);
        }
        if (w[0] < 0 || w[1] < 0 || w[2] < 0) continue;
        const size_t best = size_t(std::max_element(w.begin(), w.end()) - w.begin());
        map.classes[size_t(y) * size_t(map.columns) + size_t(x)] = data.materials[v[best]];
      }
  }
}

Result<MaterialMap> vipmMaterials(const TilesetReader& tileset, Progress& progress) {
  const TilesetHeader& h = tileset.header();
  MaterialMap map;
  map.columns = int32_t(h.sourceColumns);
  map.rows = int32_t(h.sourceRows);
  map.classes.assign(size_t(map.columns) * size_t(map.rows), 0);
  for (const TilesetMaterial& m : tileset.metadata().materials)
    map.materials.push_back({m.id, m.name, m.color});
  // Nodes are breadth first: roots (their children's coarsest points) before the leaves, which
  // hold every grid point and so have the last word.
  const auto& nodes = tileset.nodes();
  const auto wanted = [&](const NodeRecord& record) {
    return record.meshKind == MeshKind::kVipm &&
           h.chunkCells(record.level) <= int32_t(kVipmRootCells);
  };
  progress.begin("vegetation materials",
                 uint64_t(std::count_if(nodes.begin(), nodes.end(), wanted)));
  for (uint32_t n = 0; n < nodes.size(); ++n) {
    const NodeRecord& record = nodes[n];
    if (!wanted(record)) continue;
    auto bytes = tileset.readNode(n);
    if (!bytes) return bytes.error();
    auto data = decodeVipmChunk(bytes->mesh(), tileset.name() + " chunk " + std::to_string(n));
    if (!data) return data.error();
    for (uint8_t m : data->materials)
      if (m >= map.materials.size())
        return makeError(tileset.name(), "chunk " + std::to_string(n) + " names material " +
                                             std::to_string(m) + " the metadata lacks");
    paintTriangles(*data, chunkCellOrigin(h, record), map);
    progress.advance();
  }
  progress.end();
  return map;
}

}  // namespace

Result<MaterialMap> tilesetMaterials(const TilesetReader& tileset,
                                     const TilesetMaterialSource& source, Progress& progress) {
  if (!source.rasterPath.empty())
    return readMaterialRaster(
        source.rasterPath, sourceGridOf(tileset.header(), tileset.metadata()),
        tileset.metadata().sourceFile.empty() ? tileset.name() : tileset.metadata().sourceFile,
        {source.palettePath});
  if (tileset.header().meshKind != MeshKind::kVipm)
    return makeError(tileset.name(),
                     "has no materials (not a VIPM tileset): give --vegetation-materials RASTER "
                     "for --vegetation-where material=...");
  return vipmMaterials(tileset, progress);
}

}  // namespace terralod::veg
