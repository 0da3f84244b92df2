#include "terralod/format/tileset_format.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <span>

#include "terralod/format/tileset_reader.h"
#include "terralod/format/tileset_writer.h"

namespace terralod {
namespace {

TilesetHeader sampleHeader() {
  TilesetHeader h;
  h.levelCount = 3;
  h.leafCells = 16;
  h.rootCells = 64;
  h.rootsX = 2;
  h.rootsY = 1;
  h.sourceColumns = 100;
  h.sourceRows = 50;
  h.spacingX = 30.0;
  h.spacingY = 27.25;
  h.levelError[0] = 4;
  h.levelError[1] = 2;
  h.levelError[2] = 1;
  h.extentMin = {0, 0, -12.5};
  h.extentMax = {2970, 1335.25, 4000};
  h.nodeCount = 2;
  h.nodeTableOffset = 600;
  h.nodeTableBytes = 2 * kNodeRecordBytes;
  h.metadataOffset = 728;
  h.metadataBytes = 10;
  h.fileBytes = 738;
  h.filledVoids = 17;
  h.leafError = 1.0;
  return h;
}

TEST(TilesetHeader, RoundTrips) {
  const TilesetHeader h = sampleHeader();
  const std::vector<uint8_t> bytes = serializeHeader(h);
  ASSERT_EQ(bytes.size(), kHeaderBytes);
  auto parsed = parseHeader(bytes, "t.tlod");
  ASSERT_TRUE(parsed.ok()) << parsed.error().message;
  EXPECT_EQ(parsed->levelCount, 3u);
  EXPECT_EQ(parsed->spacingY, 27.25);
  EXPECT_EQ(parsed->extentMax[1], 1335.25);
  EXPECT_EQ(parsed->filledVoids, 17u);
  EXPECT_EQ(parsed->levelError[2], 1.0);
}

// meshKind is a u32 in the header: a corrupted 0x101 must not read as kind 1 once narrowed.
TEST(TilesetHeader, MeshKindIsCheckedAsTheU32ItIs) {
  std::vector<uint8_t> bytes = serializeHeader(sampleHeader());
  const auto withKind = [&](uint32_t kind) {
    auto b = bytes;
    std::memcpy(b.data() + 24, &kind, sizeof kind);
    const uint32_t crc = crc32Of(std::span(b).first(kHeaderBytes - 4));
    std::memcpy(b.data() + kHeaderBytes - 4, &crc, sizeof crc);
    return parseHeader(b, "k.tlod");
  };
  EXPECT_TRUE(withKind(1).ok());
  EXPECT_EQ(withKind(0x101).error().message,
            "k.tlod: invalid tileset header: unknown chunk mesh kind 257");
  EXPECT_EQ(withKind(0x01000001).error().message,
            "k.tlod: invalid tileset header: unknown chunk mesh kind 16777217");
}

TEST(TilesetHeader, RejectsWrongMagicFutureVersionAndCorruption) {
  std::vector<uint8_t> bytes = serializeHeader(sampleHeader());
  auto wrongMagic = bytes;
  wrongMagic[0] = 'X';
  EXPECT_EQ(parseHeader(wrongMagic, "a.tlod").error().message,
            "a.tlod: not a terralod tileset (wrong magic bytes)");
  auto future = bytes;
  future[8] = 8;
  EXPECT_EQ(parseHeader(future, "b.tlod").error().message,
            "b.tlod: tileset format version 8 is not supported (this terralod reads versions 1 "
            "to 7)");
  auto flipped = bytes;
  flipped[100] ^= 1;
  EXPECT_EQ(parseHeader(flipped, "c.tlod").error().message,
            "c.tlod: tileset header is corrupt (checksum mismatch)");
  EXPECT_FALSE(parseHeader(std::span(bytes.data(), 100), "d.tlod").ok());
}

TEST(TilesetHeader, AVipmTilesetMustHaveItsNormalMaps) {
  TilesetHeader h = sampleHeader();
  h.meshKind = MeshKind::kVipm;
  EXPECT_EQ(parseHeader(serializeHeader(h), "v.tlod").error().message,
            "v.tlod: invalid tileset header: a VIPM tileset (mesh kind 2) has no normal maps; "
            "rebuild it");
  h.version = 2;
  EXPECT_FALSE(parseHeader(serializeHeader(h), "v.tlod").ok());  // version 2, untextured
  h.flags = kTilesetTextured;
  h.textureMinTau = 2.0;
  EXPECT_TRUE(parseHeader(serializeHeader(h), "v.tlod").ok());
}

TEST(TilesetHeader, RejectsImpossibleValuesEvenWithAValidChecksum) {
  TilesetHeader h = sampleHeader();
  h.levelCount = 40;
  EXPECT_FALSE(parseHeader(serializeHeader(h), "x").ok());
  h = sampleHeader();
  h.nodeTableOffset = h.fileBytes;
  EXPECT_FALSE(parseHeader(serializeHeader(h), "x").ok());
  h = sampleHeader();
  h.spacingX = -1;
  EXPECT_FALSE(parseHeader(serializeHeader(h), "x").ok());
  // Version 4's compressed table: at least a byte a record (each holds a 4-byte CRC), so a
  // header cannot make a few bytes decompress into billions of records.
  h = sampleHeader();
  h.version = 4;
  h.nodeTableBytes = 2;
  EXPECT_TRUE(parseHeader(serializeHeader(h), "x").ok());
  h.nodeTableBytes = 1;
  EXPECT_EQ(parseHeader(serializeHeader(h), "x").error().message,
            "x: invalid tileset header: node count");
  h.version = 3;
  h.nodeTableBytes = 2;
  EXPECT_FALSE(parseHeader(serializeHeader(h), "x").ok()) << "versions 1-3 store 64 a record";
}

TEST(NodeRecord, RoundTrips) {
  NodeRecord n;
  n.level = 5;
  n.childMask = 0b1011;
  n.x = 123456;
  n.y = 7;
  n.firstChild = 99;
  n.parent = 3;
  n.minZ = -1.5f;
  n.maxZ = 8848.0f;
  n.vertexCount = 4000;
  n.triangleCount = 7800;
  n.skirtTriangleCount = 250;
  n.blobOffset = (uint64_t{1} << 40) + 5;
  n.blobBytes = 12345;
  n.blobCrc = 0xDEADBEEF;
  n.maxSkirtDepth = 3.25f;
  uint8_t bytes[kNodeRecordBytes];
  serializeNode(n, bytes);
  const NodeRecord m = parseNode(bytes, kTilesetVersion);
  EXPECT_EQ(m.level, 5);
  EXPECT_EQ(m.childMask, 0b1011);
  EXPECT_EQ(m.x, 123456u);
  EXPECT_EQ(m.blobOffset, n.blobOffset);
  EXPECT_EQ(m.blobCrc, 0xDEADBEEFu);
  EXPECT_EQ(m.maxZ, 8848.0f);
  EXPECT_EQ(m.maxSkirtDepth, 3.25f);
}

// Version 4 stores the node table as one zstd frame of shuffled records: the same records
// come back, in a fraction of the bytes; a frame of another size or one that does not
// decompress is refused with its own line.
TEST(NodeTable, VersionFourStoresTheRecordsCompressed) {
  std::vector<NodeRecord> nodes(500);
  for (uint32_t i = 0; i < nodes.size(); ++i) {
    NodeRecord& n = nodes[i];
    n.level = uint8_t(i % 7);
    n.x = i * 3;
    n.y = i / 5;
    n.parent = i ? i / 4 : kNoNode;
    n.minZ = float(i) * 0.5f;
    n.maxZ = n.minZ + 30;
    n.vertexCount = 100 + i % 50;
    n.blobOffset = kHeaderBytes + uint64_t(i) * 900;
    n.blobBytes = 900;
    n.blobCrc = i * 2654435761u;
  }
  TilesetHeader h;
  h.nodeCount = nodes.size();
  const std::vector<uint8_t> v3 = encodeNodeTable(nodes, 3), v4 = encodeNodeTable(nodes, 4);
  EXPECT_EQ(v3.size(), nodes.size() * kNodeRecordBytes);
  EXPECT_LT(v4.size() * 3, v3.size());
  for (uint32_t version : {3u, 4u}) {
    h.version = version;
    auto decoded = decodeNodeTable(version == 3 ? v3 : v4, h, "t.tlod");
    ASSERT_TRUE(decoded.ok()) << decoded.error().message;
    EXPECT_EQ(encodeNodeTable(*decoded, 3), v3);
  }
  h.version = 4;
  h.nodeCount = nodes.size() + 1;
  EXPECT_EQ(decodeNodeTable(v4, h, "t.tlod").error().message,
            "t.tlod: node table is corrupt (not 501 records in one zstd frame)");
  h.nodeCount = nodes.size();
  std::vector<uint8_t> damaged = v4;
  damaged[damaged.size() / 2] ^= 0x5A;
  damaged.resize(damaged.size() - 1);
  EXPECT_EQ(decodeNodeTable(damaged, h, "t.tlod").error().message,
            "t.tlod: node table is corrupt (does not decompress)");
}

// Two roots side by side, one level, blobs at 512 and 612, then the node table and metadata.
struct TwoRoots {
  TilesetHeader header;
  std::vector<NodeRecord> nodes;
  TwoRoots() {
    TilesetHeader& h = header;
    h.levelCount = 1;
    h.leafCells = h.rootCells = 16;
    h.rootsX = 2;
    h.rootsY = 1;
    h.sourceColumns = 33;
    h.sourceRows = 17;
    h.levelError[0] = 1;
    h.nodeCount = 2;
    h.nodeTableOffset = 712;
    h.nodeTableBytes = 2 * kNodeRecordBytes;
    h.metadataOffset = 840;
    h.metadataBytes = 10;
    h.fileBytes = 850;
    nodes.resize(2);
    for (uint32_t i = 0; i < 2; ++i) {
      nodes[i].x = i;
      nodes[i].blobOffset = kHeaderBytes + 100 * i;
      nodes[i].blobBytes = 100;
    }
  }
  std::string check() const {
    const Status s = validateNodes(header, nodes, "t.tlod");
    return s ? "ok" : s.error().message;
  }
};

TEST(NodeTable, ChunksMustNotOverlapEachOtherOrTheTables) {
  EXPECT_EQ(TwoRoots().check(), "ok");
  TwoRoots inside;
  inside.nodes[1].blobOffset = kHeaderBytes + 50;
  EXPECT_EQ(inside.check(), "t.tlod: corrupt node table: node 1 overlaps node 0");
  TwoRoots same;
  same.nodes[1].blobOffset = same.nodes[0].blobOffset;
  EXPECT_EQ(same.check(), "t.tlod: corrupt node table: node 1 overlaps node 0");
  TwoRoots textured;  // node 0's texture runs into node 1's geometry
  textured.header.version = 2;
  textured.header.flags = kTilesetTextured;
  for (NodeRecord& n : textured.nodes) {
    n.flags = kNodeHasTexture;
    n.blobBytes = 99;
    n.textureBytes = 1;
  }
  EXPECT_EQ(textured.check(), "ok");
  textured.nodes[0].textureBytes = 2;
  EXPECT_EQ(textured.check(), "t.tlod: corrupt node table: node 1 overlaps node 0");
  TwoRoots table;
  table.nodes[1].blobOffset = table.header.nodeTableOffset - 1;
  EXPECT_EQ(table.check(), "t.tlod: corrupt node table: node 1 overlaps the node table");
  TwoRoots metadata;
  metadata.nodes[0].blobOffset = metadata.header.metadataOffset;
  metadata.nodes[0].blobBytes = 5;
  EXPECT_EQ(metadata.check(), "t.tlod: corrupt node table: node 0 overlaps the metadata");
}

// Version 5: a textured root and its four children, which draw its texture (kNodeInheritsTexture).
struct SharedTexture {
  TilesetHeader header;
  std::vector<NodeRecord> nodes;
  SharedTexture() {
    TilesetHeader& h = header;
    h.version = 5;
    h.flags = kTilesetTextured;
    h.levelCount = 2;
    h.leafCells = 16;
    h.rootCells = 32;
    h.rootsX = h.rootsY = 1;
    h.sourceColumns = h.sourceRows = 33;
    h.levelError[0] = 2;
    h.levelError[1] = 1;
    h.nodeCount = 5;
    h.nodeTableOffset = 1032;
    h.nodeTableBytes = 5 * kNodeRecordBytes;
    h.metadataOffset = 1352;
    h.metadataBytes = 10;
    h.fileBytes = 1362;
    nodes.resize(5);
    nodes[0].flags = kNodeHasTexture;
    nodes[0].blobOffset = kHeaderBytes;
    nodes[0].blobBytes = 100;
    nodes[0].textureBytes = 20;
    nodes[0].childMask = 15;
    nodes[0].firstChild = 1;
    for (uint32_t q = 0; q < 4; ++q) {
      NodeRecord& c = nodes[1 + q];
      c.level = 1;
      c.x = q & 1;
      c.y = q >> 1;
      c.parent = 0;
      c.flags = kNodeInheritsTexture;
      c.blobOffset = 632 + 100 * q;
      c.blobBytes = 100;
    }
  }
  std::string check() const {
    const Status s = validateNodes(header, nodes, "t.tlod");
    return s ? "ok" : s.error().message;
  }
};

TEST(NodeTable, ChunksMayDrawTheirParentsTextureFromVersionFive) {
  const SharedTexture shared;
  EXPECT_EQ(shared.check(), "ok");
  const TextureSource source = textureSourceOf(shared.nodes, 4);
  EXPECT_EQ(source.owner, 0u);
  EXPECT_EQ(source.depth, 1u);
  EXPECT_EQ(source.column, 1u);
  EXPECT_EQ(source.row, 1u);
  EXPECT_EQ(textureSourceOf(shared.nodes, 0).owner, 0u);
  EXPECT_EQ(textureSourceOf(shared.nodes, 0).depth, 0u);
  SharedTexture v4;
  v4.header.version = 4;
  EXPECT_EQ(v4.check(), "t.tlod: corrupt node table: node 1 has unknown flags");
  SharedTexture both;
  both.nodes[2].flags |= kNodeHasTexture;
  EXPECT_EQ(both.check(), "t.tlod: corrupt node table: node 2 both has a texture and inherits one");
  SharedTexture neither;
  neither.nodes[3].flags = 0;
  EXPECT_EQ(neither.check(),
            "t.tlod: corrupt node table: node 3 disagrees with the header about textures");
  SharedTexture untextured;
  untextured.header.flags = 0;
  untextured.nodes[0].flags = 0;
  untextured.nodes[0].textureBytes = 0;
  EXPECT_EQ(untextured.check(),
            "t.tlod: corrupt node table: node 1 disagrees with the header about textures");
  EXPECT_EQ(textureSourceOf(untextured.nodes, 0).owner, kNoNode);
  SharedTexture root;
  root.nodes[0].flags = kNodeInheritsTexture;
  root.nodes[0].textureBytes = 0;
  EXPECT_EQ(root.check(),
            "t.tlod: corrupt node table: node 0 inherits a texture but has no parent");
}

// Regression: offsets near 2^64 wrapped around in `offset + length > fileBytes` and passed.
TEST(NodeTable, OffsetsThatWouldWrapAroundAreOutsideTheFile) {
  TwoRoots wrap;
  wrap.nodes[1].blobOffset = ~uint64_t{0} - 50;
  EXPECT_EQ(wrap.check(), "t.tlod: corrupt node table: node 1 points outside the file");
}

TEST(TilesetHeader, TableOffsetsThatWouldWrapAroundOrOverlapAreRefused) {
  auto problem = [](const TilesetHeader& h) {
    auto parsed = parseHeader(serializeHeader(h), "x");
    return parsed ? std::string("ok") : parsed.error().message;
  };
  const TwoRoots t;
  EXPECT_EQ(problem(t.header), "ok");
  TilesetHeader h = t.header;
  h.nodeTableOffset = ~uint64_t{0} - 64;
  EXPECT_EQ(problem(h), "x: invalid tileset header: table offsets");
  h = t.header;
  h.metadataOffset = ~uint64_t{0} - 4;
  EXPECT_EQ(problem(h), "x: invalid tileset header: table offsets");
  h = t.header;
  h.metadataOffset = h.nodeTableOffset + 10;
  EXPECT_EQ(problem(h), "x: invalid tileset header: table offsets");
}

// A whole file through the writer and reader, then damaged in several ways.
class TinyTileset : public ::testing::Test {
 protected:
  void SetUp() override {
    char name[] = "/tmp/terralod-format-test-XXXXXX";
    mDir = mkdtemp(name);
    mPath = mDir + "/t.tlod";
    auto writer = TilesetWriter::create(mPath).value();
    ChunkGeometry g;
    g.zStep = 0.5;
    ChunkPart& p = g.parts.emplace_back();
    p.vertices = {{0, 0, 10, 0}, {16, 0, 20, -1}, {16, 16, 30, 2}, {0, 16, 40, 0}};
    p.indices = {0, 1, 2, 0, 2, 3};
    p.surfaceIndexCount = 6;
    const std::vector<uint8_t> blob = encodeChunk(g);
    NodeRecord root;
    root.blobOffset = writer->appendBlob(blob).value();
    root.blobBytes = uint32_t(blob.size());
    root.blobCrc = crc32Of(blob);
    root.maxZ = 20;
    TilesetHeader h;
    h.levelCount = 1;
    h.leafCells = 16;
    h.rootCells = 16;
    h.rootsX = h.rootsY = 1;
    h.sourceColumns = h.sourceRows = 17;
    h.levelError[0] = 1;
    ASSERT_TRUE(writer->finish(h, {root}, "{\"hello\":1}").ok());
    mBytes = readAll();
  }
  void TearDown() override { std::filesystem::remove_all(mDir); }
  std::vector<uint8_t> readAll() {
    auto s = openFileSource(mPath).value();
    return s->read(0, s->size()).value();
  }
  Result<std::unique_ptr<TilesetReader>> openBytes(std::vector<uint8_t> bytes) {
    return TilesetReader::open(makeMemorySource(std::move(bytes), "mem.tlod"));
  }
  std::string mDir, mPath;
  std::vector<uint8_t> mBytes;
};

TEST_F(TinyTileset, ReadsBack) {
  auto t = TilesetReader::openFile(mPath);
  ASSERT_TRUE(t.ok()) << t.error().message;
  EXPECT_EQ((*t)->nodes().size(), 1u);
  EXPECT_EQ((*t)->metadataJson(), "{\"hello\":1}");
  auto g = (*t)->readChunk(0);
  ASSERT_TRUE(g.ok());
  EXPECT_EQ(g->parts[0].vertices.size(), 4u);
  EXPECT_FALSE((*t)->readChunk(1).ok());
}

TEST_F(TinyTileset, TruncationIsReportedAsSuch) {
  for (size_t n : {size_t(0), size_t(100), size_t(kHeaderBytes), mBytes.size() - 1}) {
    auto t = openBytes(std::vector<uint8_t>(mBytes.begin(), mBytes.begin() + n));
    ASSERT_FALSE(t.ok());
    const std::string& m = t.error().message;
    EXPECT_TRUE(m.find("too short") != std::string::npos ||
                m.find("truncated") != std::string::npos)
        << m;
  }
}

TEST_F(TinyTileset, DamagedTablesAndBlobsAreCaught) {
  const TilesetHeader h = parseHeader(mBytes, "x").value();
  auto table = mBytes;
  table[h.nodeTableOffset + 3] ^= 0x10;
  EXPECT_EQ(openBytes(table).error().message,
            "mem.tlod: node table is corrupt (checksum mismatch)");
  auto blob = mBytes;
  blob[kHeaderBytes + 5] ^= 0x01;
  auto opened = openBytes(blob);
  ASSERT_TRUE(opened.ok());
  EXPECT_EQ((*opened)->readChunk(0).error().message,
            "mem.tlod: chunk 0 is corrupt (checksum mismatch)");
  auto meta = mBytes;
  meta[h.metadataOffset] ^= 0x01;
  EXPECT_FALSE(openBytes(meta).ok());
}

TEST(TilesetWriter, AbandonedWriteLeavesNothingBehind) {
  char name[] = "/tmp/terralod-format-test-XXXXXX";
  const std::string dir = mkdtemp(name);
  {
    auto writer = TilesetWriter::create(dir + "/never.tlod").value();
    ASSERT_TRUE(writer->appendBlob(std::vector<uint8_t>(1000, 7)).ok());
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  EXPECT_FALSE(TilesetWriter::create(dir + "/no/such/dir/x.tlod").ok());
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace terralod
