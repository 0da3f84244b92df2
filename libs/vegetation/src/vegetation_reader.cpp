// Opens a .tlv file with three range reads (header, settings and tiles, directory), each
// checked before the next is trusted; LDIs are read one range each, on demand.

#include <algorithm>
#include <cassert>

#include "terralod/format/http_source.h"
#include "terralod/format/tileset_format.h"  // crc32Of
#include "terralod/vegetation/vegetation_file.h"

namespace terralod::veg {

Result<std::unique_ptr<VegetationReader>> VegetationReader::openPathOrUrl(
    const std::string& pathOrUrl) {
  auto source = openByteSource(pathOrUrl);
  if (!source) return source.error();
  return open(std::move(source).value());
}

Result<std::unique_ptr<VegetationReader>> VegetationReader::open(
    std::unique_ptr<ByteSource> source) {
  const std::string& name = source->name();
  const uint64_t fileSize = source->size();
  auto headerBytes = source->read(0, std::min(fileSize, tlv::kHeaderBytes));
  if (!headerBytes) return headerBytes.error();
  auto header = tlv::parseFileHeader(*headerBytes, fileSize, name);
  if (!header) return header.error();

  auto settings = source->read(header->settingsOffset, header->settingsBytes);
  if (!settings) return settings.error();
  if (crc32Of(*settings) != header->settingsCrc)
    return makeError(name, "vegetation settings are corrupt (checksum mismatch)");
  auto parsed = tlv::parseSettings(*settings, name);
  if (!parsed) return parsed.error();

  auto directory = source->read(header->directoryOffset, header->directoryBytes);
  if (!directory) return directory.error();
  if (crc32Of(*directory) != header->directoryCrc)
    return makeError(name, "LDI directory is corrupt (checksum mismatch)");
  auto entries = tlv::parseDirectory(*directory, *header, name);
  if (!entries) return entries.error();

  std::unique_ptr<VegetationReader> reader(new VegetationReader());
  reader->mHeader = std::move(parsed).value();
  reader->mEntries = std::move(entries).value();
  reader->mSource = std::move(source);
  return reader;
}

const LdiEntry& VegetationReader::entry(int tile, int resolution, int direction) const {
  assert(tile >= 0 && tile < kPrototiles && resolution >= 0 && resolution < kLdiResolutions &&
         direction >= 0 && direction < kLdiDirections);
  return mEntries[ldiIndex(tile, resolution, direction)];
}

Result<Ldi> VegetationReader::readLdi(int tile, int resolution, int direction) const {
  if (tile < 0 || tile >= kPrototiles || resolution < 0 || resolution >= kLdiResolutions ||
      direction < 0 || direction >= kLdiDirections)
    return makeError(name(), "no LDI (tile " + std::to_string(tile) + ", resolution " +
                                 std::to_string(resolution) + ", direction " +
                                 std::to_string(direction) + ")");
  const int index = ldiIndex(tile, resolution, direction);
  const std::string subject = name() + " " + tlv::describeLdi(index);
  const LdiEntry& e = mEntries[index];
  auto bytes = mSource->read(e.offset, e.bytes);
  if (!bytes) return bytes.error();
  if (crc32Of(*bytes) != e.crc) return makeError(subject, "corrupt (checksum mismatch)");
  auto ldi = decodeLdi(bytes->data(), bytes->size());
  if (!ldi) return makeError(subject, ldi.error().message);
  uint32_t maxLayers = 0;
  for (uint8_t count : ldi->layerCounts) maxLayers = std::max<uint32_t>(maxLayers, count);
  if (ldi->camera.width != e.width || ldi->camera.height != e.height ||
      ldi->pixels.size() != e.depthPixels || maxLayers != e.maxLayers)
    return makeError(subject, "does not match its directory entry (" + std::to_string(e.width) +
                                  " x " + std::to_string(e.height) + " pixels, " +
                                  std::to_string(e.depthPixels) + " depth pixels, " +
                                  std::to_string(e.maxLayers) + " layers)");
  return ldi;
}

}  // namespace terralod::veg
