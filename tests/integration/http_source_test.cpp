// Tilesets over HTTP: the libcurl byte source against a real nginx (tests/support/nginx_server.h)
// serving the golden v2 tileset — ranges, a whole TilesetReader, the CLI, and every failure the
// source must survive: 404, 500, connection resets, a server ignoring ranges, a slow or stalled
// server, a server that goes away and comes back.

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <random>
#include <thread>

#include "cli_runner.h"
#include "nginx_server.h"
#include "terralod/format/http_source.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/render/image.h"

namespace terralod::test {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::vector<uint8_t> bytesOf(const std::string& path) {
  const std::string s = readWholeFile(path);
  return std::vector<uint8_t>(s.begin(), s.end());
}

bool startsWith(const std::string& s, const std::string& prefix) {
  return s.rfind(prefix, 0) == 0;
}

/// Quick retries, so that failure tests take milliseconds.
HttpOptions fastRetries(int retries) {
  HttpOptions o;
  o.retries = retries;
  o.firstBackoffSeconds = 0.01;
  o.maxBackoffSeconds = 0.05;
  o.connectTimeoutSeconds = 2;
  o.requestTimeoutSeconds = 5;
  return o;
}

class Http : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::copy_file(testData("golden/v2/gully.tlod"), mWww.file("gully.tlod"));
    mLocal = mWww.file("gully.tlod");
    mBytes = bytesOf(mLocal);
    ASSERT_GT(mBytes.size(), 10000u);
    mServer = std::make_unique<NginxServer>(mWww.path());
    ASSERT_TRUE(mServer->running()) << mServer->error();
  }
  std::string url(const std::string& path = "gully.tlod") const { return mServer->url(path); }

  TempDir mWww;
  std::string mLocal;
  std::vector<uint8_t> mBytes;
  std::unique_ptr<NginxServer> mServer;
};

TEST_F(Http, SizeAndArbitraryRangesAreTheFilesBytes) {
  auto opened = openHttpSource(url());
  ASSERT_TRUE(opened.ok()) << opened.error().message;
  const ByteSource& s = **opened;
  EXPECT_EQ(s.name(), url());
  ASSERT_EQ(s.size(), mBytes.size());
  EXPECT_EQ(s.stats().requests, 1u) << "the size takes one request";

  auto whole = s.read(0, s.size());
  ASSERT_TRUE(whole.ok()) << whole.error().message;
  EXPECT_TRUE(*whole == mBytes);
  std::mt19937_64 random(7);
  uint64_t asked = whole->size();
  for (int i = 0; i < 60; ++i) {
    const uint64_t offset = random() % mBytes.size();
    const uint64_t length = 1 + random() % std::min<uint64_t>(mBytes.size() - offset, 5000);
    auto part = s.read(offset, length);
    ASSERT_TRUE(part.ok()) << part.error().message;
    ASSERT_EQ(part->size(), length);
    EXPECT_TRUE(std::equal(part->begin(), part->end(), mBytes.begin() + offset))
        << "bytes " << offset << "+" << length;
    asked += length;
  }
  auto last = s.read(mBytes.size() - 1, 1);
  ASSERT_TRUE(last.ok()) << last.error().message;
  EXPECT_EQ(last->at(0), mBytes.back());
  asked += 1;
  EXPECT_TRUE(s.read(5, 0).ok());

  const SourceStats before = s.stats();
  auto past = s.read(mBytes.size() - 10, 11);
  ASSERT_FALSE(past.ok());
  EXPECT_TRUE(startsWith(past.error().message, url() + ": ")) << past.error().message;
  EXPECT_NE(past.error().message.find("past the end"), std::string::npos);
  EXPECT_EQ(s.stats().requests, before.requests) << "refused without asking the server";

  const SourceStats st = s.stats();
  EXPECT_EQ(st.requests, 1u + 1 + 60 + 1);
  EXPECT_EQ(st.bytesRead, asked + 1) << "every body byte, the size probe's one included";
  EXPECT_EQ(st.retries, 0u);
  EXPECT_EQ(st.failures, 1u);
  // Every request was a range request (nginx logged the Range header).
  EXPECT_EQ(mServer->requestsFor("/gully.tlod 206 bytes=", st.requests), st.requests)
      << mServer->accessLog();
}

