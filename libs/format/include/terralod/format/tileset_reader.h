#pragma once
// Opening a tileset: header, node table and metadata are read and validated up front (three reads);
// chunk blobs are read on demand, one read each, and checked against their CRC before decoding.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "terralod/format/byte_source.h"
#include "terralod/format/chunk_codec.h"
#include "terralod/format/node_bytes.h"
#include "terralod/format/static_chunk.h"
#include "terralod/format/tileset_format.h"
#include "terralod/format/tileset_metadata.h"

namespace terralod {

class TilesetReader {
 public:
  /// Reads and validates header, node table and metadata. Never trusts the file.
  static Result<std::unique_ptr<TilesetReader>> open(std::unique_ptr<ByteSource> source);
  /// Convenience: a local file.
  static Result<std::unique_ptr<TilesetReader>> openFile(const std::string& path);
  /// A local path or an http(s):// URL (openByteSource), as every command takes them.
  static Result<std::unique_ptr<TilesetReader>> openPathOrUrl(const std::string& pathOrUrl);

  const TilesetHeader& header() const { return mHeader; }
  const std::vector<NodeRecord>& nodes() const { return mNodes; }
  const std::string& metadataJson() const { return mMetadata; }
  /// The metadata's typed fields, validated when the tileset was opened.
  const TilesetMetadata& metadata() const { return mTypedMetadata; }
  const std::string& name() const { return mSource->name(); }
  const ByteSource& source() const { return *mSource; }

  /// The stored bytes of a chunk, CRC-checked. Thread-safe.
  Result<std::vector<uint8_t>> readBlob(uint32_t node) const;
  /// A node's mesh and texture blobs with one read, the mesh blob's CRC checked; of any mesh
  /// kind (the kind decodes them). Thread-safe.
  Result<NodeBytes> readNode(uint32_t node) const;
  /// Reads and decodes a static chunk's geometry. Thread-safe.
  Result<ChunkGeometry> readChunk(uint32_t node) const;
  /// A static chunk's geometry and texture: readNode, then decodeStaticChunk. Fails for
  /// chunks of another mesh kind. Thread-safe.
  Result<ChunkData> readChunkData(uint32_t node) const;

 private:
  TilesetReader() = default;
  Status checkStatic(uint32_t node) const;
  std::unique_ptr<ByteSource> mSource;
  TilesetHeader mHeader;
  std::vector<NodeRecord> mNodes;
  std::string mMetadata;
  TilesetMetadata mTypedMetadata;
};

}  // namespace terralod
