#include "terralod/vegetation/vegetation_file.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <zstd.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <random>

#include "temp_dir.h"
#include "terralod/format/tileset_format.h"  // crc32Of

// Helpers in a named namespace: test files are compiled four to a unit (unity builds).
namespace terralod::veg::vegetation_file_test {

VegetationHeader sampleHeader() {
  VegetationHeader h;
  BakeSettings& s = h.settings;
  s.scene = "sunflowers";
  s.seed = 0x123456789ABCDEFull;
  s.tileSize = 4;
  s.headHeight = 1.7f;
  s.tileHeight = 2.25f;
  s.resolutions = {468, 331, 234, 165, 117, 83, 62};
  s.ringDistances = {6, 8.5f, 12, 17, 24, 34, 48};
  s.elevations = {0.3f, 0.2f, 0.14f, 0.1f, 0.07f, 0.05f, -0.01f};
  s.raysPerPixel = 4;
  s.bakeSeconds = 12.5;
  s.raysCast = 987654321;
  for (int t = 0; t < kPrototiles; ++t) {
    h.tiles[t].edges = {uint8_t(t & 1), uint8_t(t >> 1 & 1), uint8_t(t & 1), uint8_t(t >> 2)};
    for (int i = 0; i < t; ++i) {
      PlacedObject o;
      o.x = -0.25f + 0.6f * i;
      o.y = 4.1f - 0.5f * i;
      o.tightRadius = 0.3f;
      o.packingRadius = 0.36f;
      o.species = Species(i % kSpeciesCount);
      o.version = uint8_t(i % 9);
      o.rotation = 0.1f * i;
      o.scale = 0.9f + 0.01f * i;
      h.tiles[t].objects.push_back(o);
    }
    h.trianglesModelled[t] = 1000 * uint64_t(t) + 7;
  }
  return h;
}

// 448 tiny LDIs, each different (its index is in its colours and camera).
std::vector<Ldi> sampleLdis() {
  std::mt19937 rng(17);
  std::vector<Ldi> ldis(kLdiCount);
  for (int i = 0; i < kLdiCount; ++i) {
    Ldi& l = ldis[i];
    l.camera.width = 1 + i % 3;
    l.camera.height = 1 + i % 2;
    l.camera.pixelSize = 0.01f * (1 + i);
    l.camera.origin = {float(i), 0, 2};
    l.camera.depthMin = 0.5f;
    l.camera.depthMax = 9;
    for (uint32_t p = 0; p < l.camera.width * l.camera.height; ++p) {
      const uint8_t layers = uint8_t(i % 5 == 0 ? 0 : rng() % 4);
      l.layerCounts.push_back(layers);
      for (int k = 0; k < layers; ++k)
        l.pixels.push_back(
            DepthPixel::make(uint32_t(i) << 8 | 0xFF000000u, rng() & kLdiMaxDepth, rng() % 2025));
    }
  }
  return ldis;
}

std::vector<EncodedLdi> encodeAll(const std::vector<Ldi>& ldis) {
  std::vector<EncodedLdi> encoded;
  for (const Ldi& l : ldis) encoded.push_back(encodeLdiForFile(l));
  return encoded;
}

std::vector<uint8_t> fileBytes(const std::string& path) {
  const std::string s = test::readWholeFile(path);
  return std::vector<uint8_t>(s.begin(), s.end());
}

Result<std::unique_ptr<VegetationReader>> openBytes(std::vector<uint8_t> bytes) {
  return VegetationReader::open(makeMemorySource(std::move(bytes), "mem.tlv"));
}

std::string openError(std::vector<uint8_t> bytes) {
  auto r = openBytes(std::move(bytes));
  return r.ok() ? "opened" : r.error().message;
}

void expectOneLineNamingTheFile(const std::string& message) {
  EXPECT_EQ(message.rfind("mem.tlv", 0), 0u) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

// A memory source that records every read.
class RecordingSource : public ByteSource {
 public:
  explicit RecordingSource(std::vector<uint8_t> bytes)
      : mInner(makeMemorySource(std::move(bytes), "rec.tlv")) {}
  uint64_t size() const override { return mInner->size(); }
  Result<std::vector<uint8_t>> read(uint64_t offset, uint64_t length) const override {
    std::lock_guard lock(mMutex);
    reads.push_back({offset, length});
    return mInner->read(offset, length);
  }
  const std::string& name() const override { return mInner->name(); }
  mutable std::vector<std::pair<uint64_t, uint64_t>> reads;

 private:
  std::unique_ptr<ByteSource> mInner;
  mutable std::mutex mMutex;
};

// A view of a file's bytes cut to `size` and with one byte changed, without copying them: the
// every-byte tests open tens of thousands of variants.
class VariantSource : public ByteSource {
 public:
  VariantSource(const std::vector<uint8_t>& bytes, uint64_t size, uint64_t flipAt = ~uint64_t{0},
                uint8_t flipMask = 0)
      : mBytes(bytes), mSize(size), mFlipAt(flipAt), mFlipMask(flipMask) {}
  uint64_t size() const override { return mSize; }
  Result<std::vector<uint8_t>> read(uint64_t offset, uint64_t length) const override {
    if (offset > mSize || length > mSize - offset) return makeError(mName, "read past the end");
    std::vector<uint8_t> out(mBytes.begin() + offset, mBytes.begin() + offset + length);
    if (mFlipAt >= offset && mFlipAt - offset < length) out[mFlipAt - offset] ^= mFlipMask;
    return out;
  }
  const std::string& name() const override { return mName; }
  void changeByte(uint64_t at, uint8_t mask) { mFlipAt = at, mFlipMask = mask; }

 private:
  const std::vector<uint8_t>& mBytes;
  const uint64_t mSize;
  uint64_t mFlipAt;
  uint8_t mFlipMask;
  const std::string mName = "mem.tlv";
};

class VegetationFile : public ::testing::Test {
 protected:
  void SetUp() override {
    mPath = mDir.file("veg.tlv");
    Status s = writeVegetationFile(mPath, mHeader, encodeAll(mLdis));
    ASSERT_TRUE(s.ok()) << s.error().message;
    mBytes = fileBytes(mPath);
    mFileHeader = tlv::parseFileHeader(mBytes, mBytes.size(), "x").value();
  }
  // The file with one section's bytes changed and every CRC recomputed: for checks behind
  // the checksums.
  std::vector<uint8_t> withSettings(const VegetationHeader& h) {
    const std::vector<uint8_t> settings = tlv::serializeSettings(h);
    tlv::FileHeader fh = mFileHeader;
    const int64_t shift = int64_t(settings.size()) - int64_t(fh.settingsBytes);
    std::vector<uint8_t> bytes(mBytes.begin(), mBytes.begin() + fh.settingsOffset);
    bytes.insert(bytes.end(), settings.begin(), settings.end());
    bytes.insert(bytes.end(), mBytes.begin() + fh.directoryOffset, mBytes.end());
    fh.settingsBytes = settings.size();
    fh.settingsCrc = crc32Of(settings);
    fh.directoryOffset += shift;
    fh.ldiAreaOffset += shift;
    fh.fileBytes += shift;
    std::vector<LdiEntry> entries =
        tlv::parseDirectory(directoryOf(mBytes), mFileHeader, "x").value();
    for (LdiEntry& e : entries) e.offset += shift;
    const std::vector<uint8_t> directory = tlv::serializeDirectory(entries);
    fh.directoryCrc = crc32Of(directory);
    std::copy(directory.begin(), directory.end(), bytes.begin() + fh.directoryOffset);
    const std::vector<uint8_t> header = tlv::serializeFileHeader(fh);
    std::copy(header.begin(), header.end(), bytes.begin());
    return bytes;
  }
  std::vector<uint8_t> withEntries(const std::vector<LdiEntry>& entries) {
    std::vector<uint8_t> bytes = mBytes;
    tlv::FileHeader fh = mFileHeader;
    const std::vector<uint8_t> directory = tlv::serializeDirectory(entries);
    fh.directoryCrc = crc32Of(directory);
    std::copy(directory.begin(), directory.end(), bytes.begin() + fh.directoryOffset);
    const std::vector<uint8_t> header = tlv::serializeFileHeader(fh);
    std::copy(header.begin(), header.end(), bytes.begin());
    return bytes;
  }
  std::vector<uint8_t> withFileHeader(const tlv::FileHeader& fh) {
    std::vector<uint8_t> bytes = mBytes;
    const std::vector<uint8_t> header = tlv::serializeFileHeader(fh);
    std::copy(header.begin(), header.end(), bytes.begin());
    return bytes;
  }
  std::span<const uint8_t> directoryOf(const std::vector<uint8_t>& bytes) const {
    return std::span(bytes).subspan(mFileHeader.directoryOffset, mFileHeader.directoryBytes);
  }
  std::vector<LdiEntry> entries() const {
    return tlv::parseDirectory(directoryOf(mBytes), mFileHeader, "x").value();
  }

  test::TempDir mDir;
  std::string mPath;
  const VegetationHeader mHeader = sampleHeader();
  const std::vector<Ldi> mLdis = sampleLdis();
  std::vector<uint8_t> mBytes;
  tlv::FileHeader mFileHeader;
};

TEST_F(VegetationFile, RoundTripsThroughAFile) {
  auto reader = VegetationReader::openPathOrUrl(mPath);
  ASSERT_TRUE(reader.ok()) << reader.error().message;
  const VegetationReader& r = **reader;
  EXPECT_EQ(r.header(), mHeader);
  EXPECT_EQ(r.fileBytes(), mBytes.size());
  EXPECT_EQ(r.name(), mPath);
  for (int t = 0; t < kPrototiles; ++t)
    for (int res = 0; res < kLdiResolutions; ++res)
      for (int d = 0; d < kLdiDirections; ++d) {
        const Ldi& expected = mLdis[ldiIndex(t, res, d)];
        const LdiEntry& e = r.entry(t, res, d);
        EXPECT_EQ(e.width, expected.camera.width);
        EXPECT_EQ(e.height, expected.camera.height);
        EXPECT_EQ(e.depthPixels, expected.pixels.size());
        auto ldi = r.readLdi(t, res, d);
        ASSERT_TRUE(ldi.ok()) << ldi.error().message;
        EXPECT_TRUE(*ldi == expected) << t << " " << res << " " << d;
      }
  EXPECT_EQ(r.readLdi(8, 0, 0).error().message,
            mPath + ": no LDI (tile 8, resolution 0, direction 0)");
  EXPECT_FALSE(r.readLdi(0, -1, 0).ok());
}

TEST_F(VegetationFile, LaysOutTheFileAsDocumented) {
  EXPECT_EQ(std::memcmp(mBytes.data(), "TLVEG\0\0\0", 8), 0);
  EXPECT_EQ(mFileHeader.settingsOffset, 128u);
  uint64_t objects = 0;
  for (const PrototileContent& t : mHeader.tiles) objects += t.objects.size();
  EXPECT_EQ(mFileHeader.settingsBytes, 144 + 8 * 16 + 28 * objects);
  EXPECT_EQ(mFileHeader.directoryOffset, 128 + mFileHeader.settingsBytes);
  EXPECT_EQ(mFileHeader.directoryBytes, 448u * 40);
  EXPECT_EQ(mFileHeader.ldiAreaOffset, mFileHeader.directoryOffset + 448 * 40);
  EXPECT_EQ(mFileHeader.fileBytes, mBytes.size());
  EXPECT_EQ(mFileHeader.ldiAreaOffset + mFileHeader.ldiAreaBytes, mBytes.size());
  const std::vector<LdiEntry> e = entries();
  EXPECT_EQ(e[0].offset, mFileHeader.ldiAreaOffset);
  for (int i = 1; i < kLdiCount; ++i) EXPECT_EQ(e[i].offset, e[i - 1].offset + e[i - 1].bytes);
}

TEST_F(VegetationFile, ReadsOnlyTheTablesThenOneRangePerLdi) {
  auto owned = std::make_unique<RecordingSource>(mBytes);
  RecordingSource* source = owned.get();
  auto reader = VegetationReader::open(std::move(owned));
  ASSERT_TRUE(reader.ok()) << reader.error().message;
  using Range = std::pair<uint64_t, uint64_t>;
  EXPECT_EQ(source->reads,
            (std::vector<Range>{{0, 128},
                                {mFileHeader.settingsOffset, mFileHeader.settingsBytes},
                                {mFileHeader.directoryOffset, mFileHeader.directoryBytes}}));
  source->reads.clear();
  const LdiEntry& e = (*reader)->entry(3, 4, 5);
  auto ldi = (*reader)->readLdi(3, 4, 5);
  ASSERT_TRUE(ldi.ok()) << ldi.error().message;
  EXPECT_TRUE(*ldi == mLdis[ldiIndex(3, 4, 5)]);
  EXPECT_EQ(source->reads, (std::vector<Range>{{e.offset, e.bytes}}));
}

TEST_F(VegetationFile, RoundTripsThroughMemory) {
  auto reader = openBytes(mBytes);
  ASSERT_TRUE(reader.ok()) << reader.error().message;
  EXPECT_EQ((*reader)->header(), mHeader);
  EXPECT_TRUE((*reader)->readLdi(7, 6, 7).value() == mLdis.back());
}

TEST_F(VegetationFile, EveryTruncationAndPaddingIsRefused) {
  for (size_t n = 0; n < mBytes.size(); ++n) {
    auto r = VegetationReader::open(std::make_unique<VariantSource>(mBytes, n));
    ASSERT_FALSE(r.ok()) << n;
    const std::string& m = r.error().message;
    expectOneLineNamingTheFile(m);
    EXPECT_TRUE(m.find("truncated") != std::string::npos || m.find("empty") != std::string::npos)
        << m;
  }
  EXPECT_EQ(openError({}), "mem.tlv: empty file, not a terralod vegetation file");
  EXPECT_EQ(openError(std::vector<uint8_t>(mBytes.begin(), mBytes.begin() + 100)),
            "mem.tlv: truncated (the header ends at 128 but the file has 100 bytes)");
  const uint64_t directoryEnd = mFileHeader.directoryOffset + mFileHeader.directoryBytes;
  const uint64_t cut = mFileHeader.directoryOffset + 100;
  EXPECT_EQ(openError(std::vector<uint8_t>(mBytes.begin(), mBytes.begin() + cut)),
            "mem.tlv: truncated (the directory ends at " + std::to_string(directoryEnd) +
                " but the file has " + std::to_string(cut) + " bytes)");
  EXPECT_EQ(openError(std::vector<uint8_t>(mBytes.begin(), mBytes.begin() + 800)),
            "mem.tlv: truncated (the settings section ends at " +
                std::to_string(mFileHeader.directoryOffset) + " but the file has 800 bytes)");
  auto padded = mBytes;
  padded.push_back(0);
  EXPECT_EQ(openError(padded), "mem.tlv: padded (the header says " + std::to_string(mBytes.size()) +
                                   " bytes but the file has " + std::to_string(padded.size()) +
                                   ")");
}

TEST_F(VegetationFile, EveryFlippedByteIsCaught) {
  // Header, settings and directory: refused when opened. A blob: refused when that LDI is
  // read (its CRC); opening reads no blob, so one reader serves them all.
  const auto mask = [](size_t i) { return uint8_t(1 << (i % 8)); };
  for (size_t i = 0; i < mFileHeader.ldiAreaOffset; ++i) {
    auto reader =
        VegetationReader::open(std::make_unique<VariantSource>(mBytes, mBytes.size(), i, mask(i)));
    ASSERT_FALSE(reader.ok()) << "byte " << i;
    expectOneLineNamingTheFile(reader.error().message);
  }
  auto owned = std::make_unique<VariantSource>(mBytes, mBytes.size());
  VariantSource* source = owned.get();
  auto reader = VegetationReader::open(std::move(owned));
  ASSERT_TRUE(reader.ok()) << reader.error().message;
  const std::vector<LdiEntry> e = entries();
  int owner = 0;
  for (size_t i = mFileHeader.ldiAreaOffset; i < mBytes.size(); ++i) {
    source->changeByte(i, mask(i));
    while (i >= e[owner].offset + e[owner].bytes) ++owner;
    auto ldi = (*reader)->readLdi(owner / 56, owner / 8 % 7, owner % 8);
    ASSERT_FALSE(ldi.ok()) << "byte " << i;
    EXPECT_EQ(ldi.error().message,
              "mem.tlv " + tlv::describeLdi(owner) + ": corrupt (checksum mismatch)");
    if (owner > 0) {
      EXPECT_TRUE((*reader)->readLdi(0, 0, 0).ok());
    }
  }
}

TEST_F(VegetationFile, NamesWhatIsWrongInTheHeader) {
  auto magic = mBytes;
  magic[1] = 'X';
  EXPECT_EQ(openError(magic), "mem.tlv: not a terralod vegetation file (bad magic)");
  EXPECT_EQ(openError({'T', 'L', 'D'}), "mem.tlv: not a terralod vegetation file (bad magic)");
  auto version = mBytes;
  version[8] = 2;
  EXPECT_EQ(openError(version),
            "mem.tlv: vegetation file version 2 is not supported (this terralod reads version 1)");
  auto crc = mBytes;
  crc[100] ^= 1;  // reserved, but covered by the header CRC
  EXPECT_EQ(openError(crc), "mem.tlv: vegetation header is corrupt (checksum mismatch)");
  auto settings = mBytes;
  settings[mFileHeader.settingsOffset + 20] ^= 1;
  EXPECT_EQ(openError(settings), "mem.tlv: vegetation settings are corrupt (checksum mismatch)");
  auto directory = mBytes;
  directory[mFileHeader.directoryOffset + 20] ^= 1;
  EXPECT_EQ(openError(directory), "mem.tlv: LDI directory is corrupt (checksum mismatch)");

  // Behind a valid CRC.
  tlv::FileHeader h = mFileHeader;
  h.directoryOffset = mFileHeader.settingsOffset + 8;
  EXPECT_EQ(openError(withFileHeader(h)),
            "mem.tlv: invalid vegetation header: the settings section overlaps the directory");
  h = mFileHeader;
  h.ldiAreaOffset = 64;
  EXPECT_EQ(openError(withFileHeader(h)),
            "mem.tlv: invalid vegetation header: the LDI area overlaps the header");
  h = mFileHeader;
  h.directoryBytes = 448 * 40 + 1;
  EXPECT_EQ(openError(withFileHeader(h)),
            "mem.tlv: invalid vegetation header: directory size 17921 is not 17920");
  h = mFileHeader;
  h.ldiAreaOffset = ~uint64_t{0} - 10;                       // would wrap around
  const std::string wrapped = openError(withFileHeader(h));  // the true end, past 2^64
  EXPECT_EQ(wrapped.rfind("mem.tlv: truncated (the LDI area ends at 184467440737096", 0), 0u)
      << wrapped;
  h = mFileHeader;
  h.settingsBytes = uint64_t{1} << 40;
  EXPECT_EQ(openError(withFileHeader(h)),
            "mem.tlv: invalid vegetation header: settings size 1099511627776 is impossible");
  auto counts = mBytes;
  counts[16] = 9;  // prototiles
  const uint32_t c = crc32Of(std::span(counts).subspan(0, 124));
  std::memcpy(counts.data() + 124, &c, 4);
  EXPECT_EQ(openError(counts),
            "mem.tlv: invalid vegetation header: counts or record sizes are not 128, 8, 7, 8, 40");
}

TEST_F(VegetationFile, NamesWhatIsWrongInTheSettings) {
  EXPECT_EQ(openError(withSettings(mHeader)), "opened");  // the helper itself
  const auto error = [&](auto change) {
    VegetationHeader h = mHeader;
    change(h);
    const std::string m = openError(withSettings(h));
    return m.rfind("mem.tlv: invalid vegetation settings: ", 0) == 0
               ? m.substr(std::strlen("mem.tlv: invalid vegetation settings: "))
               : m;
  };
  EXPECT_EQ(error([](auto& h) { h.settings.scene = ""; }),
            "scene name is not 1 to 16 characters a-z, 0-9, _ or -");
  EXPECT_EQ(error([](auto& h) { h.settings.scene = "Meadow"; }),
            "scene name is not 1 to 16 characters a-z, 0-9, _ or -");
  EXPECT_EQ(error([](auto& h) { h.settings.scene = "meadow_2-b"; }), "opened");
  EXPECT_EQ(error([](auto& h) { h.settings.tileSize = NAN; }),
            "tile size is not a positive number of metres");
  EXPECT_EQ(error([](auto& h) { h.settings.tileSize = 0; }),
            "tile size is not a positive number of metres");
  EXPECT_EQ(error([](auto& h) { h.settings.headHeight = -1; }),
            "head height is not a positive number of metres");
  EXPECT_EQ(error([](auto& h) { h.settings.tileHeight = INFINITY; }),
            "tile height is not a number of metres >= 0");
  EXPECT_EQ(error([](auto& h) { h.settings.raysPerPixel = 0; }), "rays per pixel is 0");
  EXPECT_EQ(error([](auto& h) { h.settings.resolutions[0] = 4097; }),
            "LDI size of resolution level 0 is outside 1..4096 pixels");
  EXPECT_EQ(error([](auto& h) { h.settings.resolutions[6] = 0; }),
            "LDI size of resolution level 6 is outside 1..4096 pixels");
  EXPECT_EQ(error([](auto& h) { h.settings.resolutions[3] = 300; }),
            "LDI size of resolution level 3 is larger than the level before (finest first)");
  EXPECT_EQ(error([](auto& h) { h.settings.ringDistances[2] = 5; }),
            "ring distance of resolution level 2 is nearer than the level before (finest first)");
  EXPECT_EQ(error([](auto& h) { h.settings.ringDistances[0] = 0; }),
            "ring distance of resolution level 0 is not a positive number of metres");
  EXPECT_EQ(error([](auto& h) { h.settings.elevations[4] = 1.6f; }),
            "elevation of resolution level 4 is not an angle within ±pi/2");
  EXPECT_EQ(error([](auto& h) { h.settings.bakeSeconds = -1; }),
            "bake time is not a number of seconds >= 0");
  EXPECT_EQ(error([](auto& h) { h.tiles[2].edges.west = 2; }),
            "tile 2 has an edge colour other than 0 or 1");
  EXPECT_EQ(error([](auto& h) { h.tiles[3].objects[1].species = Species(4); }),
            "tile 3 object 1 has an unknown species 4");
  EXPECT_EQ(error([](auto& h) { h.tiles[7].objects[0].version = 11; }),
            "tile 7 object 0 has version 11 but sunflower has 11");
  EXPECT_EQ(error([](auto& h) { h.tiles[7].objects[2].version = 9; }),
            "tile 7 object 2 has version 9 but dandelion has 9");
  EXPECT_EQ(error([](auto& h) { h.tiles[5].objects[4].tightRadius = -0.1f; }),
            "tile 5 object 4 has a tight radius that is not a number of metres >= 0");
  EXPECT_EQ(error([](auto& h) { h.tiles[5].objects[4].packingRadius = 0.29f; }),
            "tile 5 object 4 has a packing radius smaller than its tight radius");
  EXPECT_EQ(error([](auto& h) { h.tiles[1].objects[0].x = 8.5f; }),
            "tile 1 object 0 lies more than a tile size outside its tile (or not at a finite "
            "position)");
  EXPECT_EQ(error([](auto& h) { h.tiles[1].objects[0].y = NAN; }),
            "tile 1 object 0 lies more than a tile size outside its tile (or not at a finite "
            "position)");
  EXPECT_EQ(error([](auto& h) { h.tiles[6].objects[5].rotation = INFINITY; }),
            "tile 6 object 5 has a rotation that is not finite");
  EXPECT_EQ(error([](auto& h) { h.tiles[6].objects[5].scale = 0; }),
            "tile 6 object 5 has a scale that is not positive");
  // An object count that does not match the section's length.
  std::vector<uint8_t> s = tlv::serializeSettings(mHeader);
  s[144 + 16 * 4 + 4] += 1;  // tile 4's object count
  EXPECT_EQ(tlv::parseSettings(s, "x").error().message,
            "x: invalid vegetation settings: 29 objects need 1084 bytes but the section has "
            "1056");
}

TEST_F(VegetationFile, NamesWhatIsWrongInTheDirectory) {
  const std::vector<LdiEntry> good = entries();
  const auto error = [&](int i, auto change) {
    std::vector<LdiEntry> e = good;
    change(e[i]);
    return openError(withEntries(e));
  };
  const std::string prefix =
      "mem.tlv: corrupt LDI directory: LDI (tile 1, resolution 2, direction 3) ";
  const int i = ldiIndex(1, 2, 3);
  EXPECT_EQ(error(i, [&](LdiEntry& e) { e.offset = mFileHeader.directoryOffset; }),
            prefix + "lies outside the LDI area");
  EXPECT_EQ(error(i, [&](LdiEntry& e) { e.bytes = mBytes.size(); }),
            prefix + "lies outside the LDI area");
  EXPECT_EQ(error(i, [&](LdiEntry& e) { e.bytes = ~uint64_t{0}; }),
            prefix + "lies outside the LDI area");
  EXPECT_EQ(error(i, [&](LdiEntry& e) { e.bytes = 0; }), prefix + "is empty");
  EXPECT_EQ(error(i, [&](LdiEntry& e) { e.width = 0; }),
            prefix + "is 0 x " + std::to_string(good[i].height) + " pixels, outside 1..4096");
  EXPECT_EQ(error(i, [&](LdiEntry& e) { e.height = 4097; }),
            prefix + "is " + std::to_string(good[i].width) + " x 4097 pixels, outside 1..4096");
  EXPECT_EQ(error(i, [&](LdiEntry& e) { e.maxLayers = 256; }), prefix + "has more than 255 layers");
  EXPECT_EQ(error(i, [&](LdiEntry& e) { e.depthPixels = 0, e.maxLayers = 1; }),
            prefix + "has 0 depth pixels, impossible with 1 layers at most");
  EXPECT_EQ(error(i, [&](LdiEntry& e) { e.depthPixels = 1000, e.maxLayers = 3; }),
            prefix + "has 1000 depth pixels, impossible with 3 layers at most");
  EXPECT_EQ(error(ldiIndex(1, 2, 4), [&](LdiEntry& e) { e.offset -= 1; }),
            "mem.tlv: corrupt LDI directory: LDI (tile 1, resolution 2, direction 4) overlaps " +
                std::string("LDI (tile 1, resolution 2, direction 3)"));
  // Consistent with the directory but not with the blob: found when the LDI is read.
  auto reader = openBytes(withEntries([&] {
    std::vector<LdiEntry> e = good;
    e[i].width += 1;
    return e;
  }()));
  ASSERT_TRUE(reader.ok()) << reader.error().message;
  const std::string m = (*reader)->readLdi(1, 2, 3).error().message;
  EXPECT_EQ(m.rfind("mem.tlv LDI (tile 1, resolution 2, direction 3): does not match its "
                    "directory entry (",
                    0),
            0u)
      << m;
}

TEST_F(VegetationFile, ABlobThatPassesItsChecksumIsStillDecodedWithCare) {
  // A writer's bug rather than damage: a blob that is not an LDI, with a matching CRC.
  std::vector<LdiEntry> e = entries();
  const int i = ldiIndex(0, 1, 2);
  std::vector<uint8_t> blob(mBytes.begin() + e[i].offset,
                            mBytes.begin() + e[i].offset + e[i].bytes);
  blob[0] = 'X';
  e[i].crc = crc32Of(blob);
  std::vector<uint8_t> bytes = withEntries(e);
  bytes[e[i].offset] = 'X';
  auto reader = openBytes(bytes);
  ASSERT_TRUE(reader.ok()) << reader.error().message;
  EXPECT_EQ((*reader)->readLdi(0, 1, 2).error().message,
            "mem.tlv LDI (tile 0, resolution 1, direction 2): corrupt LDI: bad magic");
}

TEST_F(VegetationFile, TheWriterRefusesWhatTheReaderWould) {
  const std::string path = mDir.file("bad.tlv");
  std::vector<EncodedLdi> ldis = encodeAll(mLdis);
  VegetationHeader h = mHeader;
  h.settings.tileSize = -4;
  EXPECT_EQ(writeVegetationFile(path, h, ldis).error().message,
            path + ": invalid vegetation settings: tile size is not a positive number of metres");
  h = mHeader;
  h.settings.scene = "sunflowers_and_more";
  EXPECT_EQ(writeVegetationFile(path, h, ldis).error().message,
            path +
                ": cannot write scene name \"sunflowers_and_more\": it is longer than 16 "
                "characters");
  ldis.pop_back();
  EXPECT_EQ(writeVegetationFile(path, mHeader, ldis).error().message,
            path + ": cannot write a vegetation file of 447 LDIs (it holds 448)");
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST_F(VegetationFile, AFailedWriteLeavesNothingAndKeepsTheOldFile) {
  const std::vector<EncodedLdi> ldis = encodeAll(mLdis);
  EXPECT_FALSE(writeVegetationFile(mDir.file("no/such/dir/v.tlv"), mHeader, ldis).ok());

  // Refused before writing: the old file stays as it was.
  VegetationHeader bad = mHeader;
  bad.tiles[0].edges.north = 7;
  EXPECT_FALSE(writeVegetationFile(mPath, bad, ldis).ok());
  EXPECT_EQ(fileBytes(mPath), mBytes);

  // Failing half way, as on a full disk: a file size limit makes write() fail with EFBIG.
  VegetationHeader changed = mHeader;
  changed.settings.seed += 1;
  rlimit old{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &old), 0);
  rlimit limited = old;
  limited.rlim_cur = 4096;
  void (*oldHandler)(int) = signal(SIGXFSZ, SIG_IGN);
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &limited), 0);
  const Status s = writeVegetationFile(mPath, changed, ldis);
  setrlimit(RLIMIT_FSIZE, &old);
  signal(SIGXFSZ, oldHandler);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message.find('\n'), std::string::npos);
  EXPECT_EQ(fileBytes(mPath), mBytes);
  size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(mDir.path())) {
    (void)entry;
    ++files;
  }
  EXPECT_EQ(files, 1u);  // no temporary file left behind

  // And with room, the new file replaces the old one.
  ASSERT_TRUE(writeVegetationFile(mPath, changed, ldis).ok());
  EXPECT_EQ(VegetationReader::openPathOrUrl(mPath).value()->header(), changed);
}