TEST_F(Http, ConcurrentReadsFromManyThreads) {
  auto opened = openHttpSource(url());
  ASSERT_TRUE(opened.ok()) << opened.error().message;
  const ByteSource& s = **opened;
  std::atomic<int> wrong{0}, failed{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      std::mt19937_64 random(t);
      for (int i = 0; i < 40; ++i) {
        const uint64_t offset = random() % mBytes.size();
        const uint64_t length = 1 + random() % std::min<uint64_t>(mBytes.size() - offset, 20000);
        auto part = s.read(offset, length);
        if (!part.ok())
          ++failed;
        else if (!std::equal(part->begin(), part->end(), mBytes.begin() + offset))
          ++wrong;
      }
    });
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(failed.load(), 0);
  EXPECT_EQ(wrong.load(), 0);
  EXPECT_EQ(s.stats().requests, 1u + 4 * 40);
}

void expectSameChunk(const ChunkData& a, const ChunkData& b, uint32_t node) {
  EXPECT_EQ(a.bytesRead, b.bytesRead) << node;
  EXPECT_EQ(a.geometry.zBase, b.geometry.zBase) << node;
  EXPECT_EQ(a.geometry.zStep, b.geometry.zStep) << node;
  ASSERT_EQ(a.geometry.parts.size(), b.geometry.parts.size()) << node;
  for (size_t p = 0; p < a.geometry.parts.size(); ++p) {
    EXPECT_TRUE(a.geometry.parts[p].vertices == b.geometry.parts[p].vertices) << node;
    EXPECT_TRUE(a.geometry.parts[p].indices == b.geometry.parts[p].indices) << node;
    EXPECT_EQ(a.geometry.parts[p].surfaceIndexCount, b.geometry.parts[p].surfaceIndexCount);
  }
  ASSERT_EQ(a.texture.has_value(), b.texture.has_value()) << node;
  if (!a.texture) return;
  ASSERT_EQ(a.texture->layers.size(), b.texture->layers.size()) << node;
  for (size_t l = 0; l < a.texture->layers.size(); ++l) {
    EXPECT_EQ(a.texture->layers[l].size, b.texture->layers[l].size) << node;
    EXPECT_TRUE(a.texture->layers[l].mips == b.texture->layers[l].mips) << node;
  }
}

TEST_F(Http, TilesetReaderReadsEveryChunkLikeTheLocalFile) {
  auto local = TilesetReader::openFile(mLocal);
  ASSERT_TRUE(local.ok()) << local.error().message;
  auto source = openByteSource(url());
  ASSERT_TRUE(source.ok()) << source.error().message;
  auto remote = TilesetReader::open(std::move(source).value());
  ASSERT_TRUE(remote.ok()) << remote.error().message;
  const TilesetReader& a = **local;
  const TilesetReader& b = **remote;
  EXPECT_EQ(b.name(), url());
  EXPECT_TRUE(b.header().textured());
  EXPECT_EQ(a.header().nodeCount, b.header().nodeCount);
  EXPECT_EQ(a.metadataJson(), b.metadataJson());
  ASSERT_EQ(a.nodes().size(), b.nodes().size());
  ASSERT_GT(a.nodes().size(), 1u);
  for (uint32_t i = 0; i < a.nodes().size(); ++i) {
    auto ca = a.readChunkData(i);
    auto cb = b.readChunkData(i);
    ASSERT_TRUE(ca.ok()) << ca.error().message;
    ASSERT_TRUE(cb.ok()) << cb.error().message;
    expectSameChunk(*ca, *cb, i);
  }
  const SourceStats st = b.source().stats();
  EXPECT_EQ(st.requests, 1u + 3 + a.nodes().size()) << "size, header, nodes, metadata, chunks";
  EXPECT_EQ(st.retries, 0u);
  EXPECT_EQ(st.failures, 0u);
}

