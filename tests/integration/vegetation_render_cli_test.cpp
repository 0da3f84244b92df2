// render and bench with --vegetation: a small DEM with a ridge (written here) and a quick
// sunflower bake; plants behind the ridge hidden by it, plants in front drawn over it, golden
// images of both, the bench's vegetation figures, material rules, and bad input.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "cli_expectations.h"
#include "cli_runner.h"
#include "image_compare.h"
#include "terralod/render/image.h"

namespace terralod::test {
namespace {

namespace fs = std::filesystem;

// 129 × 129 samples, 1 m apart: flat at 100 m in the south, a ridge 6 m high along y = 64,
// and flat at 97 m beyond it (y north; rows of the grid from the north).
void writeRidgeDem(const std::string& path) {
  constexpr int n = 129;
  std::ofstream out(path);
  out << "ncols " << n << "\nnrows " << n << "\nxllcorner 0\nyllcorner 0\ncellsize 1\n";
  for (int row = 0; row < n; ++row) {
    const double y = n - 1 - row;
    double s = std::clamp((y - 66) / 6, 0.0, 1.0);
    s = s * s * (3 - 2 * s);
    const double h = 100 - 3 * s + 6 * std::exp(-std::pow((y - 64) / 3, 2));
    for (int x = 0; x < n; ++x) out << (x ? " " : "") << h;
    out << "\n";
  }
}

class VegetationRender : public ::testing::Test {
 public:
  static void SetUpTestSuite() {
    dir = new TempDir;
    writeRidgeDem(dir->file("ridge.asc"));
    RunResult r = runTerralod(
        {"build", dir->file("ridge.asc"), "-o", dir->file("ridge.tlod"), "--no-texture"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    r = runTerralod({"vegetation", "bake", "--scene", "sunflowers", "--finest", "48",
                     "--rays-per-pixel", "1", "--occlusion-rays", "2", "-o",
                     dir->file("sunflowers.tlv")});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    // The ground truth ray traces every plant: the meadow's 0.66 M triangles build in a
    // fraction of the sunflowers' 5.5 M.
    r = runTerralod({"vegetation", "bake", "--scene", "meadow", "--finest", "48",
                     "--rays-per-pixel", "1", "--occlusion-rays", "2", "-o",
                     dir->file("meadow.tlv")});
    ASSERT_EQ(r.exitCode, 0) << r.err;
  }
  static void TearDownTestSuite() { delete dir; }

  // Renders the ridge from the south, above the flat ground, looking over the ridge.
  static Image render(const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> args = {"render",   dir->file("ridge.tlod"),
                                     "--eye",    "64,4,105",
                                     "--target", "64,80,100",
                                     "--size",   "320x240",
                                     "-o",       dir->file(name)};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult r = runTerralod(args);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    auto image = readPng(dir->file(name));
    EXPECT_TRUE(image.ok());
    return image.ok() ? *image : Image{};
  }

  static size_t differing(const Image& a, const Image& b, int threshold = 2) {
    size_t n = 0;
    for (size_t i = 0; i + 3 < a.rgba.size(); i += 4)
      for (size_t c = 0; c < 3; ++c)
        if (std::abs(int(a.rgba[i + c]) - int(b.rgba[i + c])) > threshold) {
          ++n;
          break;
        }
    return n;
  }

  static std::string tlv() { return dir->file("sunflowers.tlv"); }
  static std::string meadow() { return dir->file("meadow.tlv"); }
  static inline TempDir* dir = nullptr;
};

TempDir* VegetationRenderDir() {
  return VegetationRender::dir;
}

// Plants can be drawn with a few steps of difference between runs (threads merge ties).
const ImageTolerance kVegetationTolerance{8, 0.01};

TEST_F(VegetationRender, PlantsBehindARidgeHideAndPlantsInFrontStandOverIt) {
  const Image bare = render("bare.png", {});
  // Only beyond the ridge (the ground there is at 97 m): every plant is behind it.
  const Image behind =
      render("behind.png", {"--vegetation", tlv(), "--vegetation-where", "height<98"});
  EXPECT_EQ(differing(behind, bare), 0u);
  // Without the depth composite the same plants show through the ridge.
  const Image through = render("through.png", {"--vegetation", tlv(), "--vegetation-where",
                                               "height<98", "--no-vegetation-depth"});
  EXPECT_GT(differing(through, bare), 2000u);
  // Only on the flat ground in front: drawn over the ridge's face.
  const Image front =
      render("front.png", {"--vegetation", tlv(), "--vegetation-where", "height>99,slope<10"});
  EXPECT_GT(differing(front, bare), 10000u);
  const auto result = compareWithGolden(front, "vegetation_ridge_front", kVegetationTolerance);
  EXPECT_TRUE(result.matches) << result.message;
}

TEST_F(VegetationRender, AFieldOfLdisFadesIntoItsDirectionalTextures) {
  // From south of the data: LDI tiles to 40 m (the quick bake's tiny LDIs would reach much
  // farther by themselves), the directional textures beyond.
  std::vector<std::string> args = {"render",
                                   dir->file("ridge.tlod"),
                                   "--eye",
                                   "64,-20,108",
                                   "--target",
                                   "64,40,100",
                                   "--size",
                                   "320x240",
                                   "--vegetation",
                                   tlv(),
                                   "--vegetation-where",
                                   "height>99",
                                   "--vegetation-range",
                                   "40",
                                   "-o",
                                   dir->file("field.png")};
  const RunResult r = runTerralod(args);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("terralod: vegetation: "), std::string::npos) << r.out;
  auto field = readPng(dir->file("field.png"));
  ASSERT_TRUE(field.ok());
  args[args.size() - 1] = dir->file("ldis.png");
  args.push_back("--no-vegetation-textures");
  ASSERT_EQ(runTerralod(args).exitCode, 0);
  auto ldis = readPng(dir->file("ldis.png"));
  ASSERT_TRUE(ldis.ok());
  EXPECT_GT(differing(*field, *ldis), 3000u) << "the textures draw beyond the LDIs' range";
  const auto result = compareWithGolden(*field, "vegetation_field", kVegetationTolerance);
  EXPECT_TRUE(result.matches) << result.message;
}

// bench's figures for a four-frame flight over the ridge, the ground truth every other frame.
nlohmann::json benchRidge(const std::vector<std::string>& vegetation) {
  const std::string flight = VegetationRenderDir()->file("flight.json");
  std::ofstream(flight) << R"({"fov_deg": 60, "size": [320, 240], "frames": 4, "keyframes": [)"
                        << R"({"eye": [64, 4, 105], "target": [64, 80, 100]},)"
                        << R"({"eye": [64, 5, 105], "target": [66, 80, 100]}]})";
  std::vector<std::string> args = {
      "bench",  VegetationRenderDir()->file("ridge.tlod"), "--flight",          flight,
      "--json", VegetationRenderDir()->file("bench.json"), "--reference-every", "2"};
  args.insert(args.end(), vegetation.begin(), vegetation.end());
  const RunResult r = runTerralod(args);
  EXPECT_EQ(r.exitCode, 0) << r.err;
  return nlohmann::json::parse(readWholeFile(VegetationRenderDir()->file("bench.json")));
}

TEST_F(VegetationRender, BenchReportsTheVegetationFiguresAndTheGroundTruth) {
  const auto j = benchRidge(
      {"--vegetation", meadow(), "--vegetation-where", "height>99", "--vegetation-reference"});
  EXPECT_GT(j["vegetation_ms_p50"].get<double>(), 0.0);
  EXPECT_GE(j["vegetation_ms_p99"].get<double>(), j["vegetation_ms_p50"].get<double>());
  EXPECT_GT(j["composite_ms_p50"].get<double>(), 0.0);
  EXPECT_GT(j["splats_p50"].get<double>(), 1000.0);
  EXPECT_GT(j["ldi_tiles_p50"].get<double>(), 10.0);
  EXPECT_GT(j["vegetation_resident_mb"].get<double>(), 0.0);
  EXPECT_LT(j["vegetation_pop_mean"].get<double>(), 0.5);
  // Frames 0 and 2, each put off to the next frame whose terrain is loaded (the first frames
  // draw stand-ins while chunks load).
  EXPECT_GE(j["vegetation_reference_frames"].get<int>(), 1);
  EXPECT_LE(j["vegetation_reference_frames"].get<int>(), 2);
  // The quick bake's LDIs are 48 pixels across at most (4 cm pixels on the meadow's 2 m
  // tiles), the truth its real grass: some likeness.
  EXPECT_GT(j["vegetation_ssim_mean"].get<double>(), 0.2);
  EXPECT_LE(j["vegetation_ssim_mean"].get<double>(), 1.0);
  EXPECT_LT(j["vegetation_coverage_error"].get<double>(), 0.4);
}

TEST_F(VegetationRender, TheGroundTruthSeesPlantsShownThroughARidge) {
  // Plants only behind the ridge: drawn and traced agree (neither shows one), unless the
  // LDIs are composited without depth and show through.
  const std::vector<std::string> behind = {"--vegetation", meadow(), "--vegetation-where",
                                           "height<98", "--vegetation-reference"};
  const auto agree = benchRidge(behind);
  EXPECT_GT(agree["vegetation_ssim_mean"].get<double>(), 0.99);
  EXPECT_LT(agree["vegetation_coverage_error"].get<double>(), 0.005);
  auto through = behind;
  through.push_back("--no-vegetation-depth");
  const auto differ = benchRidge(through);
  EXPECT_GT(differ["vegetation_coverage_error"].get<double>(), 0.05);
  EXPECT_LT(differ["vegetation_ssim_mean"].get<double>(),
            agree["vegetation_ssim_mean"].get<double>() - 0.05);
}

TEST_F(VegetationRender, TheViewerDrawsTheVegetationAsRenderDoes) {
  std::ofstream(dir->file("view.json"))
      << R"({"fov_deg": 60, "size": [320, 240], "frames": 5, "keyframes": [)"
      << R"({"eye": [64, -20, 108], "target": [64, 40, 100]},)"
      << R"({"eye": [64, -19, 108], "target": [64, 40, 100]}]})";
  const std::vector<std::string> vegetation = {
      "--vegetation", tlv(), "--vegetation-where", "height>99", "--vegetation-range", "40"};
  std::vector<std::string> view = {"-a",
                                   "-n",
                                   "350",
                                   "-s",
                                   "-screen 0 1280x1024x24 -noreset",
                                   TERRALOD_CLI,
                                   "view",
                                   dir->file("ridge.tlod"),
                                   "--play",
                                   dir->file("view.json"),
                                   "--screenshot",
                                   dir->file("shot.png"),
                                   "--exit-after-play"};
  view.insert(view.end(), vegetation.begin(), vegetation.end());
  const RunResult viewed = runProgram(TERRALOD_XVFB_RUN, view);
  ASSERT_EQ(viewed.exitCode, 0) << viewed.out << viewed.err;
  std::vector<std::string> headless = {"render",   dir->file("ridge.tlod"),
                                       "--eye",    "64,-19,108",
                                       "--target", "64,40,100",
                                       "--size",   "320x240",
                                       "-o",       dir->file("bare_view.png")};
  ASSERT_EQ(runTerralod(headless).exitCode, 0);
  headless.back() = dir->file("headless.png");
  headless.insert(headless.end(), vegetation.begin(), vegetation.end());
  ASSERT_EQ(runTerralod(headless).exitCode, 0);
  auto shot = readPng(dir->file("shot.png"));
  ASSERT_TRUE(shot.ok()) << shot.error().message;
  EXPECT_GT(differing(*shot, readPng(dir->file("bare_view.png")).value()), 5000u)
      << "no vegetation drawn";
  const Image drawn = readPng(dir->file("headless.png")).value();
  const auto c = compareImages(*shot, drawn, kVegetationTolerance);
  EXPECT_TRUE(c.matches) << c.message;
}

// The ridge DEM's grid with class 1 west of x = 66 m and class 2 east of it (a border between
// two columns of the sunflowers' 4.4 m tiles, whose centres' nearest grid points decide), and
// class 2 all across the far north (y > 100 m), so that a grid read upside down shows.
void writeHalvesClasses(const std::string& path) {
  constexpr int n = 129;
  std::ofstream out(path);
  out << "ncols " << n << "\nnrows " << n << "\nxllcorner 0\nyllcorner 0\ncellsize 1\n";
  for (int row = 0; row < n; ++row)
    for (int x = 0; x < n; ++x)
      out << (x < 66 && n - 1 - row <= 100 ? 1 : 2) << (x + 1 < n ? " " : "\n");
}

// Pixels that differ between two images in the left and in the right half.
std::pair<size_t, size_t> differingHalves(const Image& a, const Image& b) {
  std::pair<size_t, size_t> n{0, 0};
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const size_t i = (size_t(y) * a.width + x) * 4;
      bool differs = false;
      for (size_t c = 0; c < 3; ++c)
        differs |= std::abs(int(a.rgba[i + c]) - int(b.rgba[i + c])) > 2;
      if (differs) ++(x < a.width / 2 ? n.first : n.second);
    }
  return n;
}

TEST_F(VegetationRender, MaterialRulesFollowARasterOrTheVipmTilesetsOwnMaterials) {
  const std::string classes = dir->file("halves.asc");
  writeHalvesClasses(classes);
  // Looking north along the border: class 1 is the picture's left half, class 2 its right.
  auto alongBorder = [&](const std::string& tileset, const std::string& name,
                         std::vector<std::string> extra) {
    std::vector<std::string> args = {"render",   dir->file(tileset), "--eye",  "66,4,105",
                                     "--target", "66,80,100",        "--size", "320x240",
                                     "-o",       dir->file(name)};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult run = runTerralod(args);
    EXPECT_EQ(run.exitCode, 0) << run.err;
    return readPng(dir->file(name)).value();
  };
  const Image bare = alongBorder("ridge.tlod", "bare_border.png", {});
  auto onClass = [&](const std::string& name, const std::string& rule) {
    return alongBorder("ridge.tlod", name,
                       {"--vegetation", tlv(), "--vegetation-materials", classes,
                        "--vegetation-where", "height>99,slope<10,material=" + rule});
  };
  const auto west = differingHalves(onClass("west.png", "class 1"), bare);
  const auto east = differingHalves(onClass("east.png", "class 2"), bare);
  EXPECT_GT(west.first, 5000u);
  EXPECT_LT(west.second, west.first / 10) << "plants on the eastern half";
  EXPECT_GT(east.second, 5000u);
  EXPECT_LT(east.first, east.second / 10) << "plants on the western half";
  const auto both = differingHalves(onClass("both.png", "class 1|class 2"), bare);
  EXPECT_GT(both.first, west.first * 9 / 10);
  EXPECT_GT(both.second, east.second * 9 / 10);

  // A VIPM tileset built with those classes has them itself: the same picture without the
  // raster (its leaves' triangles carry the materials; no texture differs between the two).
  RunResult r = runTerralod({"build", dir->file("ridge.asc"), "--kind", "vipm", "--materials",
                             classes, "-o", dir->file("ridge_vipm.tlod")});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::vector<std::string> rule = {"--vegetation", tlv(), "--vegetation-where",
                                         "height>99,slope<10,material=class 1"};
  const Image own = alongBorder("ridge_vipm.tlod", "vipm_own.png", rule);
  auto withRaster = rule;
  withRaster.insert(withRaster.end(), {"--vegetation-materials", classes});
  const Image raster = alongBorder("ridge_vipm.tlod", "vipm_raster.png", withRaster);
  EXPECT_GT(differingHalves(own, alongBorder("ridge_vipm.tlod", "vipm_bare.png", {})).first, 5000u);
  const auto c = compareImages(own, raster, kVegetationTolerance);
  EXPECT_TRUE(c.matches) << c.message;
}

TEST_F(VegetationRender, BadVegetationInputGetsOneLineAndWritesNothing) {
  const std::string tileset = dir->file("ridge.tlod"), out = dir->file("bad.png");
  auto run = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = {"render", tileset, "--size", "64x48", "-o", out};
    args.insert(args.end(), extra.begin(), extra.end());
    return runTerralod(args);
  };
  expectOneErrorLine(run({"--vegetation", dir->file("missing.tlv")}), "missing.tlv");
  {
    std::string bytes = readWholeFile(tlv());
    bytes.resize(bytes.size() / 2);
    std::ofstream(dir->file("half.tlv"), std::ios::binary) << bytes;
  }
  expectOneErrorLine(run({"--vegetation", dir->file("half.tlv")}), "half.tlv");
  expectOneErrorLine(run({"--vegetation", tlv(), "--vegetation-where", "slope<abc"}),
                     "--vegetation-where");
  expectOneErrorLine(run({"--vegetation-where", "height<3"}), "--vegetation-where needs");
  expectOneErrorLine(run({"--vegetation-reference"}), "--vegetation-reference needs");
  // Material rules: a static tileset has no materials of its own; names must be the raster's.
  expectOneErrorLine(run({"--vegetation", tlv(), "--vegetation-where", "material=grass"}),
                     "ridge.tlod: has no materials");
  writeHalvesClasses(dir->file("classes.asc"));
  expectOneErrorLine(run({"--vegetation", tlv(), "--vegetation-where", "material=grass",
                          "--vegetation-materials", dir->file("classes.asc")}),
                     "material 'grass' is not one of: class 1, class 2");
  expectOneErrorLine(run({"--vegetation", tlv(), "--vegetation-where", "material=grass",
                          "--vegetation-materials", dir->file("nothere.tif")}),
                     "nothere.tif");
  expectOneErrorLine(
      run({"--vegetation", tlv(), "--vegetation-materials", dir->file("classes.asc")}),
      "no material=");
  expectOneErrorLine(run({"--vegetation-materials", dir->file("classes.asc")}),
                     "--vegetation-materials needs --vegetation");
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace terralod::test