// Writes the seeds of fuzz/tlv_reader_fuzzer into $TERRALOD_TLV_SEEDS (fuzz/make-seeds.sh):
// a small valid file (checksums recomputed by the harness, and as given) and LDI blobs
// (stored, and as header plus payload for the harness to compress).
TEST(VegetationFuzzSeeds, AreWrittenWhenAsked) {
  const char* dir = std::getenv("TERRALOD_TLV_SEEDS");
  if (!dir) GTEST_SKIP() << "set TERRALOD_TLV_SEEDS to a directory to write the fuzz seeds";
  const auto save = [&](const std::string& name, uint8_t mode, std::span<const uint8_t> bytes) {
    std::ofstream out(std::string(dir) + "/" + name, std::ios::binary);
    out.put(char(mode));
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    ASSERT_TRUE(out.good()) << name;
  };
  test::TempDir temp;
  const std::string path = temp.file("seed.tlv");
  ASSERT_TRUE(writeVegetationFile(path, sampleHeader(), encodeAll(sampleLdis())).ok());
  const std::vector<uint8_t> file = fileBytes(path);
  save("tiny_file", 0, file);
  save("tiny_file_checksums_kept", 1, file);

  std::mt19937 rng(5);
  const auto ldi = [&](uint32_t width, uint32_t height, int maxLayers) {
    Ldi l;
    l.camera.width = width;
    l.camera.height = height;
    l.camera.pixelSize = 0.02f;
    l.camera.depthMax = 3;
    for (uint32_t p = 0; p < width * height; ++p) {
      const uint8_t layers = uint8_t(rng() % (maxLayers + 1));
      l.layerCounts.push_back(layers);
      uint32_t depth = rng() % 1000;
      for (int k = 0; k < layers; ++k, depth += rng() % 5000)
        l.pixels.push_back(DepthPixel::make(0xFF204080u + (rng() & 0x0F0F0F), depth, rng() % 2025));
    }
    return l;
  };
  const struct {
    const char* name;
    Ldi ldi;
  } blobs[] = {
      {"ldi_7x5", ldi(7, 5, 4)}, {"ldi_1x1_empty", ldi(1, 1, 0)}, {"ldi_3x1_deep", ldi(3, 1, 255)}};
  for (const auto& b : blobs) {
    const std::vector<uint8_t> blob = encodeLdi(b.ldi);
    save(std::string(b.name) + "_stored", 2, blob);
    std::vector<uint8_t> raw(blob.begin(), blob.begin() + 80);
    raw.resize(80 + ZSTD_getFrameContentSize(blob.data() + 80, blob.size() - 80));
    ZSTD_decompress(raw.data() + 80, raw.size() - 80, blob.data() + 80, blob.size() - 80);
    save(std::string(b.name) + "_payload", 3, raw);
  }
}

}  // namespace terralod::veg::vegetation_file_test
