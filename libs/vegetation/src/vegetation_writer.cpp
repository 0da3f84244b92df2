// Writes a .tlv file in one pass through AtomicFile: a zero header (so the temporary file
// never opens as a vegetation file), the settings and tiles, the directory, the LDI blobs back
// to back, then the real header at offset 0 and the commit.

#include "terralod/core/atomic_file.h"
#include "terralod/format/tileset_format.h"  // crc32Of
#include "terralod/vegetation/vegetation_file.h"

namespace terralod::veg {

Status writeVegetationFile(const std::string& path, const VegetationHeader& header,
                           const std::vector<EncodedLdi>& ldis) {
  if (ldis.size() != size_t(kLdiCount))
    return makeError(path, "cannot write a vegetation file of " + std::to_string(ldis.size()) +
                               " LDIs (it holds " + std::to_string(kLdiCount) + ")");
  if (header.settings.scene.size() > 16)
    return makeError(path, "cannot write scene name \"" + header.settings.scene +
                               "\": it is longer than 16 characters");
  // The writer refuses what the reader would: the same parsers check the bytes it would write.
  const std::vector<uint8_t> settings = tlv::serializeSettings(header);
  auto settingsRead = tlv::parseSettings(settings, path);
  if (!settingsRead) return settingsRead.error();
  if (!(settingsRead.value() == header))  // a backstop: nothing else is lost in serializing
    return makeError(path, "cannot write the settings: they do not read back as given");

  tlv::FileHeader h;
  h.settingsOffset = tlv::kHeaderBytes;
  h.settingsBytes = settings.size();
  h.settingsCrc = crc32Of(settings);
  h.directoryOffset = h.settingsOffset + h.settingsBytes;
  h.directoryBytes = tlv::kDirectoryBytes;
  h.ldiAreaOffset = h.directoryOffset + h.directoryBytes;
  std::vector<LdiEntry> entries(kLdiCount);
  uint64_t offset = h.ldiAreaOffset;
  for (int i = 0; i < kLdiCount; ++i) {
    const EncodedLdi& ldi = ldis[i];
    entries[i] = {offset,          ldi.blob.size(), ldi.width,        ldi.height,
                  ldi.depthPixels, ldi.maxLayers,   crc32Of(ldi.blob)};
    offset += ldi.blob.size();
  }
  h.ldiAreaBytes = offset - h.ldiAreaOffset;
  h.fileBytes = offset;
  const std::vector<uint8_t> directory = tlv::serializeDirectory(entries);
  h.directoryCrc = crc32Of(directory);
  if (auto entriesRead = tlv::parseDirectory(directory, h, path); !entriesRead)
    return entriesRead.error();
  const std::vector<uint8_t> fileHeader = tlv::serializeFileHeader(h);
  if (auto headerRead = tlv::parseFileHeader(fileHeader, h.fileBytes, path); !headerRead)
    return headerRead.error();

  auto file = AtomicFile::create(path);
  if (!file) return file.error();
  const std::vector<uint8_t> zeros(tlv::kHeaderBytes, 0);
  if (Status s = file->write(zeros); !s) return s;
  if (Status s = file->write(settings); !s) return s;
  if (Status s = file->write(directory); !s) return s;
  for (const EncodedLdi& ldi : ldis)
    if (Status s = file->write(ldi.blob); !s) return s;
  if (Status s = file->writeAt(0, fileHeader); !s) return s;
  return file->commit();
}

}  // namespace terralod::veg
