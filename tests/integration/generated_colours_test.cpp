// The generated colour on a real coast: Burrard Inlet, Indian Arm and Boundary Bay (SRTM 3",
// sea stored as 0 m) come out as water in the leaf textures, rough land never does; and the
// same sea stored as nodata (filled by the void filler) is water too. Water is found per
// sample, so those builds bake the colour (--bake-colour: a texel on every sample); the
// default's shade layer (half the resolution) gives the same colours where its texels lie.

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "cli_runner.h"
#include "terralod/format/node_colour.h"
#include "terralod/format/tileset_reader.h"

namespace terralod::test {
namespace {

const std::string kCoast = testData("burrard_inlet_srtm3.tif");
// kWaterColor (libs/build surface_texels.h) as stored bytes.
constexpr std::array<int, 3> kWater{77, 120, 158};

// Heights in grid order (south row first); voids as NaN.
struct Dem {
  int32_t columns = 0, rows = 0;
  std::vector<float> h;
  float at(int32_t x, int32_t y) const { return h[size_t(y) * columns + x]; }
};

Dem readDem(const std::string& path) {
  GDALAllRegister();
  GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER));
  EXPECT_TRUE(ds);
  Dem d;
  d.columns = ds->GetRasterXSize();
  d.rows = ds->GetRasterYSize();
  std::vector<float> raster(size_t(d.columns) * d.rows);
  EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, d.columns, d.rows, raster.data(),
                                           d.columns, d.rows, GDT_Float32, 0, 0),
            CE_None);
  int hasNodata = 0;
  const double nodata = ds->GetRasterBand(1)->GetNoDataValue(&hasNodata);
  d.h.resize(raster.size());
  for (int32_t y = 0; y < d.rows; ++y)
    for (int32_t x = 0; x < d.columns; ++x) {
      const float v = raster[size_t(d.rows - 1 - y) * d.columns + x];
      d.h[size_t(y) * d.columns + x] = hasNodata && v == float(nodata) ? NAN : v;
    }
  return d;
}

// Whether every grid sample's leaf texel is water (-1 where no texel lies on the sample).
std::vector<int> waterTexels(const std::string& tileset, const Dem& dem) {
  auto opened = TilesetReader::openFile(tileset);
  EXPECT_TRUE(opened.ok()) << opened.error().message;
  const TilesetReader& t = **opened;
  std::vector<int> water(dem.h.size(), -1);
  const uint32_t leaf = t.header().levelCount - 1;
  const uint32_t cells = t.header().leafCells;
  for (uint32_t i = 0; i < t.nodes().size(); ++i) {
    const NodeRecord& n = t.nodes()[i];
    if (n.level != leaf) continue;
    auto colour = readNodeColour(t, i);  // its own, or its part of its parent's
    EXPECT_TRUE(colour.ok() && !colour->rgb.empty());
    const uint32_t size = colour->size;
    const std::vector<uint8_t>& rgb = colour->rgb;
    EXPECT_EQ(rgb.size(), size_t(size) * size * 3);
    for (uint32_t j = 0; j < size; ++j)
      for (uint32_t k = 0; k < size; ++k) {
        if ((k * cells) % (size - 1) || (j * cells) % (size - 1)) continue;
        const int64_t gx = int64_t(n.x) * cells + k * cells / (size - 1);
        const int64_t gy = int64_t(n.y) * cells + j * cells / (size - 1);
        if (gx >= dem.columns || gy >= dem.rows) continue;
        const uint8_t* p = &rgb[(size_t(j) * size + k) * 3];
        bool isWater = true;
        for (int c = 0; c < 3; ++c) isWater = isWater && std::abs(p[c] - kWater[size_t(c)]) <= 12;
        water[size_t(gy) * dem.columns + size_t(gx)] = isWater ? 1 : 0;
      }
  }
  return water;
}

struct Counts {
  size_t sea = 0, seaWater = 0;      // samples at exactly 0 m (or void), and of them water
  size_t rough = 0, roughWater = 0;  // land unlike all its neighbours, and of them water
  size_t all = 0, allWater = 0;
};

Counts count(const Dem& original, const std::vector<int>& water) {
  Counts c;
  for (int32_t y = 1; y + 1 < original.rows; ++y)
    for (int32_t x = 1; x + 1 < original.columns; ++x) {
      const int w = water[size_t(y) * original.columns + x];
      EXPECT_NE(w, -1) << "no leaf texel on sample " << x << "," << y;
      const float h = original.at(x, y);
      ++c.all;
      c.allWater += w == 1;
      if (h == 0) {
        ++c.sea;
        c.seaWater += w == 1;
        continue;
      }
      // Rough land: above sea level and unlike each of its neighbours. A water sample lies in
      // a flat 7 x 7 window, so at least three of its neighbours have its height.
      bool unlike = h > 0.5f;
      for (int32_t dy = -1; dy <= 1; ++dy)
        for (int32_t dx = -1; dx <= 1; ++dx)
          if (dx || dy) unlike = unlike && !(std::fabs(original.at(x + dx, y + dy) - h) <= 0.01f);
      if (unlike) {
        ++c.rough;
        c.roughWater += w == 1;
      }
    }
  return c;
}