TEST_F(Http, NotFoundFailsAtOnceWithOneClearError) {
  const auto start = Clock::now();
  auto missing = openHttpSource(url("missing.tlod"), fastRetries(4));
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message, url("missing.tlod") + ": HTTP 404 Not Found");
  EXPECT_LT(secondsSince(start), 2.0);
  EXPECT_EQ(mServer->requestsFor("/missing.tlod "), 1u) << "a 404 is not retried";

  // The file disappears after opening: reads fail the same way, without retries.
  auto opened = openHttpSource(url(), fastRetries(4));
  ASSERT_TRUE(opened.ok()) << opened.error().message;
  fs::remove(mLocal);
  auto read = (*opened)->read(100, 200);
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.error().message, url() + ": HTTP 404 Not Found (bytes 100-299)");
  const SourceStats st = (*opened)->stats();
  EXPECT_EQ(st.requests, 2u);
  EXPECT_EQ(st.retries, 0u);
  EXPECT_EQ(st.failures, 1u);
}

TEST_F(Http, AFileReplacedOnTheServerIsNotMixedWithTheOldOne) {
  auto opened = openHttpSource(url(), fastRetries(4));
  ASSERT_TRUE(opened.ok()) << opened.error().message;
  fs::copy_file(testData("golden/v1/gully.tlod"), mLocal, fs::copy_options::overwrite_existing);
  const uint64_t newSize = fs::file_size(mLocal);
  ASSERT_NE(newSize, mBytes.size());
  auto read = (*opened)->read(0, 100);
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.error().message, url() + ": changed on the server: was " +
                                      std::to_string(mBytes.size()) + " bytes, now " +
                                      std::to_string(newSize) + " (bytes 0-99)");
  EXPECT_EQ((*opened)->stats().retries, 0u);
}

TEST_F(Http, ServerErrorsAreRetriedThenFailNamingUrlAndStatus) {
  const std::string u = url("status500/gully.tlod");
  auto opened = openHttpSource(u, fastRetries(3));
  ASSERT_FALSE(opened.ok());
  const std::string& m = opened.error().message;
  EXPECT_EQ(m, u + ": HTTP 500 Internal Server Error (gave up after 3 retries)");
  EXPECT_EQ(mServer->requestsFor("/status500/gully.tlod 500", 4), 4u) << mServer->accessLog();
}

TEST_F(Http, ConnectionResetsAreRetriedThenFailCleanly) {
  const std::string u = url("reset/gully.tlod");
  auto opened = openHttpSource(u, fastRetries(2));
  ASSERT_FALSE(opened.ok());
  const std::string& m = opened.error().message;
  EXPECT_TRUE(startsWith(m, u + ": ")) << m;
  EXPECT_NE(m.find("(gave up after 2 retries)"), std::string::npos) << m;
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  EXPECT_EQ(mServer->requestsFor("/reset/gully.tlod 444", 3), 3u) << mServer->accessLog();
}

TEST_F(Http, AServerIgnoringRangesIsRefused) {
  const std::string u = url("noranges/gully.tlod");
  auto opened = openHttpSource(u, fastRetries(3));
  ASSERT_FALSE(opened.ok());
  EXPECT_EQ(opened.error().message,
            u + ": server does not support range requests (HTTP 200 to a range request)");
  EXPECT_EQ(mServer->requestsFor("/noranges/gully.tlod 200"), 1u) << "not retried";
}

