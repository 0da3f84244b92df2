// Streaming under faults, drawn for real: a corrupt chunk, a web server that stops mid-flight
// and comes back, a server that trickles. Each failure is logged once, the chunk is retried
// later, drawing goes on from resident ancestors — no error, no hole, no frame waiting.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "nginx_server.h"
#include "shared_directory.h"
#include "terralod/format/http_source.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/render/framebuffer.h"
#include "terralod/render/gl_context.h"
#include "terralod/render/terrain_scene.h"

namespace terralod::test {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
constexpr std::array<uint8_t, 3> kMagenta{0xFF, 0x00, 0xFF};

class StreamingFaults : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // Built once for every test process of this build of the CLI.
    sDir = new SharedDirectory(
        sharedDirectory("crater-textured", programStamp(TERRALOD_CLI), [](const std::string& dir) {
          const RunResult r = runTerralod({"build", testData("crater_lake_0513.bt"), "-o",
                                           dir + "/crater.tlod", "--max-error", "0.5"});
          return r.exitCode == 0 ? std::string() : r.err;
        }));
    ASSERT_EQ(sDir->error, "");
  }
  static void TearDownTestSuite() { delete sDir; }

  void SetUp() override {
    auto context = GlContext::createHeadless();
    ASSERT_TRUE(context.ok()) << context.error().message;
    mContext = std::move(context).value();
  }

  std::unique_ptr<TerrainScene> scene(std::unique_ptr<ByteSource> source) {
    auto reader = TilesetReader::open(std::move(source));
    EXPECT_TRUE(reader.ok()) << reader.error().message;
    if (!reader) return nullptr;
    SceneOptions o;
    o.log = [this](const std::string& line) { mLog.push_back(line); };
    auto s = TerrainScene::create(std::move(reader).value(), o);
    EXPECT_TRUE(s.ok()) << s.error().message;
    return s ? std::move(s).value() : nullptr;
  }

  // Crater Lake is about 10.3 x 14 km: fly low along the rim, looking down 50 degrees.
  static Camera cameraAt(double t) {
    Camera c;
    c.eye = {2500 + 5000 * t, 3000 + 7000 * t, 2700};
    c.target = c.eye + glm::dvec3(0.3, 0.6, -0.9) * 1000.0;
    c.width = 240;
    c.height = 180;
    return c;
  }

  // One frame (must not fail, must not wait), then the same moment seen straight down with
  // no sky: the pixels the terrain leaves uncovered.
  size_t frame(TerrainScene& s, double t, double* worstMs = nullptr) {
    const View view = makeView(cameraAt(t)).value();
    auto target = Framebuffer::create(view.camera.width, view.camera.height).value();
    target.bind();
    SelectionOptions selection;
    selection.tau = 1.0;
    const auto start = Clock::now();
    auto stats = s.renderFrame(view, selection, TerrainStyle{});
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    if (worstMs) *worstMs = std::max(*worstMs, ms);
    EXPECT_TRUE(stats.ok()) << stats.error().message;
    if (stats) {
      EXPECT_FALSE(stats->waitedOnIo);
    }
    Camera down = view.camera;
    down.target = down.eye + glm::dvec3(0.0, 0.3, -1.0) * 500.0;
    const View downView = makeView(down).value();
    TerrainStyle holes;
    holes.sky = false;
    holes.background = kMagenta;
    s.renderResident(downView, selection, holes);
    const Image image = target.readPixels();
    size_t n = 0;
    for (size_t i = 0; i < image.rgba.size(); i += 4)
      n += image.rgba[i] == 0xFF && image.rgba[i + 1] == 0 && image.rgba[i + 2] == 0xFF;
    return n;
  }

  static inline SharedDirectory* sDir = nullptr;
  std::unique_ptr<GlContext> mContext;
  std::vector<std::string> mLog;
};

TEST_F(StreamingFaults, ACorruptChunkIsLoggedOnceAndDrawnFromItsAncestors) {
  // Damage one level-2 chunk's blob (its checksum in the node table no longer matches).
  TempDir scratch;
  const std::string path = scratch.file("corrupt.tlod");
  fs::copy_file(sDir->file("crater.tlod"), path, fs::copy_options::overwrite_existing);
  uint32_t victim = 0;
  {
    auto reader = TilesetReader::openFile(path).value();
    for (uint32_t i = 0; i < reader->nodes().size(); ++i)
      if (reader->nodes()[i].level == 2) victim = i;
    const NodeRecord& n = reader->nodes()[victim];
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(std::streamoff(n.blobOffset + n.blobBytes / 2));
    f.put(char(0x5A));
  }
  auto s = scene(openFileSource(path).value());
  ASSERT_TRUE(s);
  size_t holes = 0;
  for (int i = 0; i < 240; ++i) holes += frame(*s, i / 240.0);
  EXPECT_EQ(holes, 0u);
  const std::string name = "chunk " + std::to_string(victim) + " is corrupt";
  size_t lines = 0;
  for (const std::string& line : mLog) lines += line.find(name) != std::string::npos;
  EXPECT_EQ(lines, 1u) << ::testing::PrintToString(mLog);
  EXPECT_EQ(s->residency().state(victim) == ChunkState::kResident, false);
  EXPECT_GE(s->residency().counters().failures, 1u);
}

