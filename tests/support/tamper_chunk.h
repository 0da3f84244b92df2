#pragma once
// Rewrites a tileset with one chunk's geometry changed (its texture, if any, kept), for tests
// that show verify or a reader catches a damaged chunk.

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "terralod/format/chunk_codec.h"
#include "terralod/format/tileset_format.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/format/tileset_writer.h"

namespace terralod::test {

inline void tamperChunk(const std::string& in, const std::string& out, uint32_t node,
                        const std::function<void(ChunkGeometry&)>& change) {
  auto reader = TilesetReader::openFile(in).value();
  auto writer = TilesetWriter::create(out).value();
  std::vector<NodeRecord> nodes = reader->nodes();
  for (uint32_t i = 0; i < nodes.size(); ++i) {
    std::vector<uint8_t> blob = reader->readBlob(i).value();
    if (i == node) {
      ChunkGeometry g = reader->readChunk(i).value();
      change(g);
      blob = encodeChunk(g);
    }
    const NodeRecord& old = reader->nodes()[i];
    nodes[i].blobOffset = writer->appendBlob(blob).value();
    nodes[i].blobBytes = uint32_t(blob.size());
    nodes[i].blobCrc = crc32Of(blob);
    if (old.hasTexture()) {
      const auto texture = reader->source().read(old.blobOffset + old.blobBytes, old.textureBytes);
      ASSERT_TRUE(writer->appendBlob(texture.value()).ok());
    }
  }
  ASSERT_TRUE(writer->finish(reader->header(), nodes, reader->metadataJson()).ok());
}

}  // namespace terralod::test