TEST_F(Http, ASlowServerFailsWithinTheRequestTimeout) {
  HttpOptions o = fastRetries(1);
  o.requestTimeoutSeconds = 0.5;
  auto opened = openHttpSource(url("slow/gully.tlod"), o);  // one byte: quick even at 2 KB/s
  ASSERT_TRUE(opened.ok()) << opened.error().message;
  const auto start = Clock::now();
  auto read = (*opened)->read(0, mBytes.size());  // 30 s at 2 KB/s
  const double seconds = secondsSince(start);
  ASSERT_FALSE(read.ok());
  const std::string& m = read.error().message;
  EXPECT_TRUE(startsWith(m, url("slow/gully.tlod") + ": ")) << m;
  EXPECT_NE(m.find("timed out"), std::string::npos) << m;
  EXPECT_NE(m.find("gave up after 1 retry)"), std::string::npos) << m;
  EXPECT_GE(seconds, 2 * 0.5 - 0.05) << "two attempts of 0.5 s each";
  EXPECT_LT(seconds, 3.0);
  EXPECT_EQ((*opened)->stats().retries, 1u);
  EXPECT_EQ((*opened)->stats().failures, 1u);
}

TEST_F(Http, AStalledTransferIsAbortedByTheLowSpeedLimit) {
  HttpOptions o = fastRetries(0);
  o.lowSpeedBytesPerSecond = 50000;
  o.lowSpeedSeconds = 1;
  auto opened = openHttpSource(url("slow/gully.tlod"), o);
  ASSERT_TRUE(opened.ok()) << opened.error().message;
  const auto start = Clock::now();
  auto read = (*opened)->read(0, mBytes.size());
  const double seconds = secondsSince(start);
  ASSERT_FALSE(read.ok());
  EXPECT_TRUE(startsWith(read.error().message, url("slow/gully.tlod") + ": "));
  EXPECT_NE(read.error().message.find("too slow"), std::string::npos) << read.error().message;
  EXPECT_LT(seconds, 4.0) << "the request timeout is 5 s; the low-speed limit acts first";
}

TEST_F(Http, AServerStoppedMidwayFailsCleanlyAndReadsResumeWhenItIsBack) {
  auto local = TilesetReader::openFile(mLocal);
  ASSERT_TRUE(local.ok()) << local.error().message;
  auto source = openHttpSource(url(), fastRetries(2));
  ASSERT_TRUE(source.ok()) << source.error().message;
  auto remote = TilesetReader::open(std::move(source).value());
  ASSERT_TRUE(remote.ok()) << remote.error().message;
  const TilesetReader& r = **remote;
  ASSERT_TRUE(r.readChunkData(0).ok());

  mServer->stop();
  const auto start = Clock::now();
  auto failed = r.readChunkData(1);
  ASSERT_FALSE(failed.ok());
  const std::string& m = failed.error().message;
  EXPECT_TRUE(startsWith(m, url() + ": ")) << m;
  EXPECT_NE(m.find("(bytes "), std::string::npos) << m;
  EXPECT_NE(m.find("gave up after 2 retries)"), std::string::npos) << m;
  EXPECT_LT(secondsSince(start), 2.0);
  SourceStats st = r.source().stats();
  EXPECT_EQ(st.retries, 2u);
  EXPECT_EQ(st.failures, 1u);

  ASSERT_TRUE(mServer->start()) << mServer->error();  // the same port
  auto again = r.readChunkData(1);
  ASSERT_TRUE(again.ok()) << again.error().message;
  auto expected = (*local)->readChunkData(1);
  ASSERT_TRUE(expected.ok());
  expectSameChunk(*expected, *again, 1);
}

TEST_F(Http, OpenByteSourceDispatchesOnTheScheme) {
  auto remote = openByteSource(url());
  ASSERT_TRUE(remote.ok()) << remote.error().message;
  EXPECT_EQ((*remote)->stats().requests, 1u);
  auto upper =
      openByteSource("HTTP://127.0.0.1:" + std::to_string(mServer->port()) + "/gully.tlod");
  ASSERT_TRUE(upper.ok()) << upper.error().message;
  EXPECT_EQ((*upper)->size(), mBytes.size());
  auto file = openByteSource(mLocal);
  ASSERT_TRUE(file.ok()) << file.error().message;
  EXPECT_EQ((*file)->size(), mBytes.size());
  EXPECT_EQ((*file)->stats().requests, 0u) << "a file source";
  auto nothing = openByteSource(mWww.file("nothing.tlod"));
  ASSERT_FALSE(nothing.ok());
  EXPECT_EQ(nothing.error().message, mWww.file("nothing.tlod") + ": no such file");

  // Credentials are used but never shown.
  const std::string withPassword =
      "http://reader:s3cret@127.0.0.1:" + std::to_string(mServer->port()) + "/missing.tlod";
  auto hidden = openByteSource(withPassword);
  ASSERT_FALSE(hidden.ok());
  EXPECT_EQ(hidden.error().message, url("missing.tlod") + ": HTTP 404 Not Found");
}

