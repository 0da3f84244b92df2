// Fuzzes opening a tileset from untrusted bytes: TilesetReader on an in-memory ByteSource
// (header, node table, metadata), the runtime's ChunkTree over what it accepted, then every
// chunk's geometry and texture (VIPM chunks: their blobs and normal maps). Input: one mode
// byte, then the file.
//
// Random bytes almost never carry matching CRC-32s, which would stop every mutation at the
// first checksum. So unless mode bit 0 is set, the harness first recomputes the checksums the
// file's own fields point at (blobs, textures, node table, metadata, header), as a writer
// would; with bit 0 set the file is read exactly as given, to exercise the mismatch paths.
// Version 4 compresses the node table: there the harness fixes the table's own checksum but
// not the blobs' (inside the compressed records); chunk_codec_fuzzer covers their payloads.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "terralod/format/byte_source.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/format/vipm_chunk_codec.h"
#include "terralod/runtime/chunk_tree.h"

namespace {

using terralod::crc32Of;

template <typename T>
T load(const std::vector<uint8_t>& b, uint64_t at) {
  T v{};
  std::memcpy(&v, b.data() + at, sizeof v);
  return v;
}
void storeCrc(std::vector<uint8_t>& b, uint64_t at, uint64_t from, uint64_t length) {
  const uint32_t crc = crc32Of(std::span(b).subspan(from, length));
  std::memcpy(b.data() + at, &crc, sizeof crc);
}
bool inside(const std::vector<uint8_t>& b, uint64_t offset, uint64_t length) {
  return offset <= b.size() && length <= b.size() - offset;
}

// Offsets in the header and in a node record (docs/format.md).
constexpr uint64_t kVersion = 8, kNodeCount = 0xF8, kNodeTableOffset = 0x100,
                   kNodeTableBytes = 0x108, kMetadataOffset = 0x110, kMetadataBytes = 0x118,
                   kNodeTableCrc = 0x130, kMetadataCrc = 0x134, kHeaderCrc = 508;
constexpr uint64_t kBlobOffset = 40, kBlobBytes = 48, kBlobCrc = 52, kTextureBytes = 60;

void fixChecksums(std::vector<uint8_t>& b) {
  if (b.size() < terralod::kHeaderBytes) return;
  const uint64_t nodeCount = load<uint64_t>(b, kNodeCount);
  const uint64_t table = load<uint64_t>(b, kNodeTableOffset);
  const uint64_t tableBytes = load<uint64_t>(b, kNodeTableBytes);
  if (load<uint32_t>(b, kVersion) >= 4) {
    if (inside(b, table, tableBytes)) storeCrc(b, kNodeTableCrc, table, tableBytes);
  } else if (nodeCount < (uint64_t{1} << 32) && inside(b, table, nodeCount * 64)) {
    for (uint64_t i = 0; i < nodeCount; ++i) {
      const uint64_t node = table + i * 64;
      const uint64_t blob = load<uint64_t>(b, node + kBlobOffset);
      const uint32_t blobBytes = load<uint32_t>(b, node + kBlobBytes);
      const uint32_t textureBytes = load<uint32_t>(b, node + kTextureBytes);
      const uint64_t texture = blob + blobBytes;
      if (inside(b, blob, blobBytes) && textureBytes >= 12 && inside(b, texture, textureBytes))
        storeCrc(b, texture + 8, texture + 12, textureBytes - 12);
      if (inside(b, blob, blobBytes)) storeCrc(b, node + kBlobCrc, blob, blobBytes);
    }
    storeCrc(b, kNodeTableCrc, table, nodeCount * 64);
  }
  const uint64_t metadata = load<uint64_t>(b, kMetadataOffset);
  const uint64_t metadataBytes = load<uint64_t>(b, kMetadataBytes);
  if (inside(b, metadata, metadataBytes)) storeCrc(b, kMetadataCrc, metadata, metadataBytes);
  storeCrc(b, kHeaderCrc, 0, kHeaderCrc);
}

// What an opened reader promises (docs/format.md, "What a reader validates"), checked here
// in exact arithmetic: every table and every chunk's bytes lie inside the file.
void checkPromises(const terralod::TilesetReader& reader) {
  using Wide = unsigned __int128;
  const terralod::TilesetHeader& h = reader.header();
  if (h.fileBytes != reader.source().size()) __builtin_trap();
  if (Wide(h.nodeTableOffset) + h.nodeTableBytes > h.fileBytes) __builtin_trap();
  if (Wide(h.metadataOffset) + h.metadataBytes > h.fileBytes) __builtin_trap();
  for (const terralod::NodeRecord& n : reader.nodes())
    if (n.blobOffset < terralod::kHeaderBytes ||
        Wide(n.blobOffset) + n.blobBytes + n.textureBytes > h.fileBytes)
      __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const bool keepChecksums = (data[0] & 1) != 0;
  std::vector<uint8_t> file(data + 1, data + size);
  if (!keepChecksums) fixChecksums(file);
  auto reader = terralod::TilesetReader::open(terralod::makeMemorySource(file, "fuzz.tlod"));
  if (!reader) return 0;
  const terralod::TilesetReader& r = **reader;
  checkPromises(r);
  const terralod::ChunkTree tree(r.header(), r.nodes());
  (void)tree;
  // Chunks are what a renderer reads next; a few hundred keep one input fast.
  const uint32_t chunks = uint32_t(std::min<size_t>(r.nodes().size(), 256));
  for (uint32_t i = 0; i < chunks; ++i) {
    if (r.nodes()[i].meshKind != terralod::MeshKind::kVipm) {
      (void)r.readChunkData(i);
    } else if (auto node = r.readNode(i)) {
      (void)terralod::decodeVipmChunk(node->mesh(), "fuzz chunk");
      (void)terralod::decodeVipmNormalMap(
          node->texture(), uint32_t(r.header().chunkCells(r.nodes()[i].level)), "fuzz chunk");
    }
  }
  (void)r.readChunk(chunks);  // geometry alone, of a node that may not exist
  return 0;
}
