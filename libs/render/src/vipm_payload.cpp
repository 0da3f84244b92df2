#include "vipm_payload.h"

#include "terralod/format/vipm_chunk_codec.h"
#include "terralod/vipm/grid_patch.h"
#include "terralod/vipm/vipm_blob.h"

namespace terralod {

uint64_t VipmChunkPayload::bytes() const {
  uint64_t b = mesh.points.size() * 2 + mesh.targets.size() * 6 + mesh.triangles.size() * 6;
  for (const VipmPart& p : levels.parts())
    b +=
        p.indices.size() * 2 + p.triangles.size() * 4 + p.moveStart.size() * 4 + p.moves.size() * 4;
  b += positions.size() * sizeof(positions[0]) + materials.size();
  b += flanges.tops.size() * 4;
  b += stitcher.bytes();
  return b + textureBytes();
}

uint64_t VipmChunkPayload::textureBytes() const {
  uint64_t b = blot.size();
  for (const auto& mip : normals.mips) b += mip.size();
  return b;
}

Result<VipmChunkPayload> decodeVipmPayload(const NodeBytes& node, const std::string& subject,
                                           uint32_t chunkCells, uint8_t flangeSides,
                                           float flangeDepth, int64_t cornerX, int64_t cornerY,
                                           uint32_t largestCells,
                                           const MaterialAverages& averages) {
  auto normals = decodeVipmNormalMap(node.texture(), chunkCells, subject);
  if (!normals) return normals.error();
  // A chunk wider than a leaf is a root or above: its collapses (without the rules) fade
  // materials; a root has flanges and fans on its children's shared sides too.
  const bool root = chunkCells > uint32_t(kVipmChunkCells);
  const MaterialFade fade = root ? MaterialFade::kToTarget : MaterialFade::kKeep;
  const int32_t seams = vipmSeamStep(chunkCells);
  auto loaded = loadVipmChunk(node.mesh(), subject, fade);
  if (!loaded) return loaded.error();
  const VipmChunkData& data = loaded->data;
  UnpackedChunk& unpacked = loaded->unpacked;
  VipmChunkPayload p;
  p.zBase = data.zBase;
  p.width = data.width;
  p.height = data.height;
  p.flangeDepth = flangeDepth;
  p.positions = positionsAboveBase(*loaded);
  p.levels = std::move(loaded->levels);
  p.normals = std::move(normals).value();
  p.cells = chunkCells;
  p.flanges = makeFlanges(unpacked.mesh, flangeSides, seams);
  p.fade = fade;
  const uint32_t texels = vipmNormalMapCells(chunkCells);
  p.blot = makeBlotTexels(unpacked.mesh, unpacked.materials, averages, int32_t(texels),
                          int32_t(chunkCells / texels));
  p.materials = std::move(unpacked.materials);
  for (uint16_t top : p.flanges.tops) {
    const auto& t = p.positions[top];
    p.positions.push_back({t[0], t[1], t[2] - flangeDepth});
    p.materials.push_back(p.materials[top]);
  }
  p.stitcher = VipmStitcher(
      unpacked.mesh, {cornerX, cornerY, data.zBase, data.width, data.height, seams, largestCells});
  p.mesh = std::move(unpacked.mesh);
  return p;
}

}  // namespace terralod
