#include "terralod/vegetation/ldi_baker.h"

#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "terralod/vegetation/ldi_camera.h"
#include "terralod/vegetation/vegetation_bake.h"
#include "terralod/vegetation/wang_tiling.h"

namespace terralod::veg {
namespace {

// A "plant" of two horizontal squares, 1 m wide, centred on its axis: red at z = 0.5,
// green at z = 1.0.
PlantMesh twoSquares() {
  PlantMesh m;
  auto square = [&](float z, std::array<uint8_t, 3> colour) {
    const uint32_t b = uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(),
                       {{-0.5f, -0.5f, z}, {0.5f, -0.5f, z}, {0.5f, 0.5f, z}, {-0.5f, 0.5f, z}});
    m.triangles.push_back({b, b + 1, b + 2});
    m.triangles.push_back({b, b + 2, b + 3});
    m.colors.insert(m.colors.end(), 2, colour);
  };
  square(0.5f, {255, 0, 0});
  square(1.0f, {0, 255, 0});
  m.tightRadius = std::sqrt(0.5f);
  m.height = 1;
  return m;
}

PlantLibrary analyticLibrary() {
  std::array<std::vector<PlantMesh>, kSpeciesCount> meshes;
  for (int s = 0; s < kSpeciesCount; ++s) meshes[s].assign(versionCount(Species(s)), twoSquares());
  return PlantLibrary(meshes);
}

// Looks straight down on the 4 m tile, 40 pixels across.
LdiCamera topDown() {
  LdiCamera c;
  c.width = c.height = 40;
  c.pixelSize = 0.1f;
  c.origin = {0, 0, 0};
  c.axisU = {1, 0, 0};
  c.axisV = {0, 1, 0};
  c.direction = {0, 0, -1};
  c.depthMin = -2;  // the image plane is 2 m up
  c.depthMax = 0.01f;
  return c;
}

float depthOf(const LdiCamera& c, const DepthPixel& p) {
  return c.depthMin + float(p.depth()) * (c.depthMax - c.depthMin) / float(kLdiMaxDepth);
}

TEST(LdiBaker, EverySurfaceARayCrossesIsALayerNearestFirstAndOnlyInTheCentreTile) {
  // Prototile 0 holds one plant at (1, 1); the tile west of the centre holds one at (3.8, 2)
  // whose squares reach 0.3 m into the centre tile.
  std::vector<PrototileContent> tiles(kWangPrototiles);
  for (int k = 0; k < kWangPrototiles; ++k) tiles[k].edges = prototileEdges(k);
  PlacedObject a;
  a.x = 1, a.y = 1, a.tightRadius = 0.71f, a.packingRadius = 0.8f;
  tiles[0].objects.push_back(a);
  PlacedObject b = a;
  b.x = 3.8f, b.y = 2;
  tiles[1].objects.push_back(b);
  const std::array<int, 9> context = {2, 2, 2, 1, 0, 2, 2, 2, 2};
  const PlantLibrary plants = analyticLibrary();
  const ContextScene scene(tiles, context, 4, plants);
  EXPECT_EQ(scene.trianglesInCentre(), 4u);
  Lighting noShade;
  noShade.occlusionRays = 0;
  SamplingSettings sampling;
  uint64_t rays = 0;
  const LdiCamera cam = topDown();
  const Ldi ldi = scene.bake(cam, sampling, noShade, rays);
  EXPECT_GE(rays, 40u * 40u * 4u);  // 4 a pixel, and the sun rays of lit layers
  auto layersAt = [&](float x, float y) {
    const uint32_t col = uint32_t(x / 0.1f), row = uint32_t(y / 0.1f);
    size_t first = 0;
    for (size_t i = 0; i < size_t(row) * 40 + col; ++i) first += ldi.layerCounts[i];
    return std::vector<DepthPixel>(ldi.pixels.begin() + first,
                                   ldi.pixels.begin() + first + ldi.layerCounts[row * 40 + col]);
  };
  const auto inside = layersAt(1.05f, 1.05f);  // under plant a
  ASSERT_EQ(inside.size(), 2u);
  // Depth runs along the camera's direction (down) from the ground: z = −depth.
  EXPECT_NEAR(depthOf(cam, inside[0]), -1.0f, 1e-3);             // green, 1 m up
  EXPECT_NEAR(depthOf(cam, inside[1]), -0.5f, 1e-3);             // red, below it
  EXPECT_GT(inside[0].rgba >> 8 & 0xff, inside[0].rgba & 0xff);  // green over red
  EXPECT_GT(inside[1].rgba & 0xff, inside[1].rgba >> 8 & 0xff);
  EXPECT_EQ(inside[0].rgba >> 24, 255u);  // every ray of the pixel met it
  EXPECT_NEAR(decodeSplatNormal(inside[0].splat()).z, 1.0f, 0.02f);  // faces the viewer (up)
  EXPECT_EQ(layersAt(2.55f, 2.55f).size(), 0u);                      // bare ground
  EXPECT_EQ(layersAt(0.15f, 2.05f).size(), 2u);  // plant b, leaning in from the west
  EXPECT_EQ(layersAt(0.45f, 2.05f).size(), 0u);  // beyond plant b's reach
  // Plant b's part west of the centre tile would be at x < 0: outside the image. Plant a's
  // squares are 1 m wide: 10 × 10 pixels of 2 layers, plus b's 3 × 10.
  size_t twoLayer = 0;
  for (uint8_t c : ldi.layerCounts) twoLayer += c == 2;
  EXPECT_EQ(twoLayer, 100u + 30u);
}

TEST(LdiBaker, AHalfCoveredPixelHasHalfAlphaAndSunlessFacesAreDarker) {
  std::vector<PrototileContent> tiles(kWangPrototiles);
  for (int k = 0; k < kWangPrototiles; ++k) tiles[k].edges = prototileEdges(k);
  PlacedObject a;
  a.x = 1.05f, a.y = 1.0f, a.tightRadius = 0.71f, a.packingRadius = 0.8f;  // edge mid-pixel
  tiles[0].objects.push_back(a);
  const PlantLibrary plants = analyticLibrary();
  const ContextScene scene(tiles, {2, 2, 2, 2, 0, 2, 2, 2, 2}, 4, plants);
  SamplingSettings sampling;
  sampling.raysPerPixel = 16;
  Lighting light;
  light.occlusionRays = 16;
  uint64_t rays = 0;
  const LdiCamera cam = topDown();
  const Ldi ldi = scene.bake(cam, sampling, light, rays);
  size_t first = 0;
  const size_t edge = 10 * 40 + 5;  // column 5 spans x 0.5–0.6: half covered (x ≥ 0.55)
  for (size_t i = 0; i < edge; ++i) first += ldi.layerCounts[i];
  ASSERT_GE(ldi.layerCounts[edge], 1);
  EXPECT_NEAR(double(ldi.pixels[first].rgba >> 24), 127.5, 40);
  // The top square is lit by the sun and open to the sky; the lower one is in its shadow.
  const size_t centre = 10 * 40 + 10;
  first = 0;
  for (size_t i = 0; i < centre; ++i) first += ldi.layerCounts[i];
  ASSERT_EQ(ldi.layerCounts[centre], 2);
  const uint32_t top = ldi.pixels[first].rgba >> 8 & 0xff,
                 lower = ldi.pixels[first + 1].rgba & 0xff;
  EXPECT_GT(top, 200u);
  EXPECT_LT(double(lower), 0.6 * top);
}

TEST(LdiCameras, FrameTheTileBoxFromEachDirectionAtEachRing) {
  LdiRig rig;
  rig.tileSize = 4;
  rig.tileHeight = 2;
  rig.ringDistances = ringDistancesFor(4, rig.resolutions);
  EXPECT_FLOAT_EQ(rig.ringDistances[0], 4);
  EXPECT_NEAR(rig.ringDistances[6], 4 * 468.0 / 62.0, 1e-4);
  for (int ring = 0; ring < kRings; ++ring)
    for (int d = 0; d < kDirections; ++d) {
      const LdiCamera c = ldiCamera(rig, ring, d);
      EXPECT_EQ(std::max(c.width, c.height), rig.resolutions[ring]);
      // Every corner of the tile box projects inside the image and depth range.
      for (int k = 0; k < 8; ++k) {
        const glm::vec3 p{k & 1 ? 4.f : 0.f, k & 2 ? 4.f : 0.f, k & 4 ? 2.f : 0.f};
        const glm::vec3 q = p - c.origin;
        const float u = glm::dot(q, c.axisU) / c.pixelSize, v = glm::dot(q, c.axisV) / c.pixelSize;
        const float t = glm::dot(p, c.direction);
        EXPECT_GE(u, -1e-3f);
        EXPECT_LE(u, c.width + 1e-3f);
        EXPECT_GE(v, -1e-3f);
        EXPECT_LE(v, c.height + 1e-3f);
        EXPECT_GT(t, c.depthMin);
        EXPECT_LT(t, c.depthMax);
      }
      EXPECT_LT(c.direction.z, 0);  // looking down at the tile
    }
  // Direction 0 looks north, 2 east.
  EXPECT_GT(ldiCamera(rig, 0, 0).direction.y, 0.5f);
  EXPECT_GT(ldiCamera(rig, 0, 2).direction.x, 0.5f);
}

TEST(LdiCameras, ContextsAreValidTilingsAroundTheirTile) {
  for (int k = 0; k < kWangPrototiles; ++k) {
    const std::array<int, 9> c = contextAround(k, 5);
    EXPECT_EQ(c[4], k);
    LaidTiling t{3, 3, std::vector<uint8_t>(c.begin(), c.end())};
    EXPECT_TRUE(tilingIsValid(t));
  }
}

}  // namespace
}  // namespace terralod::veg

