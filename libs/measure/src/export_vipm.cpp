#include <unordered_map>

#include "terralod/format/chunk_position.h"
#include "terralod/format/vipm_chunk_codec.h"
#include "terralod/measure/export_mesh.h"
#include "terralod/vipm/vipm_blob.h"
#include "terralod/vipm/vipm_levels.h"

namespace terralod {

Result<LevelSurface> gatherVipmSurface(const TilesetReader& tileset, double error,
                                       Progress& progress) {
  const TilesetHeader& header = tileset.header();
  const uint32_t leaves = uint32_t(header.levelCount - 1);
  LevelSurface surface;
  for (const NodeRecord& n : tileset.nodes()) surface.chunks += n.level == leaves;
  std::unordered_map<uint64_t, uint32_t> welded;  // grid point -> vertex
  progress.begin("reading chunks", surface.chunks);
  for (uint32_t i = 0; i < tileset.nodes().size(); ++i) {
    const NodeRecord& node = tileset.nodes()[i];
    if (node.level != leaves) continue;
    const std::string subject = tileset.name() + " chunk " + std::to_string(i);
    auto bytes = tileset.readNode(i);
    if (!bytes) return bytes.error();
    auto loaded = loadVipmChunk(bytes->mesh(), subject);
    if (!loaded) return loaded.error();
    const VipmChunkData& data = loaded->data;
    const UnpackedChunk& unpacked = loaded->unpacked;
    VipmLevels* levels = &loaded->levels;
    levels->setApplied(morphWindow(unpacked.mesh.errors, error, Geomorph::kOff).applied);
    const auto [x0, y0] = chunkCellOrigin(header, node);
    const VipmPart& whole = levels->whole();
    for (uint32_t k = 0; k < levels->drawnTriangles(whole) * 3; ++k) {
      const uint16_t v = whole.indices[k];
      const int64_t x = x0 + int64_t(unpacked.positions[v][0]);
      const int64_t y = y0 + int64_t(unpacked.positions[v][1]);
      const double z = data.zBase + double(data.heights[v]) * data.zStep;
      auto [it, fresh] =
          welded.try_emplace((uint64_t(x) << 32) | uint64_t(y), uint32_t(surface.positions.size()));
      if (fresh)
        surface.positions.push_back(
            {float(double(x) * header.spacingX), float(double(y) * header.spacingY), float(z)});
      surface.indices.push_back(it->second);
    }
    progress.advance();
  }
  progress.end();
  finishSurface(header, surface);
  return surface;
}

}  // namespace terralod