TEST(GeneratedColours, SeaOfACoastalDemIsWater) {
  TempDir dir;
  const RunResult r = runTerralod(
      {"build", kCoast, "-o", dir.file("coast.tlod"), "--threads", "2", "--bake-colour"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const Dem dem = readDem(kCoast);
  const Counts c = count(dem, waterTexels(dir.file("coast.tlod"), dem));
  ASSERT_GT(c.sea, 20000u) << "the crop holds the inlet and the bay";
  // The sea at 0 m is water (but for narrow reaches and texels beside the shore: a water
  // window is 7 x 7 samples); before the fix, none was.
  EXPECT_GT(double(c.seaWater) / double(c.sea), 0.8) << c.seaWater << " of " << c.sea;
  // Rough land is never water.
  EXPECT_EQ(c.roughWater, 0u) << "of " << c.rough;
  std::printf("water texels: %zu of %zu samples (%.1f %%); sea at 0 m: %zu, of them water %zu\n",
              c.allWater, c.all, 100.0 * double(c.allWater) / double(c.all), c.sea, c.seaWater);
}

TEST(GeneratedColours, SeaStoredAsNodataIsWater) {
  // The same coast with its sea (every sample at or below 0 m) as nodata: the void filler makes
  // a smooth surface there, which the sea-void mask still colours as water.
  TempDir dir;
  GDALAllRegister();
  GDALDatasetUniquePtr source(GDALDataset::Open(kCoast.c_str(), GDAL_OF_RASTER));
  ASSERT_TRUE(source);
  const std::string nodataSea = dir.file("coast_nodata_sea.tif");
  {
    GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
    GDALDatasetUniquePtr copy(
        gtiff->CreateCopy(nodataSea.c_str(), source.get(), FALSE, nullptr, nullptr, nullptr));
    ASSERT_TRUE(copy);
    GDALRasterBand* band = copy->GetRasterBand(1);
    const int w = copy->GetRasterXSize(), h = copy->GetRasterYSize();
    std::vector<int16_t> v(size_t(w) * h);
    ASSERT_EQ(band->RasterIO(GF_Read, 0, 0, w, h, v.data(), w, h, GDT_Int16, 0, 0), CE_None);
    for (int16_t& s : v)
      if (s <= 0) s = -32767;
    ASSERT_EQ(band->RasterIO(GF_Write, 0, 0, w, h, v.data(), w, h, GDT_Int16, 0, 0), CE_None);
  }
  const RunResult r = runTerralod(
      {"build", nodataSea, "-o", dir.file("coast.tlod"), "--threads", "2", "--bake-colour"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const Dem dem = readDem(kCoast);
  const Counts c = count(dem, waterTexels(dir.file("coast.tlod"), dem));
  EXPECT_GT(double(c.seaWater) / double(c.sea), 0.8) << c.seaWater << " of " << c.sea;
  EXPECT_EQ(c.roughWater, 0u) << "of " << c.rough;
  auto tileset = TilesetReader::openFile(dir.file("coast.tlod"));
  ASSERT_TRUE(tileset.ok());
  EXPECT_NE((*tileset)->metadataJson().find("\"sea_voids\""), std::string::npos);
}

// The default build stores a shade layer and the colour is made from it (the shader, and
// readNodeColour for tools): at every shade texel of every leaf, the colour is the baked
// build's at the same place, water where it is water.
TEST(GeneratedColours, ShadeLayerGivesTheBakedColour) {
  TempDir dir;
  for (const char* name : {"shade.tlod", "baked.tlod"}) {
    // Versions 6 and 5 (the chunk codec has no say in the colour).
    std::vector<std::string> args{"build", kCoast,          "-o",     dir.file(name), "--threads",
                                  "2",     "--chunk-codec", "meshopt"};
    if (std::string(name) == "baked.tlod") args.push_back("--bake-colour");
    const RunResult r = runTerralod(args);
    ASSERT_EQ(r.exitCode, 0) << r.err;
  }
  auto shade = TilesetReader::openFile(dir.file("shade.tlod"));
  auto baked = TilesetReader::openFile(dir.file("baked.tlod"));
  ASSERT_TRUE(shade.ok() && baked.ok());
  EXPECT_EQ((*shade)->header().version, 6u);
  EXPECT_EQ((*baked)->header().version, 5u);
  ASSERT_EQ((*shade)->nodes().size(), (*baked)->nodes().size());
  const uint32_t leaf = (*shade)->header().levelCount - 1;
  double sum = 0;
  size_t texels = 0, water = 0, waterAgrees = 0, land = 0;
  auto isWater = [](const uint8_t* p) {
    bool w = true;
    for (int c = 0; c < 3; ++c) w = w && std::abs(p[c] - kWater[size_t(c)]) <= 12;
    return w;
  };
  for (uint32_t i = 0; i < (*shade)->nodes().size(); ++i) {
    if ((*shade)->nodes()[i].level != leaf) continue;
    auto a = readNodeColour(**shade, i);
    auto b = readNodeColour(**baked, i);
    ASSERT_TRUE(a.ok() && b.ok());
    ASSERT_EQ(2 * a->size - 1, b->size) << "the shade layer has half the texel intervals";
    for (uint32_t y = 0; y < a->size; ++y)
      for (uint32_t x = 0; x < a->size; ++x) {
        const uint8_t* p = &a->rgb[(size_t(y) * a->size + x) * 3];
        const uint8_t* q = &b->rgb[(size_t(2 * y) * b->size + 2 * x) * 3];
        for (int c = 0; c < 3; ++c) sum += std::abs(int(p[c]) - int(q[c]));
        ++texels;
        if (isWater(q)) {
          ++water;
          waterAgrees += isWater(p);
        } else {
          ++land;
        }
      }
  }
  ASSERT_GT(water, 1000u);
  ASSERT_GT(land, 1000u);
  const double mean = sum / double(3 * texels);
  std::printf("shade against baked: %.2f/255 mean over %zu texels; water %zu, agreeing %zu\n", mean,
              texels, water, waterAgrees);
  EXPECT_LT(mean, 3.0);
  // (Shade texels by the shore mix water and land: 2.17/255 mean and 93 % when written.)
  EXPECT_GT(double(waterAgrees) / double(water), 0.9);
}

}  // namespace
}  // namespace terralod::test
