// The byte layout of .tlv files (docs/format.md, "Vegetation files (.tlv)"): the fixed header,
// the settings and tiles section and the LDI directory, each written field by field in
// little-endian and checked field by field when read.

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstring>
#include <numbers>
#include <type_traits>

#include "terralod/format/byte_io.h"
#include "terralod/format/tileset_format.h"  // crc32Of
#include "terralod/vegetation/vegetation_file.h"

namespace terralod::veg {
namespace tlv {
namespace {

static_assert(std::endian::native == std::endian::little, "terralod's format is little-endian");

constexpr uint64_t kHeaderCrcOffset = 124;
constexpr size_t kSceneBytes = 16;

// [offset, offset + bytes) ends at or before `limit`, computed without wrapping around.
bool endsBy(uint64_t offset, uint64_t bytes, uint64_t limit) {
  return offset <= limit && bytes <= limit - offset;
}
// offset + bytes in decimal, exactly, even where it passes 2^64.
std::string endOf(uint64_t offset, uint64_t bytes) {
  unsigned __int128 end = (unsigned __int128)offset + bytes;
  std::string digits;
  do {
    digits.insert(digits.begin(), char('0' + int(end % 10)));
    end /= 10;
  } while (end > 0);
  return digits;
}
bool overlap(uint64_t a, uint64_t aBytes, uint64_t b, uint64_t bBytes) {
  return aBytes > 0 && bBytes > 0 && a < b + bBytes && b < a + aBytes;
}

bool sceneNameIsValid(const char (&scene)[kSceneBytes]) {
  size_t n = 0;
  while (n < kSceneBytes && scene[n] != 0) {
    const char c = scene[n];
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-')) return false;
    ++n;
  }
  if (n == 0) return false;
  for (size_t i = n; i < kSceneBytes; ++i)
    if (scene[i] != 0) return false;
  return true;
}

Error badSettings(const std::string& name, const std::string& problem) {
  return makeError(name, "invalid vegetation settings: " + problem);
}

// The checks of the fixed settings (docs/format.md lists them in this order).
Status checkBakeSettings(const BakeSettings& s, const std::string& name) {
  const auto bad = [&](const std::string& problem) { return badSettings(name, problem); };
  if (!std::isfinite(s.tileSize) || !(s.tileSize > 0))
    return bad("tile size is not a positive number of metres");
  if (!std::isfinite(s.headHeight) || !(s.headHeight > 0))
    return bad("head height is not a positive number of metres");
  if (!std::isfinite(s.tileHeight) || !(s.tileHeight >= 0))
    return bad("tile height is not a number of metres >= 0");
  if (s.raysPerPixel < 1) return bad("rays per pixel is 0");
  for (int r = 0; r < kLdiResolutions; ++r) {
    const std::string level = " of resolution level " + std::to_string(r);
    if (s.resolutions[r] < 1 || s.resolutions[r] > kMaxLdiSide)
      return bad("LDI size" + level + " is outside 1..4096 pixels");
    if (r > 0 && s.resolutions[r] > s.resolutions[r - 1])
      return bad("LDI size" + level + " is larger than the level before (finest first)");
    if (!std::isfinite(s.ringDistances[r]) || !(s.ringDistances[r] > 0))
      return bad("ring distance" + level + " is not a positive number of metres");
    if (r > 0 && s.ringDistances[r] < s.ringDistances[r - 1])
      return bad("ring distance" + level + " is nearer than the level before (finest first)");
    if (!std::isfinite(s.elevations[r]) ||
        !(std::abs(s.elevations[r]) <= float(std::numbers::pi / 2)))
      return bad("elevation" + level + " is not an angle within ±pi/2");
  }
  if (!std::isfinite(s.bakeSeconds) || !(s.bakeSeconds >= 0))
    return bad("bake time is not a number of seconds >= 0");
  return {};
}

Status checkObject(const PlacedObject& o, float tileSize, const std::string& subject,
                   const std::string& name) {
  const auto bad = [&](const std::string& problem) {
    return badSettings(name, subject + " " + problem);
  };
  const auto nearTile = [&](float v) {
    return std::isfinite(v) && v >= -tileSize && v <= 2 * tileSize;
  };
  if (!nearTile(o.x) || !nearTile(o.y))
    return bad("lies more than a tile size outside its tile (or not at a finite position)");
  if (!std::isfinite(o.tightRadius) || !(o.tightRadius >= 0))
    return bad("has a tight radius that is not a number of metres >= 0");
  if (!std::isfinite(o.packingRadius) || !(o.packingRadius >= o.tightRadius))
    return bad("has a packing radius smaller than its tight radius");
  if (uint8_t(o.species) >= kSpeciesCount)
    return bad("has an unknown species " + std::to_string(unsigned(o.species)));
  if (o.version >= versionCount(o.species))
    return bad("has version " + std::to_string(unsigned(o.version)) + " but " +
               std::string(speciesName(o.species)) + " has " +
               std::to_string(versionCount(o.species)));
  if (!std::isfinite(o.rotation)) return bad("has a rotation that is not finite");
  if (!std::isfinite(o.scale) || !(o.scale > 0)) return bad("has a scale that is not positive");
  return {};
}

}  // namespace

std::string describeLdi(int index) {
  const int direction = index % kLdiDirections;
  const int resolution = index / kLdiDirections % kLdiResolutions;
  const int tile = index / (kLdiDirections * kLdiResolutions);
  return "LDI (tile " + std::to_string(tile) + ", resolution " + std::to_string(resolution) +
         ", direction " + std::to_string(direction) + ")";
}

std::vector<uint8_t> serializeFileHeader(const FileHeader& h) {
  std::vector<uint8_t> bytes(kHeaderBytes, 0);  // the rest up to the CRC is reserved
  ByteWriter out(bytes.data());
  out.putBytes(kMagic, sizeof kMagic);
  out.put<uint32_t>(kVersion);
  out.put<uint32_t>(uint32_t(kHeaderBytes));
  out.put<uint32_t>(kPrototiles);
  out.put<uint32_t>(kLdiResolutions);
  out.put<uint32_t>(kLdiDirections);
  out.put<uint32_t>(uint32_t(kDirectoryRecordBytes));
  for (uint64_t v : {h.settingsOffset, h.settingsBytes, h.directoryOffset, h.directoryBytes,
                     h.ldiAreaOffset, h.ldiAreaBytes, h.fileBytes})
    out.put<uint64_t>(v);
  out.put<uint32_t>(h.settingsCrc);
  out.put<uint32_t>(h.directoryCrc);
  out.seek(kHeaderCrcOffset);
  out.put<uint32_t>(crc32Of(std::span(bytes).first(kHeaderCrcOffset)));
  return bytes;
}

Result<FileHeader> parseFileHeader(std::span<const uint8_t> bytes, uint64_t fileSize,
                                   const std::string& name) {
  if (bytes.empty()) return makeError(name, "empty file, not a terralod vegetation file");
  // Magic first, so that any other file is called what it is, even a short one.
  const size_t magicBytes = std::min<size_t>(bytes.size(), sizeof kMagic);
  if (std::memcmp(bytes.data(), kMagic, magicBytes) != 0)
    return makeError(name, "not a terralod vegetation file (bad magic)");
  if (bytes.size() < kHeaderBytes)
    return makeError(name, "truncated (the header ends at " + std::to_string(kHeaderBytes) +
                               " but the file has " + std::to_string(bytes.size()) + " bytes)");
  ByteReader in(bytes.data());
  in.skip(sizeof kMagic);
  if (const uint32_t version = in.get<uint32_t>(); version != kVersion)
    return makeError(name, "vegetation file version " + std::to_string(version) +
                               " is not supported (this terralod reads version 1)");
  uint32_t stored;
  std::memcpy(&stored, bytes.data() + kHeaderCrcOffset, 4);
  if (crc32Of(bytes.subspan(0, kHeaderCrcOffset)) != stored)
    return makeError(name, "vegetation header is corrupt (checksum mismatch)");
  const uint32_t headerBytes = in.get<uint32_t>(), tiles = in.get<uint32_t>(),
                 resolutions = in.get<uint32_t>(), directions = in.get<uint32_t>(),
                 recordBytes = in.get<uint32_t>();
  if (headerBytes != kHeaderBytes || tiles != kPrototiles || resolutions != kLdiResolutions ||
      directions != kLdiDirections || recordBytes != kDirectoryRecordBytes)
    return makeError(name,
                     "invalid vegetation header: counts or record sizes are not 128, 8, "
                     "7, 8, 40");
  FileHeader h;
  h.settingsOffset = in.get<uint64_t>();
  h.settingsBytes = in.get<uint64_t>();
  h.directoryOffset = in.get<uint64_t>();
  h.directoryBytes = in.get<uint64_t>();
  h.ldiAreaOffset = in.get<uint64_t>();
  h.ldiAreaBytes = in.get<uint64_t>();
  h.fileBytes = in.get<uint64_t>();
  h.settingsCrc = in.get<uint32_t>();
  h.directoryCrc = in.get<uint32_t>();

  if (h.settingsBytes < kSettingsFixedBytes + kPrototiles * kTileRecordBytes ||
      h.settingsBytes > kMaxSettingsBytes)
    return makeError(name, "invalid vegetation header: settings size " +
                               std::to_string(h.settingsBytes) + " is impossible");
  if (h.directoryBytes != kDirectoryBytes)
    return makeError(name, "invalid vegetation header: directory size " +
                               std::to_string(h.directoryBytes) + " is not " +
                               std::to_string(kDirectoryBytes));
  const struct {
    const char* what;
    uint64_t offset, bytes;
  } sections[] = {{"settings section", h.settingsOffset, h.settingsBytes},
                  {"directory", h.directoryOffset, h.directoryBytes},
                  {"LDI area", h.ldiAreaOffset, h.ldiAreaBytes}};
  for (const auto& s : sections) {
    if (s.offset < kHeaderBytes)
      return makeError(
          name, std::string("invalid vegetation header: the ") + s.what + " overlaps the header");
    if (!endsBy(s.offset, s.bytes, fileSize))
      return makeError(name, std::string("truncated (the ") + s.what + " ends at " +
                                 endOf(s.offset, s.bytes) + " but the file has " +
                                 std::to_string(fileSize) + " bytes)");
  }
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b)
      if (overlap(sections[a].offset, sections[a].bytes, sections[b].offset, sections[b].bytes))
        return makeError(name, std::string("invalid vegetation header: the ") + sections[a].what +
                                   " overlaps the " + sections[b].what);
  if (h.fileBytes != fileSize)
    return makeError(name, (h.fileBytes > fileSize ? "truncated" : "padded") +
                               std::string(" (the header says ") + std::to_string(h.fileBytes) +
                               " bytes but the file has " + std::to_string(fileSize) + ")");
  return h;
}

std::vector<uint8_t> serializeSettings(const VegetationHeader& header) {
  const BakeSettings& s = header.settings;
  size_t objects = 0;
  for (const PrototileContent& tile : header.tiles) objects += tile.objects.size();
  std::vector<uint8_t> bytes(kSettingsFixedBytes + kPrototiles * kTileRecordBytes +
                             objects * kObjectRecordBytes);
  ByteWriter out(bytes.data());
  char scene[kSceneBytes] = {};
  std::memcpy(scene, s.scene.data(), std::min(s.scene.size(), kSceneBytes));
  out.putBytes(scene, kSceneBytes);
  out.put<uint64_t>(s.seed);
  out.put<float>(s.tileSize);
  out.put<float>(s.headHeight);
  out.put<float>(s.tileHeight);
  out.put<uint32_t>(s.raysPerPixel);
  for (uint32_t v : s.resolutions) out.put<uint32_t>(v);
  for (float v : s.ringDistances) out.put<float>(v);
  for (float v : s.elevations) out.put<float>(v);
  out.put<uint32_t>(0);  // reserved
  out.put<double>(s.bakeSeconds);
  out.put<uint64_t>(s.raysCast);
  for (int t = 0; t < kPrototiles; ++t) {
    const TileEdges& e = header.tiles[t].edges;
    for (uint8_t v : {e.north, e.east, e.south, e.west}) out.put<uint8_t>(v);
    out.put<uint32_t>(uint32_t(header.tiles[t].objects.size()));
    out.put<uint64_t>(header.trianglesModelled[t]);
  }
  for (const PrototileContent& tile : header.tiles)
    for (const PlacedObject& o : tile.objects) {
      for (float v : {o.x, o.y, o.tightRadius, o.packingRadius}) out.put<float>(v);
      out.put<uint8_t>(uint8_t(o.species));
      out.put<uint8_t>(o.version);
      out.put<uint16_t>(0);  // reserved
      out.put<float>(o.rotation);
      out.put<float>(o.scale);
    }
  assert(out.position() == bytes.size());
  return bytes;
}

Result<VegetationHeader> parseSettings(std::span<const uint8_t> bytes, const std::string& name) {
  if (bytes.size() < kSettingsFixedBytes + kPrototiles * kTileRecordBytes)
    return badSettings(name, "section of " + std::to_string(bytes.size()) + " bytes is too short");
  VegetationHeader h;
  BakeSettings& s = h.settings;
  ByteReader in(bytes.data());
  char scene[kSceneBytes];
  in.getBytes(scene, kSceneBytes);
  if (!sceneNameIsValid(scene))
    return badSettings(name, "scene name is not 1 to 16 characters a-z, 0-9, _ or -");
  s.scene.assign(scene, strnlen(scene, kSceneBytes));
  s.seed = in.get<uint64_t>();
  s.tileSize = in.get<float>();
  s.headHeight = in.get<float>();
  s.tileHeight = in.get<float>();
  s.raysPerPixel = in.get<uint32_t>();
  for (uint32_t& v : s.resolutions) v = in.get<uint32_t>();
  for (float& v : s.ringDistances) v = in.get<float>();
  for (float& v : s.elevations) v = in.get<float>();
  in.skip(4);  // reserved
  s.bakeSeconds = in.get<double>();
  s.raysCast = in.get<uint64_t>();
  if (Status ok = checkBakeSettings(s, name); !ok) return ok.error();

  uint64_t objects = 0;
  std::array<uint32_t, kPrototiles> counts{};
  for (int t = 0; t < kPrototiles; ++t) {
    TileEdges& e = h.tiles[t].edges;
    for (uint8_t* v : {&e.north, &e.east, &e.south, &e.west}) *v = in.get<uint8_t>();
    if (e.north > 1 || e.east > 1 || e.south > 1 || e.west > 1)
      return badSettings(name,
                         "tile " + std::to_string(t) + " has an edge colour other than 0 or 1");
    counts[t] = in.get<uint32_t>();
    objects += counts[t];
    h.trianglesModelled[t] = in.get<uint64_t>();
  }
  const uint64_t expected =
      kSettingsFixedBytes + kPrototiles * kTileRecordBytes + objects * kObjectRecordBytes;
  if (expected != bytes.size())
    return badSettings(name, std::to_string(objects) + " objects need " + std::to_string(expected) +
                                 " bytes but the section has " + std::to_string(bytes.size()));
  for (int t = 0; t < kPrototiles; ++t) {
    std::vector<PlacedObject>& list = h.tiles[t].objects;
    list.resize(counts[t]);
    for (uint32_t i = 0; i < counts[t]; ++i) {
      PlacedObject& o = list[i];
      o.x = in.get<float>();
      o.y = in.get<float>();
      o.tightRadius = in.get<float>();
      o.packingRadius = in.get<float>();
      o.species = Species(in.get<uint8_t>());
      o.version = in.get<uint8_t>();
      in.skip(2);  // reserved
      o.rotation = in.get<float>();
      o.scale = in.get<float>();
      const std::string subject = "tile " + std::to_string(t) + " object " + std::to_string(i);
      if (Status ok = checkObject(o, s.tileSize, subject, name); !ok) return ok.error();
    }
  }
  return h;
}

std::vector<uint8_t> serializeDirectory(const std::vector<LdiEntry>& entries) {
  std::vector<uint8_t> bytes(entries.size() * kDirectoryRecordBytes);
  ByteWriter out(bytes.data());
  for (const LdiEntry& e : entries) {
    out.put<uint64_t>(e.offset);
    out.put<uint64_t>(e.bytes);
    out.put<uint32_t>(e.width);
    out.put<uint32_t>(e.height);
    out.put<uint64_t>(e.depthPixels);
    out.put<uint32_t>(e.maxLayers);
    out.put<uint32_t>(e.crc);
  }
  return bytes;
}

Result<std::vector<LdiEntry>> parseDirectory(std::span<const uint8_t> bytes,
                                             const FileHeader& header, const std::string& name) {
  if (bytes.size() != kDirectoryBytes)
    return makeError(name, "corrupt LDI directory: " + std::to_string(bytes.size()) +
                               " bytes instead of " + std::to_string(kDirectoryBytes));
  std::vector<LdiEntry> entries(kLdiCount);
  ByteReader in(bytes.data());
  for (int i = 0; i < kLdiCount; ++i) {
    LdiEntry& e = entries[i];
    e.offset = in.get<uint64_t>();
    e.bytes = in.get<uint64_t>();
    e.width = in.get<uint32_t>();
    e.height = in.get<uint32_t>();
    e.depthPixels = in.get<uint64_t>();
    e.maxLayers = in.get<uint32_t>();
    e.crc = in.get<uint32_t>();
    const auto bad = [&](const std::string& problem) {
      return makeError(name, "corrupt LDI directory: " + describeLdi(i) + " " + problem);
    };
    if (e.offset < header.ldiAreaOffset ||
        !endsBy(e.offset - header.ldiAreaOffset, e.bytes, header.ldiAreaBytes))
      return bad("lies outside the LDI area");
    if (e.bytes == 0) return bad("is empty");
    if (e.width < 1 || e.width > kMaxLdiSide || e.height < 1 || e.height > kMaxLdiSide)
      return bad("is " + std::to_string(e.width) + " x " + std::to_string(e.height) +
                 " pixels, outside 1..4096");
    if (e.maxLayers > 255) return bad("has more than 255 layers");
    if ((e.depthPixels == 0) != (e.maxLayers == 0) || e.depthPixels < e.maxLayers ||
        e.depthPixels > uint64_t(e.width) * e.height * e.maxLayers)
      return bad("has " + std::to_string(e.depthPixels) + " depth pixels, impossible with " +
                 std::to_string(e.maxLayers) + " layers at most");
  }
  std::vector<int> order(kLdiCount);
  for (int i = 0; i < kLdiCount; ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return entries[a].offset < entries[b].offset; });
  for (int k = 1; k < kLdiCount; ++k) {
    const LdiEntry& before = entries[order[k - 1]];
    if (entries[order[k]].offset - before.offset < before.bytes)
      return makeError(name, "corrupt LDI directory: " + describeLdi(order[k]) + " overlaps " +
                                 describeLdi(order[k - 1]));
  }
  return entries;
}

}  // namespace tlv

EncodedLdi encodeLdiForFile(const Ldi& ldi) {
  EncodedLdi e;
  e.blob = encodeLdi(ldi);
  e.width = ldi.camera.width;
  e.height = ldi.camera.height;
  e.depthPixels = ldi.pixels.size();
  for (uint8_t count : ldi.layerCounts) e.maxLayers = std::max<uint32_t>(e.maxLayers, count);
  return e;
}

}  // namespace terralod::veg