TEST_F(Http, NothingListensFailsCleanly) {
  const std::string u = url();
  mServer->stop();
  auto opened = openHttpSource(u, fastRetries(1));
  ASSERT_FALSE(opened.ok());
  EXPECT_TRUE(startsWith(opened.error().message, u + ": ")) << opened.error().message;
  EXPECT_NE(opened.error().message.find("(gave up after 1 retry)"), std::string::npos)
      << opened.error().message;
}

TEST_F(Http, CliInfoOverHttpPrintsWhatItPrintsForTheFile) {
  for (const bool json : {false, true}) {
    std::vector<std::string> localArgs = {"info", mLocal}, remoteArgs = {"info", url()};
    if (json) {
      localArgs.push_back("--json");
      remoteArgs.push_back("--json");
    }
    const RunResult a = runTerralod(localArgs);
    const RunResult b = runTerralod(remoteArgs);
    ASSERT_EQ(a.exitCode, 0) << a.err;
    ASSERT_EQ(b.exitCode, 0) << b.err;
    std::string expected = a.out;
    for (size_t at; (at = expected.find(mLocal)) != std::string::npos;)
      expected.replace(at, mLocal.size(), url());
    EXPECT_EQ(b.out, expected);
    EXPECT_GT(b.out.size(), 200u);
  }
  const RunResult missing = runTerralod({"info", url("missing.tlod")});
  EXPECT_EQ(missing.exitCode, 1);
  EXPECT_EQ(missing.err, "terralod: error: " + url("missing.tlod") + ": HTTP 404 Not Found\n");
}

TEST_F(Http, CliVerifyOverHttpChecksWhatItChecksForTheFile) {
  const std::string dem = testData("landlab_west_bijou_gully_3m.asc");
  const RunResult a = runTerralod({"verify", mLocal, "--source", dem});
  const RunResult b = runTerralod({"verify", url(), "--source", dem});
  ASSERT_EQ(a.exitCode, 0) << a.out << a.err;
  ASSERT_EQ(b.exitCode, 0) << b.out << b.err;
  std::string expected = a.out;
  for (size_t at; (at = expected.find(mLocal)) != std::string::npos;)
    expected.replace(at, mLocal.size(), url());
  EXPECT_EQ(b.out, expected);
}

TEST_F(Http, CliRenderOverHttpDrawsWhatItDrawsFromTheFile) {
  TempDir out;
  const RunResult a =
      runTerralod({"render", mLocal, "-o", out.file("local.png"), "--size", "160x120"});
  const RunResult b =
      runTerralod({"render", url(), "-o", out.file("http.png"), "--size", "160x120"});
  ASSERT_EQ(a.exitCode, 0) << a.err;
  ASSERT_EQ(b.exitCode, 0) << b.err;
  auto la = readPng(out.file("local.png"));
  auto lb = readPng(out.file("http.png"));
  ASSERT_TRUE(la.ok()) << la.error().message;
  ASSERT_TRUE(lb.ok()) << lb.error().message;
  EXPECT_EQ(lb->width, 160);
  EXPECT_EQ(lb->height, 120);
  EXPECT_TRUE(la->rgba == lb->rgba) << "the same tileset over HTTP draws the same image";
  EXPECT_GT(mServer->requestsFor("/gully.tlod 206", 4), 3u);
}

}  // namespace
}  // namespace terralod::test