TEST_F(StreamingFaults, AServerStoppedMidFlightDegradesToCoarserTerrainAndRecovers) {
  TempDir www;
  fs::copy_file(sDir->file("crater.tlod"), www.file("crater.tlod"));
  NginxServer server(www.path());
  ASSERT_TRUE(server.running()) << server.error();
  HttpOptions http;
  http.retries = 1;
  http.firstBackoffSeconds = 0.01;
  http.connectTimeoutSeconds = 1;
  http.requestTimeoutSeconds = 2;
  auto s = scene(openHttpSource(server.url("crater.tlod"), http).value());
  ASSERT_TRUE(s);
  size_t holes = 0;
  for (int i = 0; i < 60; ++i) holes += frame(*s, i / 240.0);
  const uint64_t loadsBefore = s->residency().counters().loads;
  EXPECT_GT(loadsBefore, 1u);
  server.stop();
  for (int i = 60; i < 160; ++i) holes += frame(*s, i / 240.0);
  EXPECT_GT(s->residency().counters().failures, 0u) << "the flight never needed a new chunk";
  EXPECT_FALSE(mLog.empty());
  ASSERT_TRUE(server.start()) << server.error();
  // Failed chunks are retried later: back on the server, the terrain fills in again.
  uint32_t coarser = 1;
  for (int i = 160; i < 400 && coarser > 0; ++i) {
    holes += frame(*s, 160 / 240.0);
    const View view = makeView(cameraAt(160 / 240.0)).value();
    SelectionOptions selection;
    selection.tau = 1.0;
    selection.drawable = s->residency().drawable();
    std::vector<SelectedChunk> out;
    coarser = selectChunks(s->tree(), view, selection, out).coarserThanWanted;
  }
  EXPECT_EQ(coarser, 0u) << "chunks that failed while the server was down never came back";
  EXPECT_EQ(holes, 0u);
}

// Reads at `fastOffsets` (header, tables, the root) from one source, the rest (the other
// chunks) from another.
class SplitSource final : public ByteSource {
 public:
  SplitSource(std::unique_ptr<ByteSource> fast, std::unique_ptr<ByteSource> slow,
              std::vector<uint64_t> fastOffsets)
      : mFast(std::move(fast)), mSlow(std::move(slow)), mFastOffsets(std::move(fastOffsets)) {}
  uint64_t size() const override { return mFast->size(); }
  Result<std::vector<uint8_t>> read(uint64_t offset, uint64_t length) const override {
    const bool fast =
        std::find(mFastOffsets.begin(), mFastOffsets.end(), offset) != mFastOffsets.end();
    return (fast ? mFast : mSlow)->read(offset, length);
  }
  const std::string& name() const override { return mSlow->name(); }

 private:
  std::unique_ptr<ByteSource> mFast, mSlow;
  std::vector<uint64_t> mFastOffsets;
};

TEST_F(StreamingFaults, ASlowServerNeverStallsAFrame) {
  TempDir www;
  fs::copy_file(sDir->file("crater.tlod"), www.file("crater.tlod"));
  NginxServer server(www.path());
  ASSERT_TRUE(server.running()) << server.error();
  std::vector<uint64_t> fastOffsets;
  {
    auto local = TilesetReader::openFile(www.file("crater.tlod")).value();
    const TilesetHeader& h = local->header();
    fastOffsets = {0, h.nodeTableOffset, h.metadataOffset};
    for (uint32_t r = 0; r < h.rootsX * h.rootsY; ++r)
      fastOffsets.push_back(local->nodes()[r].blobOffset);
  }
  // Chunks trickle at 2 KB/s (/slow/): a level-1 chunk takes seconds.
  // Loads still running when the scene closes are waited for: keep them short.
  HttpOptions http;
  http.retries = 0;
  http.requestTimeoutSeconds = 3;
  auto fast = openHttpSource(server.url("crater.tlod"), http);
  auto slow = openHttpSource(server.url("slow/crater.tlod"), http);
  ASSERT_TRUE(fast.ok() && slow.ok());
  auto s = scene(
      std::make_unique<SplitSource>(std::move(fast).value(), std::move(slow).value(), fastOffsets));
  ASSERT_TRUE(s);
  double worst = 0;
  size_t holes = 0;
  const auto start = Clock::now();
  for (int i = 0; i < 40; ++i) holes += frame(*s, i / 40.0, &worst);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  EXPECT_EQ(holes, 0u);
  EXPECT_LT(worst, 1000.0) << "a frame waited for the slow server";
  EXPECT_LT(seconds, 20.0);
  EXPECT_LT(s->residency().counters().loads, 30u) << "the server was not slow: proves nothing";
}

TEST_F(StreamingFaults, BenchFliesATilesetServedOverHttp) {
  TempDir www;
  fs::copy_file(sDir->file("crater.tlod"), www.file("crater.tlod"));
  NginxServer server(www.path());
  ASSERT_TRUE(server.running()) << server.error();
  const RunResult r = runTerralod({"bench", server.url("crater.tlod"), "--auto-flight", "--frames",
                                   "80", "--size", "160x120", "--cache-mb", "64", "--source",
                                   testData("crater_lake_0513.bt"), "--json", www.file("b.json")});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto j = nlohmann::json::parse(readWholeFile(www.file("b.json")));
  EXPECT_GT(j["bytes_read"].get<uint64_t>(), 0u);
  EXPECT_GT(j["loads"].get<uint64_t>(), 1u);
  EXPECT_EQ(j["frames_waiting_on_io"], 0);
  EXPECT_EQ(j["holes_total"], 0);
  EXPECT_LE(j["resident_mb_max"].get<double>(), 64.0);
  EXPECT_GT(server.requestsFor("crater.tlod", 2), 1u);
}

}  // namespace
}  // namespace terralod::test
