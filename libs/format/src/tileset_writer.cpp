#include "terralod/format/tileset_writer.h"

namespace terralod {

Result<std::unique_ptr<TilesetWriter>> TilesetWriter::create(const std::string& path) {
  auto file = AtomicFile::create(path);
  if (!file) return file.error();
  auto writer = std::unique_ptr<TilesetWriter>(new TilesetWriter(std::move(file).value()));
  // A zero header marks the file as incomplete until finish().
  const std::vector<uint8_t> zeros(kHeaderBytes, 0);
  if (Status s = writer->mFile.write(zeros); !s) return s.error();
  return writer;
}

Result<uint64_t> TilesetWriter::appendBlob(std::span<const uint8_t> bytes) {
  const uint64_t offset = mFile.bytesWritten();
  if (Status s = mFile.write(bytes); !s) return s.error();
  return offset;
}

Status TilesetWriter::finish(TilesetHeader header, const std::vector<NodeRecord>& nodes,
                             const std::string& metadata) {
  const std::vector<uint8_t> table = encodeNodeTable(nodes, header.version);
  header.nodeCount = nodes.size();
  header.nodeTableOffset = mFile.bytesWritten();
  header.nodeTableBytes = table.size();
  header.nodeTableCrc = crc32Of(table);
  if (Status s = mFile.write(table); !s) return s;
  const auto metadataBytes =
      std::span(reinterpret_cast<const uint8_t*>(metadata.data()), metadata.size());
  header.metadataOffset = mFile.bytesWritten();
  header.metadataBytes = metadata.size();
  header.metadataCrc = crc32Of(metadataBytes);
  if (Status s = mFile.write(metadataBytes); !s) return s;
  header.fileBytes = mFile.bytesWritten();
  if (Status s = mFile.writeAt(0, serializeHeader(header)); !s) return s;
  return mFile.commit();
}

}  // namespace terralod
