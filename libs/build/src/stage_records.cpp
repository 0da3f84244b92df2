#include "stage_records.h"

#include <algorithm>

namespace terralod::stages {
namespace {

void packTile(Packer& p, const TexelTile& t) {
  p.put(t.size);
  p.put(t.channels);
  p.putArray(t.values);
}

void packLayer(Packer& p, const LayerLevels& l) {
  p.put(uint64_t(l.levels.size()));
  for (const TexelTile& t : l.levels) packTile(p, t);
  p.put(uint64_t(l.blocks.size()));
  for (const auto& b : l.blocks) p.putBytes(b);
}

// What packLayer wrote, read a piece at a time; false past the file's end.
bool readLayer(StageFileReader& r, LayerLevels& l) {
  const auto levels = r.get<uint64_t>();
  for (uint64_t i = 0; levels && i < *levels; ++i) {
    const auto size = r.get<uint32_t>(), channels = r.get<uint32_t>();
    auto values = r.getArray<float>();
    if (!size || !channels || !values) return false;
    l.levels.push_back({});
    l.levels.back().size = *size;
    l.levels.back().channels = *channels;
    l.levels.back().values = std::move(*values);
  }
  const auto blocks = levels ? r.get<uint64_t>() : std::nullopt;
  for (uint64_t i = 0; blocks && i < *blocks; ++i) {
    const auto b = r.getView();
    if (!b) return false;
    l.blocks.emplace_back(b->begin(), b->end());
  }
  return blocks.has_value();
}

}  // namespace

std::vector<LineRun> linesOf(const TreeLayout& layout, GridPoint o, int32_t block,
                             const float* window) {
  std::vector<LineRun> runs;
  const int32_t stride = block + 1;
  const int32_t xEnd = std::min(o.x + block, layout.cellsX),
                yEnd = std::min(o.y + block, layout.cellsY);
  for (int32_t y = o.y; y <= yEnd; ++y) {
    if (y % block != 0 && y != layout.cellsY) continue;
    LineRun r{1, y, o.x, {}};
    for (int32_t x = o.x; x <= xEnd; ++x)
      r.values.push_back(window[size_t(y - o.y) * stride + (x - o.x)]);
    runs.push_back(std::move(r));
  }
  for (int32_t x = o.x; x <= xEnd; ++x) {
    if (x % block != 0 && x != layout.cellsX) continue;
    LineRun r{0, x, o.y, {}};
    for (int32_t y = o.y; y <= yEnd; ++y)
      r.values.push_back(window[size_t(y - o.y) * stride + (x - o.x)]);
    runs.push_back(std::move(r));
  }
  return runs;
}

void recordLines(SparseHeights& heights, const std::vector<LineRun>& runs) {
  for (const LineRun& r : runs) {
    const int32_t n = int32_t(r.values.size());
    if (r.row)
      heights.recordLines(r.start, r.fixed, n, 1, r.values.data());
    else
      heights.recordLines(r.fixed, r.start, 1, n, r.values.data());
  }
}

std::vector<uint8_t> packPass1Halo(const Pass1Halo& h) {
  Packer p;
  p.put(h.minHeight);
  p.put(h.maxHeight);
  p.put(uint8_t(h.sawVoid));
  p.put(h.scanned);
  p.put(h.bounded);
  p.put(uint8_t(h.square.computed));
  for (const TriangleErrorBounds& e : h.square.errors) {
    p.put(e.above);
    p.put(e.below);
  }
  p.putBytes(h.halo);
  p.put(uint64_t(h.lines.size()));
  for (const LineRun& r : h.lines) {
    p.put(r.row);
    p.put(r.fixed);
    p.put(r.start);
    p.putArray(r.values);
  }
  return std::move(p.bytes());
}

Result<Pass1Halo> unpackPass1Halo(std::span<const uint8_t> record, const std::string& path) {
  Unpacker u(record);
  Pass1Halo h;
  h.minHeight = u.get<double>();
  h.maxHeight = u.get<double>();
  h.sawVoid = u.get<uint8_t>() != 0;
  h.scanned = u.get<uint64_t>();
  h.bounded = u.get<uint64_t>();
  h.square.computed = u.get<uint8_t>() != 0;
  for (TriangleErrorBounds& e : h.square.errors) {
    e.above = u.get<float>();
    e.below = u.get<float>();
  }
  h.halo = u.getBytes();
  const uint64_t runs = u.get<uint64_t>();
  for (uint64_t i = 0; u.ok() && i < runs; ++i) {
    LineRun r;
    r.row = u.get<uint8_t>();
    r.fixed = u.get<int32_t>();
    r.start = u.get<int32_t>();
    r.values = u.getArray<float>();
    h.lines.push_back(std::move(r));
  }
  if (!u.ok() || !u.atEnd()) return makeError(path, "damaged (records do not add up)");
  return h;
}

// A built chunk's node, record (with the statistics its stage filled in) and mesh blob; its
// texture blob follows.
void packChunkMesh(Packer& p, const BuiltChunk& c, const std::vector<NodeRecord>& nodes) {
  p.put(c.node);
  uint8_t record[kNodeRecordBytes];
  serializeNode(nodes[c.node], record);
  p.putBytes(record);
  p.putBytes(c.blob);
}

// Built chunks with their node records: a piece of a chunk file (kChunks).
std::vector<uint8_t> packChunks(const std::vector<BuiltChunk>& chunks,
                                const std::vector<NodeRecord>& nodes) {
  Packer p;
  size_t bytes = 0;
  for (const BuiltChunk& c : chunks)
    bytes += 4 + 3 * 8 + kNodeRecordBytes + c.blob.size() + c.texture.size();
  p.reserve(bytes);
  for (const BuiltChunk& c : chunks) {
    packChunkMesh(p, c, nodes);
    p.putBytes(c.texture);
  }
  return std::move(p.bytes());
}

// A block's kept heights (KeptHeights::blockBits and blockValues), for its pass-2 job: a zstd
// frame (a job holds its blocks' until it ends).
std::vector<uint8_t> packKept(const KeptHeights& kept, GridPoint origin) {
  Packer p;
  const std::span<const uint64_t> bits = kept.blockBits(origin);
  const std::span<const float> values = kept.blockValues(origin);
  p.putArray(std::vector<uint64_t>(bits.begin(), bits.end()));
  p.putArray(std::vector<float>(values.begin(), values.end()));
  return compressedRecord(p.bytes());
}

Status restoreKept(KeptHeights& kept, GridPoint origin, int32_t block,
                   std::span<const uint8_t> record, const std::string& path) {
  const size_t points = size_t(block + 1) * size_t(block + 1);
  auto raw = decompressRecord(record, 16 + (points + 63) / 64 * 8 + points * 4, path);
  if (!raw) return raw.error();
  Unpacker u(*raw);
  std::vector<uint64_t> bits = u.getArray<uint64_t>();
  std::vector<float> values = u.getArray<float>();
  if (!u.ok() || !u.atEnd() || !kept.restoreBlock(origin, std::move(bits), std::move(values)))
    return makeError(path, "was written for another block layout");
  return {};
}

// Reads built chunks back, copying their statistics into `nodes`, and appends them (a piece
// at a time: the file's checksum is checked at its end, before the tileset can be finished),
// each with the texture `textures` has for it, else its own.
Status appendChunksFrom(const std::string& path, std::vector<NodeRecord>& nodes,
                        TilesetWriter& writer, TextureSource& textures) {
  auto in = StageFileReader::open(path, StageFile::kChunks);
  if (!in) return in.error();
  auto damaged = [&] { return makeError(path, "damaged (records do not add up)"); };
  while (!in->atEnd()) {
    const auto node = in->get<uint32_t>();
    const auto record = in->getView();
    if (!node || !record || *node >= nodes.size() || record->size() != kNodeRecordBytes)
      return damaged();
    const NodeRecord built = parseNode(record->data(), 2);
    NodeRecord& n = nodes[*node];
    n.minZ = built.minZ;
    n.maxZ = built.maxZ;
    n.vertexCount = built.vertexCount;
    n.triangleCount = built.triangleCount;
    n.skirtTriangleCount = built.skirtTriangleCount;
    n.maxSkirtDepth = built.maxSkirtDepth;
    n.blobBytes = built.blobBytes;
    n.blobCrc = built.blobCrc;
    const auto blob = in->getView();
    if (!blob || blob->size() != n.blobBytes) return damaged();
    auto offset = writer.appendBlob(*blob);
    if (!offset) return offset.error();
    n.blobOffset = *offset;
    auto texture = in->getView();
    if (!texture) return damaged();
    auto made = textures.take(*node);
    if (!made) return made.error();
    if (*made) texture = **made;
    if (!texture->empty()) {
      if (auto at = writer.appendBlob(*texture); !at) return at.error();
      n.flags |= kNodeHasTexture;
      n.textureBytes = uint32_t(texture->size());
    }
  }
  return in->finish();
}

// A pass-2 job's frontier: the tiles of the nodes whose parent it could not build.
std::vector<uint8_t> packFrontier(const std::vector<std::pair<uint32_t, ChunkTiles>>& frontier) {
  Packer p;
  size_t bytes = 8;
  for (const auto& [node, tiles] : frontier)
    for (const LayerLevels* l : {&tiles.color, &tiles.normal}) {
      bytes += 4 + 16;
      for (const TexelTile& t : l->levels) bytes += 16 + t.values.size() * sizeof(float);
      for (const auto& b : l->blocks) bytes += 8 + b.size();
    }
  p.reserve(bytes);
  p.put(uint64_t(frontier.size()));
  for (const auto& [node, tiles] : frontier) {
    p.put(node);
    packLayer(p, tiles.color);
    packLayer(p, tiles.normal);
  }
  return std::move(p.bytes());
}

// Reads a job's frontier back a tile at a time (not the whole file beside its copy: the
// coarse job's peak); `expected` lists its nodes.
Result<std::vector<std::pair<uint32_t, ChunkTiles>>> readFrontier(
    const std::string& path, const std::vector<uint32_t>& expected) {
  auto reader = StageFileReader::open(path, StageFile::kJobTiles);
  if (!reader) return reader.error();
  StageFileReader& r = *reader;
  const auto damaged = [&] { return makeError(path, "damaged (records do not add up)"); };
  std::vector<std::pair<uint32_t, ChunkTiles>> out;
  const auto count = r.get<uint64_t>();
  if (!count) return damaged();
  if (*count != expected.size()) return makeError(path, "was written for another block layout");
  for (uint64_t i = 0; i < *count; ++i) {
    const auto node = r.get<uint32_t>();
    if (!node) return damaged();
    if (*node != expected[i]) return makeError(path, "was written for another block layout");
    ChunkTiles tiles;
    if (!readLayer(r, tiles.color) || !readLayer(r, tiles.normal)) return damaged();
    out.emplace_back(*node, std::move(tiles));
  }
  if (Status s = r.finish(); !s) return s.error();
  return out;
}

std::vector<uint8_t> packBlockCoarse(const BlockCoarse& c) {
  Packer p;
  p.putKeyed(c.heights);
  p.putKeyed(c.activations);
  return std::move(p.bytes());
}

Result<BlockCoarse> unpackBlockCoarse(std::span<const uint8_t> record, const std::string& path) {
  Unpacker u(record);
  BlockCoarse c;
  c.heights = u.getKeyed<float>();
  c.activations = u.getKeyed<uint8_t>();
  if (!u.ok() || !u.atEnd()) return makeError(path, "damaged (records do not add up)");
  return c;
}

Result<ReduceSummary> readReduceSummary(const std::string& work) {
  auto bytes = readStageFile(coarsePoints(work), StageFile::kCoarsePoints);
  if (!bytes) return bytes.error();
  Unpacker u(bytes->bytes());
  ReduceSummary r;
  r.zMin = u.get<double>();
  r.zMax = u.get<double>();
  r.activations = u.getKeyed<uint8_t>();
  if (!u.ok() || !u.atEnd())
    return makeError(coarsePoints(work), "damaged (records do not add up)");
  return r;
}

}  // namespace terralod::stages
