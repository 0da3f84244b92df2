#include "terralod/vipm/vipm_storage.h"

#include <gtest/gtest.h>

#include <random>

#include "terralod/format/vipm_chunk_codec.h"
#include "terralod/vipm/vipm_levels.h"
#include "vipm_test_patches.h"

namespace terralod {
namespace {

struct Stored {
  GridPatch patch;
  ProgressiveMesh mesh;
  HeightQuantisation q;
  std::vector<uint8_t> blob;
};

Stored store(double maxError) {
  Stored s;
  s.patch = test::demPatch("zion_srtm3_utm12_30m.tif", 320, 640, 1500, 1800, 65);
  s.q = chooseQuantisation(s.patch, maxError);
  quantiseVertexHeights(s.patch, s.q);
  s.mesh = makeProgressiveMesh(s.patch, buildCollapseOrder(s.patch, MaterialRules::kOn), maxError);
  s.blob = encodeVipmChunk(packChunk(s.patch, s.mesh, s.q), 3);
  return s;
}

TEST(VipmStorage, RoundTripsTheMeshWithErrorsRoundedUp) {
  const Stored s = store(1.0);
  EXPECT_LE(s.q.zStep, 1.0 / 8);
  auto decoded = decodeVipmChunk(s.blob, "chunk");
  ASSERT_TRUE(decoded.ok()) << decoded.error().message;
  const UnpackedChunk u = unpackChunk(*decoded);
  EXPECT_EQ(u.mesh.points, s.mesh.points);
  EXPECT_EQ(u.mesh.targets, s.mesh.targets);
  // The index codec may rotate a triangle's corners (never reverse them).
  auto rotated = [](std::array<uint16_t, 3> t) {
    while (t[0] > t[1] || t[0] > t[2]) t = {t[1], t[2], t[0]};
    return t;
  };
  ASSERT_EQ(u.mesh.triangles.size(), s.mesh.triangles.size());
  for (size_t t = 0; t < u.mesh.triangles.size(); ++t)
    EXPECT_EQ(rotated(u.mesh.triangles[t]), rotated(s.mesh.triangles[t]));
  ASSERT_EQ(u.mesh.errors.size(), s.mesh.errors.size());
  for (size_t j = 0; j < u.mesh.errors.size(); ++j) {
    EXPECT_GE(u.mesh.errors[j], s.mesh.errors[j]);
    EXPECT_LE(u.mesh.errors[j], s.mesh.errors[j] + s.mesh.errors.back() / 60000.0f);
  }
  EXPECT_TRUE(std::is_sorted(u.mesh.errors.begin(), u.mesh.errors.end()));
  for (uint32_t v = 0; v < u.mesh.vertexCount(); ++v) {
    const uint32_t p = u.mesh.points[v];
    EXPECT_EQ(u.positions[v][2], s.patch.vertexHeights[p]);
    EXPECT_NEAR(u.positions[v][2], s.patch.heights[p], s.q.zStep / 2 + 1e-4);
  }
  EXPECT_TRUE(VipmLevels::reconstruct(u.mesh, u.materials).ok());
  // Every level in less than plain buffers of the finest level take (8 bytes per vertex, 6 per
  // triangle).
  EXPECT_LT(s.blob.size(), 8 * s.mesh.vertexCount() + 6 * s.mesh.triangles.size());
}

// A node above the roots (a sparse patch wider than 129 points) is stored as version 2: its
// points as 32-bit grid points; it reads back as it was, and damage never crashes the reader.
TEST(VipmStorage, ANodeAboveTheRootsRoundTripsAsVersion2) {
  test::SparseStart s = test::wavySparsePatch(512, 8, 4);
  CollapseStart start;
  start.triangles = s.triangles;
  start.seamX = start.seamY = 256;
  const HeightQuantisation q{-20.0, 1.0 / 64};
  quantiseVertexHeights(s.patch, q);
  const CollapseOrder order = buildCollapseOrder(s.patch, MaterialRules::kOff, start);
  ASSERT_GT(order.collapses.size(), 1000u);
  const ProgressiveMesh mesh = makeProgressiveMesh(s.patch, order, 0.0);
  const VipmChunkData data = packChunk(s.patch, mesh, q);
  EXPECT_EQ(vipmChunkVersion(data), 2);
  const std::vector<uint8_t> blob = encodeVipmChunk(data, 3);
  auto decoded = decodeVipmChunk(blob, "node");
  ASSERT_TRUE(decoded.ok()) << decoded.error().message;
  EXPECT_EQ(decoded->width, 513);
  EXPECT_EQ(decoded->points, mesh.points);
  EXPECT_EQ(*std::max_element(mesh.points.begin(), mesh.points.end()), 513u * 513u - 1);
  EXPECT_EQ(encodeVipmChunk(*decoded, 3), blob);
  const UnpackedChunk u = unpackChunk(*decoded);
  EXPECT_TRUE(VipmLevels::reconstruct(u.mesh, u.materials).ok());
  EXPECT_EQ(u.positions.back()[0], float(mesh.points.back() % 513));

  // Damage is refused or reconstructs (checked), never a crash.
  for (size_t n = 0; n < blob.size(); n += 11)
    EXPECT_FALSE(decodeVipmChunk(std::span(blob).first(n), "c").ok());
  std::mt19937 rng(11);
  for (int i = 0; i < 300; ++i) {
    std::vector<uint8_t> b = blob;
    b[rng() % b.size()] ^= uint8_t(1u << (rng() % 8));
    if (auto d = decodeVipmChunk(b, "c"); d.ok()) {
      const UnpackedChunk damaged = unpackChunk(*d);
      (void)VipmLevels::reconstruct(damaged.mesh, damaged.materials);
    }
  }
}

// Truncations and bit flips are refused or decode to something reconstruction checks; never
// a crash (the fuzz target goes further).
TEST(VipmStorage, DamagedBlobsNeverCrash) {
  const Stored s = store(2.0);
  for (size_t n = 0; n < s.blob.size(); n += 7)
    EXPECT_FALSE(decodeVipmChunk(std::span(s.blob).first(n), "c").ok());
  std::mt19937 rng(7);
  int refused = 0;
  for (int i = 0; i < 2000; ++i) {
    std::vector<uint8_t> b = s.blob;
    b[rng() % b.size()] ^= uint8_t(1u << (rng() % 8));
    auto d = decodeVipmChunk(b, "c");
    if (!d.ok()) {
      ++refused;
      EXPECT_NE(d.error().message.find("c: corrupt VIPM chunk: "), std::string::npos);
      continue;
    }
    const UnpackedChunk u = unpackChunk(*d);
    (void)VipmLevels::reconstruct(u.mesh, u.materials);
  }
  EXPECT_GT(refused, 1000);
}

}  // namespace
}  // namespace terralod
