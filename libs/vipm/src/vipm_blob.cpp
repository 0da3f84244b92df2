#include "terralod/vipm/vipm_blob.h"

namespace terralod {

Result<LoadedVipmChunk> loadVipmChunk(std::span<const uint8_t> blob, const std::string& subject,
                                      MaterialFade fade) {
  auto data = decodeVipmChunk(blob, subject);
  if (!data) return data.error();
  LoadedVipmChunk out;
  out.data = std::move(data).value();
  out.unpacked = unpackChunk(out.data);
  auto levels = VipmLevels::reconstruct(out.unpacked.mesh, out.unpacked.materials, fade);
  if (!levels) return makeError(subject, "corrupt VIPM chunk: " + levels.error().message);
  out.levels = std::move(levels).value();
  return out;
}

std::vector<std::array<float, 3>> positionsAboveBase(const LoadedVipmChunk& chunk) {
  std::vector<std::array<float, 3>> out;
  out.reserve(chunk.data.vertexCount());
  for (uint32_t v = 0; v < chunk.data.vertexCount(); ++v)
    out.push_back({chunk.unpacked.positions[v][0], chunk.unpacked.positions[v][1],
                   float(double(chunk.data.heights[v]) * chunk.data.zStep)});
  return out;
}

}  // namespace terralod
