// The generated colour: a palette in metres, snow by absolute height and latitude, and water
// where the ground is flat at sea level, exactly flat (lakes) or a filled sea void. Also keeps
// the legend in the README (docs/images/ground_palette.png) in step with the code.

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "terralod/build/height_source.h"
#include "terralod/build/surface_texels.h"
#include "terralod/raster/heightfield.h"
#include "terralod/raster/void_fill.h"

namespace terralod {
namespace {

bool isSnow(GroundColor c) {
  return c.r > 0.9f && c.g > 0.9f && c.b > 0.9f;
}
bool sameColor(const float* rgb, GroundColor c, float tolerance = 1e-6f) {
  return std::fabs(rgb[0] - c.r) <= tolerance && std::fabs(rgb[1] - c.g) <= tolerance &&
         std::fabs(rgb[2] - c.b) <= tolerance;
}

TEST(GroundColours, SnowLineFollowsLatitude) {
  EXPECT_NEAR(snowLine(0), 5200, 1e-9);
  EXPECT_NEAR(snowLine(46), 3011, 1);  // the Alps: ~2,800–3,000 m observed
  EXPECT_NEAR(snowLine(-46), snowLine(46), 1e-9);
  EXPECT_NEAR(snowLine(65), 1428, 1);  // Norway, Alaska: 1–1.5 km
  EXPECT_NEAR(snowLine(78), 493, 1);   // Svalbard: a few hundred metres
  EXPECT_NEAR(snowLine(90), 0, 1e-9);
  EXPECT_NEAR(snowLine(120), 0, 1e-9) << "clamped to the pole";
  EXPECT_EQ(snowLine(std::nan("")), snowLine(kUnknownLatitude));
  for (double lat = 0; lat < 90; lat += 1) EXPECT_GT(snowLine(lat), snowLine(lat + 1)) << lat;
}

// The three places of issue 18: by relative height, each summit of its DEM was white.
TEST(GroundColours, SnowByAbsoluteHeightAndLatitude) {
  EXPECT_EQ(snowCover(1579, 22), 0.0f) << "Kauai's summit is not snow-covered";
  EXPECT_FALSE(isSnow(groundColor(1579, 0, 22)));
  EXPECT_EQ(snowCover(160, 65), 0.0f) << "bumps of 160 m at 65°N are not snow-covered";
  EXPECT_FALSE(isSnow(groundColor(160, 0, 65)));
  EXPECT_EQ(snowCover(5000, 46), 1.0f) << "5,000 m in the Alps is";
  EXPECT_TRUE(isSnow(groundColor(5000, 0, 46)));
  // ... unless too steep to hold snow.
  EXPECT_FALSE(isSnow(groundColor(5000, 0.9f, 46)));
  // Between, a gradual edge 400 m wide above the line.
  EXPECT_GT(snowCover(snowLine(46) + 200, 46), 0.2f);
  EXPECT_LT(snowCover(snowLine(46) + 200, 46), 0.8f);
}

TEST(GroundColours, PaletteIsInMetresNotRelative) {
  // Lowland is green (more green than red or blue) and never the water colour.
  for (double h : {-20.0, 0.0, 50.0, 300.0}) {
    const GroundColor c = groundColor(h, 0, 45);
    EXPECT_GT(c.g, c.r) << h;
    EXPECT_GT(c.g, c.b) << h;
    EXPECT_GT(std::fabs(c.r - kWaterColor.r), 0.15f) << h;
  }
  // High ground below the snow line is rock: no longer green.
  const GroundColor rock = groundColor(3500, 0, 10);
  EXPECT_GE(rock.r, rock.g);
  EXPECT_FALSE(isSnow(rock));
}

// A block of heights in memory, with its texels.
struct Block {
  Heightfield heights;
  SurfaceTexelOptions options;
  std::unique_ptr<MemoryHeights> source;
  TexelTile colors{1, 3};

