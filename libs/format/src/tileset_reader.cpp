#include "terralod/format/tileset_reader.h"

#include "terralod/format/http_source.h"

namespace terralod {

Result<std::unique_ptr<TilesetReader>> TilesetReader::openFile(const std::string& path) {
  auto source = openFileSource(path);
  if (!source) return source.error();
  return open(std::move(source).value());
}

Result<std::unique_ptr<TilesetReader>> TilesetReader::openPathOrUrl(const std::string& pathOrUrl) {
  auto source = openByteSource(pathOrUrl);
  if (!source) return source.error();
  return open(std::move(source).value());
}

Result<std::unique_ptr<TilesetReader>> TilesetReader::open(std::unique_ptr<ByteSource> source) {
  std::unique_ptr<TilesetReader> t(new TilesetReader());
  const std::string& name = source->name();
  const uint64_t fileSize = source->size();
  if (fileSize < kHeaderBytes)
    return makeError(name, "file is too short to be a terralod tileset (" +
                               std::to_string(fileSize) + " bytes)");
  auto headerBytes = source->read(0, kHeaderBytes);
  if (!headerBytes) return headerBytes.error();
  auto header = parseHeader(*headerBytes, name);
  if (!header) return header.error();
  if (header->fileBytes != fileSize)
    return makeError(name, "tileset is truncated or padded: header says " +
                               std::to_string(header->fileBytes) + " bytes, file has " +
                               std::to_string(fileSize));
  t->mHeader = *header;

  auto table = source->read(t->mHeader.nodeTableOffset, t->mHeader.nodeTableBytes);
  if (!table) return table.error();
  if (crc32Of(*table) != t->mHeader.nodeTableCrc)
    return makeError(name, "node table is corrupt (checksum mismatch)");
  auto nodes = decodeNodeTable(*table, t->mHeader, name);
  if (!nodes) return nodes.error();
  t->mNodes = std::move(nodes).value();
  if (Status s = validateNodes(t->mHeader, t->mNodes, name); !s) return s.error();

  auto metadata = source->read(t->mHeader.metadataOffset, t->mHeader.metadataBytes);
  if (!metadata) return metadata.error();
  if (crc32Of(*metadata) != t->mHeader.metadataCrc)
    return makeError(name, "metadata is corrupt (checksum mismatch)");
  t->mMetadata.assign(metadata->begin(), metadata->end());
  auto typed = parseTilesetMetadata(t->mMetadata, t->mHeader, name);
  if (!typed) return typed.error();
  t->mTypedMetadata = std::move(typed).value();
  t->mSource = std::move(source);
  return t;
}

Result<std::vector<uint8_t>> TilesetReader::readBlob(uint32_t node) const {
  if (node >= mNodes.size()) return makeError(name(), "no chunk " + std::to_string(node));
  const NodeRecord& n = mNodes[node];
  auto bytes = mSource->read(n.blobOffset, n.blobBytes);
  if (!bytes) return bytes.error();
  if (crc32Of(*bytes) != n.blobCrc)
    return makeError(name(), "chunk " + std::to_string(node) + " is corrupt (checksum mismatch)");
  return bytes;
}

Status TilesetReader::checkStatic(uint32_t node) const {
  if (node < mNodes.size() && mNodes[node].meshKind != MeshKind::kStaticRtin)
    return makeError(name(), "chunk " + std::to_string(node) + " has mesh kind " +
                                 std::to_string(unsigned(mNodes[node].meshKind)) +
                                 ", not static RTIN");
  return {};
}

Result<ChunkGeometry> TilesetReader::readChunk(uint32_t node) const {
  if (Status s = checkStatic(node); !s) return s.error();
  auto bytes = readBlob(node);
  if (!bytes) return bytes.error();
  return decodeChunk(*bytes, name() + " chunk " + std::to_string(node));
}

Result<NodeBytes> TilesetReader::readNode(uint32_t node) const {
  if (node >= mNodes.size()) return makeError(name(), "no chunk " + std::to_string(node));
  const NodeRecord& n = mNodes[node];
  auto bytes = mSource->read(n.blobOffset, uint64_t(n.blobBytes) + n.textureBytes);
  if (!bytes) return bytes.error();
  NodeBytes read{std::move(bytes).value(), n.blobBytes};
  if (crc32Of(read.mesh()) != n.blobCrc)
    return makeError(name(), "chunk " + std::to_string(node) + " is corrupt (checksum mismatch)");
  return read;
}

Result<ChunkData> TilesetReader::readChunkData(uint32_t node) const {
  if (Status s = checkStatic(node); !s) return s.error();
  auto bytes = readNode(node);
  if (!bytes) return bytes.error();
  return decodeStaticChunk(*bytes, name() + " chunk " + std::to_string(node));
}

}  // namespace terralod
