#pragma once
// The .tlv vegetation file (docs/format.md, "Vegetation files (.tlv)"): how a scene's 8 Wang
// prototiles were baked, what stands in each, and their 448 layered depth images (7
// resolutions × 8 view directions per tile), each a self-contained blob that one range read
// fetches. Written atomically; the reader trusts nothing and reads only what it is asked for.

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/format/byte_source.h"
#include "terralod/vegetation/ldi.h"
#include "terralod/vegetation/tile_objects.h"

namespace terralod::veg {

inline constexpr int kPrototiles = 8, kLdiResolutions = 7, kLdiDirections = 8;
inline constexpr int kLdiCount = kPrototiles * kLdiResolutions * kLdiDirections;  // 448

struct BakeSettings {    // how the LDIs were made (the reader returns them)
  std::string scene;     // "sunflowers" | "meadow"
  uint64_t seed = 0;     // placement and model seed
  float tileSize = 0;    // metres (square tiles)
  float headHeight = 0;  // metres: the viewer height the LDIs were sampled for
  float tileHeight = 0;  // metres: top of the tallest plant (bounding box height)
  std::array<uint32_t, kLdiResolutions> resolutions{};  // LDI pixels across, finest first
  std::array<float, kLdiResolutions> ringDistances{};   // metres from viewer to tile centre
  std::array<float, kLdiResolutions> elevations{};      // radians, ray angle below horizontal
  uint32_t raysPerPixel = 0;
  double bakeSeconds = 0;  // filled by the baker, for `info`
  uint64_t raysCast = 0;
  bool operator==(const BakeSettings&) const = default;
};

struct VegetationHeader {
  BakeSettings settings;
  std::array<PrototileContent, kPrototiles> tiles;        // edges + placed objects
  std::array<uint64_t, kPrototiles> trianglesModelled{};  // geometry of each tile's plants
  bool operator==(const VegetationHeader&) const = default;
};

/// One LDI's record in the directory.
struct LdiEntry {
  uint64_t offset = 0, bytes = 0;  ///< the blob's byte range in the file
  uint32_t width = 0, height = 0;
  uint64_t depthPixels = 0;
  uint32_t maxLayers = 0;
  uint32_t crc = 0;  ///< CRC-32 of the blob
  bool operator==(const LdiEntry&) const = default;
};

/// Index of (tile, resolution, direction) in the directory and in writeVegetationFile's list.
constexpr int ldiIndex(int tile, int resolution, int direction) {
  return (tile * kLdiResolutions + resolution) * kLdiDirections + direction;
}

/// An LDI as the file stores it: its blob and what the directory says about it.
struct EncodedLdi {
  std::vector<uint8_t> blob;
  uint32_t width = 0, height = 0;
  uint64_t depthPixels = 0;
  uint32_t maxLayers = 0;
};
/// encodeLdi and the directory's figures. Thread-safe (bakers encode in parallel).
EncodedLdi encodeLdiForFile(const Ldi& ldi);

/// Writes a .tlv file atomically (AtomicFile): a failed or interrupted write leaves nothing
/// and an existing file at `path` untouched. `ldis` holds kLdiCount LDIs in ldiIndex order.
/// Refuses (one line naming `path`) a header or list the reader would refuse.
Status writeVegetationFile(const std::string& path, const VegetationHeader& header,
                           const std::vector<EncodedLdi>& ldis);

class VegetationReader {
 public:
  /// Reads and checks the file header, the settings and tiles and the LDI directory (three
  /// range reads); LDIs are read on demand. Errors are one line starting with the name.
  static Result<std::unique_ptr<VegetationReader>> open(std::unique_ptr<ByteSource> source);
  /// A path or an http(s):// URL (openByteSource).
  static Result<std::unique_ptr<VegetationReader>> openPathOrUrl(const std::string& pathOrUrl);

  const VegetationHeader& header() const { return mHeader; }
  /// Asserts on indices out of range.
  const LdiEntry& entry(int tile, int resolution, int direction) const;
  /// Reads that LDI's bytes alone, checks its CRC, decodes it and checks it against its entry.
  Result<Ldi> readLdi(int tile, int resolution, int direction) const;
  uint64_t fileBytes() const { return mSource->size(); }
  const std::string& name() const { return mSource->name(); }
  const ByteSource& source() const { return *mSource; }

 private:
  VegetationReader() = default;
  std::unique_ptr<ByteSource> mSource;
  VegetationHeader mHeader;
  std::vector<LdiEntry> mEntries;  ///< kLdiCount, ldiIndex order
};

// The byte layout (docs/format.md), shared by the writer, the reader, tests and the fuzzer.
namespace tlv {

inline constexpr uint8_t kMagic[8] = {'T', 'L', 'V', 'E', 'G', 0, 0, 0};
inline constexpr uint32_t kVersion = 1;
inline constexpr uint64_t kHeaderBytes = 128;
inline constexpr uint64_t kSettingsFixedBytes = 144;  ///< settings before the tile records
inline constexpr uint64_t kTileRecordBytes = 16, kObjectRecordBytes = 28;
inline constexpr uint64_t kDirectoryRecordBytes = 40;
inline constexpr uint64_t kDirectoryBytes = kLdiCount * kDirectoryRecordBytes;
inline constexpr uint64_t kMaxSettingsBytes = uint64_t{1} << 26;
inline constexpr uint32_t kMaxLdiSide = 4096;

/// The fixed header: where the three sections are and their CRCs.
struct FileHeader {
  uint64_t settingsOffset = 0, settingsBytes = 0;
  uint64_t directoryOffset = 0, directoryBytes = 0;
  uint64_t ldiAreaOffset = 0, ldiAreaBytes = 0;
  uint64_t fileBytes = 0;
  uint32_t settingsCrc = 0, directoryCrc = 0;
};

/// kHeaderBytes bytes, headerCrc filled in.
std::vector<uint8_t> serializeFileHeader(const FileHeader& header);
/// Checks magic, version, headerCrc, the counts and that the sections lie inside a file of
/// `fileSize` bytes without overlapping each other or the header.
Result<FileHeader> parseFileHeader(std::span<const uint8_t> bytes, uint64_t fileSize,
                                   const std::string& name);

std::vector<uint8_t> serializeSettings(const VegetationHeader& header);
/// Checks every field (docs/format.md, "What a reader validates").
Result<VegetationHeader> parseSettings(std::span<const uint8_t> bytes, const std::string& name);

std::vector<uint8_t> serializeDirectory(const std::vector<LdiEntry>& entries);
/// Checks every entry's sizes and that the blobs lie in the blob area without overlapping.
Result<std::vector<LdiEntry>> parseDirectory(std::span<const uint8_t> bytes,
                                             const FileHeader& header, const std::string& name);

/// "LDI (tile 1, resolution 2, direction 3)", for messages.
std::string describeLdi(int index);

}  // namespace tlv
}  // namespace terralod::veg
