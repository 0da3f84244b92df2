// Every real DEM bundled with the tests builds, describes itself and verifies: the true error
// of every chunk within its level's bound, full coverage, exact morph targets, crack-proof
// skirts. This is the promise users check first on their own data.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_runner.h"

namespace terralod::test {
namespace {

struct Dem {
  std::string file;
  std::vector<std::string> extra;  ///< build options
  uint64_t voids;                  ///< expected filled voids
};

// Names the case in ctest's output instead of dumping its bytes.
void PrintTo(const Dem& dem, std::ostream* out) {
  *out << dem.file;
}

class EveryDem : public ::testing::TestWithParam<Dem> {};

TEST_P(EveryDem, BuildsAndVerifies) {
  const Dem& dem = GetParam();
  TempDir dir;
  std::vector<std::string> build = {"build", testData(dem.file), "-o", dir.file("t.tlod")};
  build.insert(build.end(), dem.extra.begin(), dem.extra.end());
  const RunResult built = runTerralod(build);
  ASSERT_EQ(built.exitCode, 0) << built.err;

  const RunResult info = runTerralod({"info", dir.file("t.tlod"), "--json"});
  ASSERT_EQ(info.exitCode, 0) << info.err;
  const auto j = nlohmann::json::parse(info.out);
  for (const char* key : {"levels", "chunks", "vertices", "triangles", "file_bytes", "leaf_error",
                          "level_error", "extent", "spacing", "source_size"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["filled_voids"].get<uint64_t>(), dem.voids);
  EXPECT_EQ(j["level_error"].size(), j["levels"].get<size_t>());
  EXPECT_EQ(j["level_error"].back().get<double>(), j["leaf_error"].get<double>());

  const RunResult verified =
      runTerralod({"verify", dir.file("t.tlod"), "--source", testData(dem.file)});
  EXPECT_EQ(verified.exitCode, 0) << verified.out << verified.err;
  EXPECT_NE(verified.out.find("verify: OK"), std::string::npos) << verified.out;
}

INSTANTIATE_TEST_SUITE_P(
    Bundled, EveryDem,
    ::testing::Values(Dem{"gzcommon_dem_squared_129.tif", {}, 0}, Dem{"crater_lake_0513.bt", {}, 0},
                      Dem{"zion_srtm3.tif", {}, 0}, Dem{"zion_srtm3_utm12_30m.tif", {}, 23982},
                      Dem{"N43W123.hgt", {"--max-error", "2"}, 0},
                      Dem{"osgearth_mt_rainier_90m.tif", {"--max-error", "2"}, 9033},
                      Dem{"nz_elev_1km.tif", {"--max-error", "4"}, 1348639},
                      Dem{"landlab_srtmgl3_frontrange.asc", {}, 0},
                      Dem{"landlab_west_bijou_gully_3m.asc", {"--max-error", "0.1"}, 2739},
                      Dem{"loadersgl_terrarium_256.png", {"--encoding", "terrarium"}, 0},
                      Dem{"burrard_inlet_srtm3.tif", {}, 1413}),
    [](const ::testing::TestParamInfo<Dem>& param) {
      std::string name = param.param.file.substr(0, param.param.file.find('.'));
      for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      return name;
    });

}  // namespace
}  // namespace terralod::test
