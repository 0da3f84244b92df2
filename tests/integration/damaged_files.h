#pragma once
// Broken inputs for the bad-input matrix, made on the spot: tilesets edited behind valid
// checksums (so the damage reaches the checks behind them), PNG headers that promise more
// than they hold, and GeoTIFFs of one repeated value.

#include <gdal_priv.h>

#include <cstdint>
#include <fstream>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "terralod/format/tileset_format.h"

namespace terralod::test {

/// Writes `to`: the tileset `from` with its header and node records changed by `edit`, the
/// node table written back where it was and every checksum the edit touched made valid again.
inline void writeEditedTileset(
    const std::string& from, const std::string& to,
    const std::function<void(TilesetHeader&, std::vector<NodeRecord>&)>& edit) {
  std::string bytes = readWholeFile(from);
  auto* data = reinterpret_cast<uint8_t*>(bytes.data());
  TilesetHeader header = parseHeader(std::span(data, bytes.size()), from).value();
  const uint64_t tableAt = header.nodeTableOffset;
  std::vector<NodeRecord> nodes(header.nodeCount);
  for (size_t i = 0; i < nodes.size(); ++i)
    nodes[i] = parseNode(data + tableAt + i * kNodeRecordBytes, header.version);
  edit(header, nodes);
  for (size_t i = 0; i < nodes.size(); ++i)
    serializeNode(nodes[i], data + tableAt + i * kNodeRecordBytes);
  header.nodeTableCrc = crc32Of(std::span(data + tableAt, nodes.size() * kNodeRecordBytes));
  const std::vector<uint8_t> head = serializeHeader(header);
  std::copy(head.begin(), head.end(), data);
  std::ofstream(to, std::ios::binary) << bytes;
}

/// A PNG whose header says `width` x `height` (RGB or 16-bit grey) and whose data holds one
/// row of them.
inline void writePngPromising(const std::string& path, uint32_t width, uint32_t height, bool rgb) {
  auto big = [](std::string& s, uint32_t v) {
    for (int i = 3; i >= 0; --i) s.push_back(char(v >> (8 * i)));
  };
  std::string png = "\x89PNG\r\n\x1a\n";
  auto chunk = [&](const std::string& type, const std::string& body) {
    big(png, uint32_t(body.size()));
    const std::string typed = type + body;
    png += typed;
    big(png, crc32Of(std::span(reinterpret_cast<const uint8_t*>(typed.data()), typed.size())));
  };
  std::string header;
  big(header, width);
  big(header, height);
  header += rgb ? std::string("\x08\x02\x00\x00\x00", 5) : std::string("\x10\x00\x00\x00\x00", 5);
  chunk("IHDR", header);
  // One row of filter type 0 and zero samples, deflated as stored blocks of zlib.
  const std::string rows(1 + size_t(width) * (rgb ? 3 : 2), '\0');
  std::string zlib = "\x78\x01";
  for (size_t at = 0; at < rows.size(); at += 65535) {
    const size_t n = std::min<size_t>(65535, rows.size() - at);
    zlib.push_back(at + n == rows.size() ? 1 : 0);
    zlib.push_back(char(n & 0xFF));
    zlib.push_back(char(n >> 8));
    zlib.push_back(char(~n & 0xFF));
    zlib.push_back(char((~n >> 8) & 0xFF));
    zlib += rows.substr(at, n);
  }
  zlib += std::string(4, '\0');  // Adler-32 left wrong: the data ends before it matters
  chunk("IDAT", zlib);
  chunk("IEND", "");
  std::ofstream(path, std::ios::binary) << png;
}

/// A GeoTIFF (no georeferencing) of `columns` x `rows` samples all equal to `value`; sparse
/// (only a header) when `value` is 0.
inline void writeConstantTiff(const std::string& path, int columns, int rows, GDALDataType type,
                              double value) {
  GDALAllRegister();
  const char* sparse[] = {"SPARSE_OK=TRUE", nullptr};
  GDALDatasetUniquePtr ds(GetGDALDriverManager()->GetDriverByName("GTiff")->Create(
      path.c_str(), columns, rows, 1, type, const_cast<char**>(sparse)));
  if (value != 0) (void)ds->GetRasterBand(1)->Fill(value);
}

}  // namespace terralod::test