namespace terralod::veg {
namespace {

TEST(VegetationBake, GivesTheSameFileBytesWithAnyThreadCount) {
  auto scene = vegetationScene("meadow", std::nullopt, 3);
  ASSERT_TRUE(scene);
  scaleResolutions(scene->rig, 16);
  scene->sampling.raysPerPixel = 1;
  scene->lighting.occlusionRays = 2;
  NullProgress quiet;
  const VegetationBake one = bakeVegetation(*scene, 1, quiet);
  const VegetationBake two = bakeVegetation(*scene, 2, quiet);
  ASSERT_EQ(one.ldis.size(), size_t(kLdiCount));
  EXPECT_EQ(one.header.tiles, two.header.tiles);
  uint64_t depthPixels = 0;
  for (int i = 0; i < kLdiCount; ++i) {
    EXPECT_EQ(one.ldis[i].blob, two.ldis[i].blob) << tlv::describeLdi(i);
    depthPixels += one.ldis[i].depthPixels;
  }
  EXPECT_GT(depthPixels, 1000u);
  // Another seed places and casts differently.
  auto other = vegetationScene("meadow", std::nullopt, 4);
  scaleResolutions(other->rig, 16);
  other->sampling.raysPerPixel = 1;
  other->lighting.occlusionRays = 2;
  EXPECT_NE(bakeVegetation(*other, 2, quiet).header.tiles, one.header.tiles);
}

}  // namespace
}  // namespace terralod::veg
