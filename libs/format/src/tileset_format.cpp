#include "terralod/format/tileset_format.h"

#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstring>

#include "terralod/format/byte_io.h"

namespace terralod {

uint32_t crc32Continue(uint32_t previous, std::span<const uint8_t> bytes) {
  uLong crc = previous;
  // zlib takes uInt lengths; feed large ranges in pieces.
  size_t done = 0;
  while (done < bytes.size()) {
    const size_t n = std::min<size_t>(bytes.size() - done, 1u << 30);
    crc = crc32(crc, bytes.data() + done, static_cast<uInt>(n));
    done += n;
  }
  return static_cast<uint32_t>(crc);
}

uint32_t crc32Of(std::span<const uint8_t> bytes) {
  return crc32Continue(uint32_t(crc32(0L, Z_NULL, 0)), bytes);
}

std::vector<uint8_t> serializeHeader(const TilesetHeader& h) {
  std::vector<uint8_t> out(kHeaderBytes, 0);
  ByteWriter w(out.data());
  w.putBytes(kTilesetMagic, 8);
  w.put<uint32_t>(h.version);
  w.put<uint32_t>(kHeaderBytes);
  w.put<uint32_t>(kNodeRecordBytes);
  w.put<uint32_t>(h.flags);
  w.put<uint32_t>(static_cast<uint32_t>(h.meshKind));
  w.put<uint32_t>(h.levelCount);
  w.put<uint32_t>(h.leafCells);
  w.put<uint32_t>(h.rootCells);
  w.put<uint32_t>(h.rootsX);
  w.put<uint32_t>(h.rootsY);
  w.put<uint32_t>(h.sourceColumns);
  w.put<uint32_t>(h.sourceRows);
  w.put<double>(h.spacingX);
  w.put<double>(h.spacingY);
  for (double e : h.levelError) w.put<double>(e);
  for (double v : h.extentMin) w.put<double>(v);
  for (double v : h.extentMax) w.put<double>(v);
  w.put<uint64_t>(h.nodeCount);
  w.put<uint64_t>(h.nodeTableOffset);
  w.put<uint64_t>(h.nodeTableBytes);
  w.put<uint64_t>(h.metadataOffset);
  w.put<uint64_t>(h.metadataBytes);
  w.put<uint64_t>(h.fileBytes);
  w.put<uint64_t>(h.filledVoids);
  w.put<uint32_t>(h.nodeTableCrc);
  w.put<uint32_t>(h.metadataCrc);
  w.put<double>(h.leafError);
  w.put<double>(h.verticalScale);
  if (h.version >= 2) w.put<double>(h.textureMinTau);
  // Bytes up to 508 are reserved (zero); the last four hold the CRC of everything before.
  w.seek(kHeaderBytes - 4);
  w.put<uint32_t>(crc32Of(std::span(out.data(), kHeaderBytes - 4)));
  return out;
}

Result<TilesetHeader> parseHeader(std::span<const uint8_t> bytes, const std::string& subject) {
  if (bytes.size() < kHeaderBytes)
    return makeError(subject, "file is too short to be a terralod tileset (" +
                                  std::to_string(bytes.size()) + " bytes)");
  if (std::memcmp(bytes.data(), kTilesetMagic, 8) != 0)
    return makeError(subject, "not a terralod tileset (wrong magic bytes)");
  ByteReader r(bytes.data());
  r.seek(8);
  TilesetHeader h;
  h.version = r.get<uint32_t>();
  if (h.version < 1 || h.version > kTilesetVersion)
    return makeError(subject, "tileset format version " + std::to_string(h.version) +
                                  " is not supported (this terralod reads versions 1 to " +
                                  std::to_string(kTilesetVersion) + ")");
  const uint32_t headerBytes = r.get<uint32_t>();
  const uint32_t nodeBytes = r.get<uint32_t>();
  if (headerBytes != kHeaderBytes || nodeBytes != kNodeRecordBytes)
    return makeError(subject, "tileset header has inconsistent record sizes");
  ByteReader crcReader(bytes.data());
  crcReader.seek(kHeaderBytes - 4);
  if (crcReader.get<uint32_t>() != crc32Of(bytes.first(kHeaderBytes - 4)))
    return makeError(subject, "tileset header is corrupt (checksum mismatch)");
  h.flags = r.get<uint32_t>();
  const uint32_t meshKind = r.get<uint32_t>();  // a u32 in the file: checked before narrowing
  h.levelCount = r.get<uint32_t>();
  h.leafCells = r.get<uint32_t>();
  h.rootCells = r.get<uint32_t>();
  h.rootsX = r.get<uint32_t>();
  h.rootsY = r.get<uint32_t>();
  h.sourceColumns = r.get<uint32_t>();
  h.sourceRows = r.get<uint32_t>();
  h.spacingX = r.get<double>();
  h.spacingY = r.get<double>();
  for (double& e : h.levelError) e = r.get<double>();
  for (double& v : h.extentMin) v = r.get<double>();
  for (double& v : h.extentMax) v = r.get<double>();
  h.nodeCount = r.get<uint64_t>();
  h.nodeTableOffset = r.get<uint64_t>();
  h.nodeTableBytes = r.get<uint64_t>();
  h.metadataOffset = r.get<uint64_t>();
  h.metadataBytes = r.get<uint64_t>();
  h.fileBytes = r.get<uint64_t>();
  h.filledVoids = r.get<uint64_t>();
  h.nodeTableCrc = r.get<uint32_t>();
  h.metadataCrc = r.get<uint32_t>();
  h.leafError = r.get<double>();
  h.verticalScale = r.get<double>();
  // Version 1 reserves what later versions use: never look at it.
  if (h.version >= 2) {
    h.textureMinTau = r.get<double>();
  } else {
    h.flags = 0;
  }

  auto bad = [&](const std::string& what) {
    return makeError(subject, "invalid tileset header: " + what);
  };
  // Any kind may be stored; the runtime refuses kinds nobody registered (ChunkKinds).
  if (meshKind == 0 || meshKind > 0xFF)
    return bad("unknown chunk mesh kind " + std::to_string(meshKind));
  h.meshKind = MeshKind(meshKind);
  if ((h.flags & ~kTilesetTextured) != 0) return bad("unknown flags");
  if (h.textured() && !(h.textureMinTau > 0 && std::isfinite(h.textureMinTau)))
    return bad("texture τ");
  // VIPM chunks are lit by stored normal maps only (docs/format.md "VIPM tilesets").
  if (h.meshKind == MeshKind::kVipm && !h.textured())
    return bad("a VIPM tileset (mesh kind 2) has no normal maps; rebuild it");
  if (h.levelCount < 1 || h.levelCount > kMaxLevels) return bad("level count out of range");
  if (h.leafCells < 4 || (h.leafCells & (h.leafCells - 1)) != 0) return bad("leaf size");
  if (h.rootCells != (h.leafCells << (h.levelCount - 1)) || h.rootCells > 32768)
    return bad("root size");
  if (h.rootsX < 1 || h.rootsY < 1 || h.rootsX > 4096 || h.rootsY > 4096) return bad("root grid");
  if (h.sourceColumns < 2 || h.sourceRows < 2 ||
      uint64_t(h.sourceColumns - 1) > uint64_t(h.rootsX) * h.rootCells ||
      uint64_t(h.sourceRows - 1) > uint64_t(h.rootsY) * h.rootCells)
    return bad("source size does not fit the root grid");
  if (!(h.spacingX > 0) || !(h.spacingY > 0) || !std::isfinite(h.spacingX) ||
      !std::isfinite(h.spacingY))
    return bad("spacing");
  for (uint32_t l = 0; l < h.levelCount; ++l)
    if (!(h.levelError[l] > 0) || !std::isfinite(h.levelError[l])) return bad("level error");
  // From version 4 the table is compressed. Every record holds a CRC, 4 bytes no compressor
  // shrinks, so a table of fewer bytes than records is damage: refused before anything is
  // decompressed (which bounds the records to 64 bytes for every stored byte).
  if (h.nodeCount == 0 || h.nodeCount > (uint64_t{1} << 32) - 1 ||
      (h.version < 4 ? h.nodeTableBytes != h.nodeCount * kNodeRecordBytes
                     : h.nodeTableBytes < h.nodeCount))
    return bad("node count");
  // Offsets come from the file: compared so that no sum can wrap around.
  auto insideFile = [&](uint64_t offset, uint64_t length) {
    return offset >= kHeaderBytes && offset <= h.fileBytes && length <= h.fileBytes - offset;
  };
  if (!insideFile(h.nodeTableOffset, h.nodeTableBytes) ||
      !insideFile(h.metadataOffset, h.metadataBytes) || h.metadataBytes > (uint64_t{1} << 26))
    return bad("table offsets");
  if (h.metadataBytes > 0 && h.metadataOffset < h.nodeTableOffset + h.nodeTableBytes &&
      h.nodeTableOffset < h.metadataOffset + h.metadataBytes)
    return bad("table offsets");
  return h;
}

void serializeNode(const NodeRecord& n, uint8_t* out) {
  std::memset(out, 0, kNodeRecordBytes);
  ByteWriter w(out);
  w.put<uint8_t>(n.level);
  w.put<uint8_t>(n.childMask);
  w.put<uint8_t>(static_cast<uint8_t>(n.meshKind));
  w.put<uint8_t>(n.flags);
  w.put<uint32_t>(n.x);
  w.put<uint32_t>(n.y);
  w.put<uint32_t>(n.firstChild);
  w.put<uint32_t>(n.parent);
  w.put<float>(n.minZ);
  w.put<float>(n.maxZ);
  w.put<uint32_t>(n.vertexCount);
  w.put<uint32_t>(n.triangleCount);
  w.put<uint32_t>(n.skirtTriangleCount);
  w.put<uint64_t>(n.blobOffset);
  w.put<uint32_t>(n.blobBytes);
  w.put<uint32_t>(n.blobCrc);
  w.put<float>(n.maxSkirtDepth);
  w.put<uint32_t>(n.textureBytes);
}

NodeRecord parseNode(const uint8_t* in, uint32_t version) {
  ByteReader r(in);
  NodeRecord n;
  n.level = r.get<uint8_t>();
  n.childMask = r.get<uint8_t>();
  n.meshKind = static_cast<MeshKind>(r.get<uint8_t>());
  n.flags = r.get<uint8_t>();
  n.x = r.get<uint32_t>();
  n.y = r.get<uint32_t>();
  n.firstChild = r.get<uint32_t>();
  n.parent = r.get<uint32_t>();
  n.minZ = r.get<float>();
  n.maxZ = r.get<float>();
  n.vertexCount = r.get<uint32_t>();
  n.triangleCount = r.get<uint32_t>();
  n.skirtTriangleCount = r.get<uint32_t>();
  n.blobOffset = r.get<uint64_t>();
  n.blobBytes = r.get<uint32_t>();
  n.blobCrc = r.get<uint32_t>();
  n.maxSkirtDepth = r.get<float>();
  if (version >= 2) {
    n.textureBytes = r.get<uint32_t>();
  } else {
    n.flags = 0;  // reserved in version 1
  }
  return n;
}

std::vector<uint8_t> encodeNodeTable(const std::vector<NodeRecord>& nodes, uint32_t version) {
  std::vector<uint8_t> table(nodes.size() * kNodeRecordBytes);
  for (size_t i = 0; i < nodes.size(); ++i)
    serializeNode(nodes[i], table.data() + i * kNodeRecordBytes);
  if (version < 4) return table;
  std::vector<uint8_t> shuffled(table.size());
  for (size_t i = 0; i < nodes.size(); ++i)
    for (size_t k = 0; k < kNodeRecordBytes; ++k)
      shuffled[k * nodes.size() + i] = table[i * kNodeRecordBytes + k];
  std::vector<uint8_t> stored(ZSTD_compressBound(shuffled.size()));
  const size_t n = ZSTD_compress(stored.data(), stored.size(), shuffled.data(), shuffled.size(),
                                 kNodeTableCompressionLevel);
  assert(!ZSTD_isError(n));
  stored.resize(n);
  return stored;
}

Result<std::vector<NodeRecord>> decodeNodeTable(std::span<const uint8_t> stored,
                                                const TilesetHeader& header,
                                                const std::string& subject) {
  const size_t count = header.nodeCount;
  std::vector<uint8_t> table;
  if (header.version < 4) {
    if (stored.size() != count * kNodeRecordBytes)
      return makeError(subject,
                       "node table is corrupt (not " + std::to_string(count) + " records)");
    table.assign(stored.begin(), stored.end());
  } else {
    const unsigned long long size = ZSTD_getFrameContentSize(stored.data(), stored.size());
    if (size != count * kNodeRecordBytes)
      return makeError(subject, "node table is corrupt (not " + std::to_string(count) +
                                    " records in one zstd frame)");
    std::vector<uint8_t> shuffled(size);
    const size_t got = ZSTD_decompress(shuffled.data(), size, stored.data(), stored.size());
    if (ZSTD_isError(got) || got != size)
      return makeError(subject, "node table is corrupt (does not decompress)");
    table.resize(size);
    for (size_t i = 0; i < count; ++i)
      for (size_t k = 0; k < kNodeRecordBytes; ++k)
        table[i * kNodeRecordBytes + k] = shuffled[k * count + i];
  }
  std::vector<NodeRecord> nodes(count);
  for (size_t i = 0; i < count; ++i)
    nodes[i] = parseNode(table.data() + i * kNodeRecordBytes, header.version);
  return nodes;
}

namespace {

// Every chunk's bytes (geometry and texture) are its own: an offset that points into another
// chunk, the node table or the metadata is damage, found here rather than as a bad decode (or
// worse, a good decode of the wrong chunk). Sorted by start, any overlap shows between
// neighbours. Assumes every range lies inside the file (checked before).
Status checkDisjoint(const TilesetHeader& h, const std::vector<NodeRecord>& nodes,
                     const std::string& subject) {
  constexpr uint64_t kNodeTable = ~uint64_t{0}, kMetadata = kNodeTable - 1;
  struct Range {
    uint64_t begin, end, owner;  // owner: a node index, kNodeTable or kMetadata
  };
  std::vector<Range> ranges;
  ranges.reserve(nodes.size() + 2);
  for (size_t i = 0; i < nodes.size(); ++i) {
    const NodeRecord& n = nodes[i];
    ranges.push_back({n.blobOffset, n.blobOffset + n.blobBytes + n.textureBytes, i});
  }
  ranges.push_back({h.nodeTableOffset, h.nodeTableOffset + h.nodeTableBytes, kNodeTable});
  if (h.metadataBytes > 0)
    ranges.push_back({h.metadataOffset, h.metadataOffset + h.metadataBytes, kMetadata});
  std::sort(ranges.begin(), ranges.end(), [](const Range& a, const Range& b) {
    return a.begin != b.begin ? a.begin < b.begin : a.owner < b.owner;
  });
  auto name = [](uint64_t owner) {
    return owner == kNodeTable  ? std::string("the node table")
           : owner == kMetadata ? std::string("the metadata")
                                : "node " + std::to_string(owner);
  };
  for (size_t k = 1; k < ranges.size(); ++k) {
    const Range& a = ranges[k - 1];
    const Range& b = ranges[k];
    if (b.begin >= a.end) continue;
    // The one that starts inside the other is named first, unless that is a table (the
    // tables never overlap each other: the header's checks).
    const Range& node = b.owner < kMetadata ? b : a;
    const Range& other = b.owner < kMetadata ? a : b;
    return makeError(subject, "corrupt node table: node " + std::to_string(node.owner) +
                                  " overlaps " + name(other.owner));
  }
  return {};
}

}  // namespace

TextureSource textureSourceOf(const std::vector<NodeRecord>& nodes, uint32_t node) {
  TextureSource s;
  uint32_t at = node;
  while (at != kNoNode && nodes[at].inheritsTexture()) {
    at = nodes[at].parent;
    ++s.depth;
  }
  if (at == kNoNode || !nodes[at].hasTexture()) return {};
  s.owner = at;
  s.column = nodes[node].x - (nodes[at].x << s.depth);
  s.row = nodes[node].y - (nodes[at].y << s.depth);
  return s;
}

Status validateNodes(const TilesetHeader& h, const std::vector<NodeRecord>& nodes,
                     const std::string& subject) {
  auto bad = [&](size_t i, const std::string& what) {
    return makeError(subject, "corrupt node table: node " + std::to_string(i) + " " + what);
  };
  const uint64_t rootCount = uint64_t(h.rootsX) * h.rootsY;
  for (size_t i = 0; i < nodes.size(); ++i) {
    const NodeRecord& n = nodes[i];
    if (n.level >= h.levelCount) return bad(i, "has an impossible level");
    if (uint8_t(n.meshKind) == 0) return bad(i, "has an unknown mesh kind");
    const uint64_t perSide = uint64_t(1) << n.level;
    if (n.x >= h.rootsX * perSide || n.y >= h.rootsY * perSide)
      return bad(i, "lies outside the tree");
    if ((n.level == 0) != (i < rootCount)) return bad(i, "is out of breadth-first order");
    if (n.level == 0 ? n.parent != kNoNode
                     : (n.parent >= i || nodes[n.parent].level + 1 != n.level))
      return bad(i, "has a bad parent link");
    if (n.childMask > 15) return bad(i, "has a bad child mask");
    if (n.childMask != 0) {
      const uint32_t count = std::popcount(unsigned(n.childMask));
      if (n.firstChild == kNoNode || n.firstChild <= i ||
          uint64_t(n.firstChild) + count > nodes.size())
        return bad(i, "has children outside the table");
      uint32_t c = n.firstChild;
      for (int q = 0; q < 4; ++q) {
        if (!(n.childMask & (1u << q))) continue;
        const NodeRecord& child = nodes[c];
        if (child.parent != i || child.x != n.x * 2 + (q & 1) || child.y != n.y * 2 + (q >> 1))
          return bad(i, "has a child that does not point back");
        ++c;
      }
    } else if (n.firstChild != kNoNode) {
      return bad(i, "has a child index but no children");
    }
    // Compared so that no sum can wrap around (offsets near 2^64 once passed as small ones).
    if (n.blobBytes == 0 || n.blobOffset < kHeaderBytes || n.blobOffset > h.fileBytes ||
        n.blobBytes > h.fileBytes - n.blobOffset)
      return bad(i, "points outside the file");
    const uint8_t known = h.version >= 5 ? kNodeHasTexture | kNodeInheritsTexture : kNodeHasTexture;
    if ((n.flags & ~known) != 0) return bad(i, "has unknown flags");
    if (n.hasTexture() && n.inheritsTexture()) return bad(i, "both has a texture and inherits one");
    if ((n.hasTexture() || n.inheritsTexture()) != h.textured())
      return bad(i, "disagrees with the header about textures");
    if (n.inheritsTexture() && n.level == 0) return bad(i, "inherits a texture but has no parent");
    const uint64_t blobEnd = n.blobOffset + n.blobBytes;  // <= fileBytes: checked above
    if (n.hasTexture() ? n.textureBytes == 0 || n.textureBytes > h.fileBytes - blobEnd
                       : n.textureBytes != 0)
      return bad(i, "has a texture outside the file");
    if (!(n.minZ <= n.maxZ)) return bad(i, "has an invalid height range");
  }
  return checkDisjoint(h, nodes, subject);
}

}  // namespace terralod