  explicit Block(Heightfield h, double latitude = 45) : heights(std::move(h)) {
    options.spacingX = options.spacingY = 30;
    options.columns = heights.columns();
    options.rows = heights.rows();
    options.rowLatitudes =
        std::make_shared<const std::vector<double>>(size_t(heights.rows()), latitude);
  }
  void texels() {
    source = std::make_unique<MemoryHeights>(heights);
    BlockTexels t(options);
    const int32_t cells = std::max(heights.columns(), heights.rows()) - 1;
    ASSERT_TRUE(t.load(*source, 0, nullptr, 0, 0, cells).ok());
    colors = t.colors(0, 0, cells);
  }
  bool water(int32_t x, int32_t y) const {
    return sameColor(colors.at(uint32_t(x), uint32_t(y)), kWaterColor);
  }
};

// West: sea at 0 m; east: land rising from 2 m, rough; a flat lake at 250.0 m; a single 0 m
// sample on land; and 0 m along the east edge beside 20 m land.
Heightfield coast() {
  Heightfield h(96, 96);
  for (int32_t y = 0; y < 96; ++y)
    for (int32_t x = 0; x < 96; ++x)
      h(x, y) = x < 40 ? 0.0f : 2.0f + 6.0f * (x - 40) + 1.5f * float((x * 7 + y * 13) % 5);
  for (int32_t y = 60; y < 75; ++y)
    for (int32_t x = 70; x < 85; ++x) h(x, y) = 250.0f;
  h(60, 20) = 0.0f;
  for (int32_t y = 10; y < 30; ++y) h(95, y) = 0.0f, h(94, y) = 20.0f;
  return h;
}

TEST(GroundColours, SeaAtSeaLevelIsWater) {
  Block b(coast());
  b.texels();
  for (int32_t y = 0; y < 96; ++y)
    for (int32_t x = 0; x < 40; ++x) ASSERT_TRUE(b.water(x, y)) << x << "," << y;
  for (int32_t y = 0; y < 96; ++y)
    for (int32_t x = 40; x < 96; ++x) {
      const bool lake = x >= 70 && x < 85 && y >= 60 && y < 75;
      ASSERT_EQ(b.water(x, y), lake) << x << "," << y << " at " << b.heights(x, y) << " m";
    }
}

TEST(GroundColours, WaterNeedsAFlatWindowInsideTheData) {
  // A strip of 0 m four samples wide and rough land 0.6 m up are not sea, nor is a column of
  // 0 m along the east edge (edge replication must not stand in for the data's missing side).
  Heightfield h(64, 64);
  for (int32_t y = 0; y < 64; ++y) {
    for (int32_t x = 0; x < 64; ++x) h(x, y) = 30.0f + float((x * 7 + y * 3) % 4);
    if (y >= 20 && y < 40) h(63, y) = 0.0f;
    for (int32_t x = 10; x < 14; ++x) h(x, y) = 0.0f;
    for (int32_t x = 30; x < 50; ++x) h(x, y) = 0.6f + 0.3f * float((x + y) % 2);
  }
  Block b(h);
  b.texels();
  for (int32_t y = 0; y < 64; ++y)
    for (int32_t x = 0; x < 64; ++x) ASSERT_FALSE(b.water(x, y)) << x << "," << y;
}

TEST(GroundColours, FilledSeaVoidsAreWater) {
  // Sea left as nodata along the west edge, filled by the void filler before colouring.
  Heightfield h(80, 80);
  for (int32_t y = 0; y < 80; ++y)
    for (int32_t x = 0; x < 80; ++x) h(x, y) = x < 25 ? NAN : 1.0f + 9.0f * (x - 25);
  const SampleMask sea = seaVoids(h);
  ASSERT_EQ(sea.count(), 25u * 80u);
  ASSERT_TRUE(fillVoids(h, "test").ok());
  Block b(h);
  b.texels();
  EXPECT_FALSE(b.water(10, 40)) << "without the mask, a filled sea is land";
  b.options.seaVoids = std::make_shared<const SampleMask>(sea);
  b.texels();
  for (int32_t y = 0; y < 80; ++y)
    for (int32_t x = 0; x < 80; ++x) ASSERT_EQ(b.water(x, y), x < 25) << x << "," << y;
}

// Issue 18's flat DEM at 64.8°N, 127–163 m: its bumps were white. Now no texel is snow, and
// a summit of 1,579 m at 22°N has none either; 5,000 m at 46°N is white.
TEST(GroundColours, NoSnowOnLowBumpsOrTropicalSummits) {
  auto snowTexels = [](float base, float amplitude, double latitude) {
    Heightfield h(64, 64);
    for (int32_t y = 0; y < 64; ++y)
      for (int32_t x = 0; x < 64; ++x)
        h(x, y) = base +
                  amplitude * float(std::exp(-((x - 32) * (x - 32) + (y - 32) * (y - 32)) / 300.0));
    Block b(h, latitude);
    b.options.spacingX = 200;  // gentle slopes: snow would hold
    b.options.spacingY = 200;
    b.texels();
    int n = 0;
    for (size_t i = 0; i < b.colors.values.size(); i += 3)
      n += isSnow({b.colors.values[i], b.colors.values[i + 1], b.colors.values[i + 2]});
    return n;
  };
  EXPECT_EQ(snowTexels(127, 36, 64.8), 0);
  EXPECT_EQ(snowTexels(600, 979, 22), 0);
  EXPECT_GT(snowTexels(3000, 2000, 46), 50);
}

// ---------------------------------------------------------------------------------------------
// The legend: columns are heights 0–6,000 m (10 m a pixel) after a water swatch of 40 pixels;
// rows are latitudes from the equator (top) to the pole (bottom), half a degree a pixel; dark
// ticks every 1,000 m along the top and every 15° along the left of the heights.

constexpr int kLegendWidth = 640, kLegendHeight = 180, kSwatch = 40;

std::vector<uint8_t> legend() {
  std::vector<uint8_t> rgb(size_t(kLegendWidth) * kLegendHeight * 3);
  auto byte = [](float v) { return uint8_t(std::clamp(v * 255.0f + 0.5f, 0.0f, 255.0f)); };
  for (int y = 0; y < kLegendHeight; ++y) {
    const double latitude = (y + 0.5) * 0.5;
    for (int x = 0; x < kLegendWidth; ++x) {
      GroundColor c = kWaterColor;
      if (x >= kSwatch) {
        const int metres = (x - kSwatch) * 10;
        c = groundColor(metres + 5.0, 0, latitude);
        const bool heightTick = metres % 1000 == 0 && y < 6;
        const bool latitudeTick = y % 30 == 0 && x < kSwatch + 6;
        if (heightTick || latitudeTick) c = {0.15f, 0.15f, 0.15f};
      }
      uint8_t* p = &rgb[(size_t(y) * kLegendWidth + x) * 3];
      p[0] = byte(c.r);
      p[1] = byte(c.g);
      p[2] = byte(c.b);
    }
  }
  return rgb;
}

const std::string kLegendPath =
    std::string(TERRALOD_TEST_DATA) + "/../../docs/images/ground_palette.png";

TEST(GroundColours, LegendInTheReadmeIsUpToDate) {
  GDALAllRegister();
  std::vector<uint8_t> expected = legend();
  if (std::getenv("TERRALOD_WRITE_LEGEND")) {
    // Regenerate: TERRALOD_WRITE_LEGEND=1 build_tests --gtest_filter=*Legend*
    GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
    GDALDriver* png = GetGDALDriverManager()->GetDriverByName("PNG");
    ASSERT_TRUE(mem && png);
    GDALDatasetUniquePtr image(mem->Create("", kLegendWidth, kLegendHeight, 3, GDT_Byte, nullptr));
    ASSERT_EQ(
        image->RasterIO(GF_Write, 0, 0, kLegendWidth, kLegendHeight, expected.data(), kLegendWidth,
                        kLegendHeight, GDT_Byte, 3, nullptr, 3, 3 * kLegendWidth, 1, nullptr),
        CE_None);
    GDALDatasetUniquePtr out(
        png->CreateCopy(kLegendPath.c_str(), image.get(), FALSE, nullptr, nullptr, nullptr));
    ASSERT_TRUE(out);
    out.reset();
    std::filesystem::remove(kLegendPath + ".aux.xml");
  }
  GDALDatasetUniquePtr stored(GDALDataset::Open(kLegendPath.c_str(), GDAL_OF_RASTER));
  ASSERT_TRUE(stored) << kLegendPath << " is missing: run with TERRALOD_WRITE_LEGEND=1";
  ASSERT_EQ(stored->GetRasterXSize(), kLegendWidth);
  ASSERT_EQ(stored->GetRasterYSize(), kLegendHeight);
  std::vector<uint8_t> actual(expected.size());
  ASSERT_EQ(
      stored->RasterIO(GF_Read, 0, 0, kLegendWidth, kLegendHeight, actual.data(), kLegendWidth,
                       kLegendHeight, GDT_Byte, 3, nullptr, 3, 3 * kLegendWidth, 1, nullptr),
      CE_None);
  size_t off = 0;
  for (size_t i = 0; i < actual.size(); ++i) off += std::abs(int(actual[i]) - int(expected[i])) > 1;
  EXPECT_EQ(off, 0u) << "docs/images/ground_palette.png no longer shows the palette: run "
                        "TERRALOD_WRITE_LEGEND=1 build_tests --gtest_filter=*Legend*";
}

}  // namespace
}  // namespace terralod
