// terralod export --format 3dtiles: a small georeferenced tileset as a 3D Tiles 1.1 tileset
// (tree, errors, placement on Earth, one valid glTF per chunk), the default placement of a DEM
// without a CRS, and bad requests.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>

#include "cli_expectations.h"
#include "cli_runner.h"
#include "gltf_validator.h"
#include "nginx_server.h"
#include "temp_dir.h"
#include "terralod/format/tileset_reader.h"
#include "tiles3d_checks.h"

namespace terralod::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Longitude and latitude (degrees) of an ECEF point, to a few hundredths of a degree.
std::array<double, 2> roughlyWhere(double x, double y, double z) {
  constexpr double e2 = 0.00669437999014;
  const double degrees = 180.0 / std::numbers::pi;
  return {std::atan2(y, x) * degrees, std::atan2(z, std::hypot(x, y) * (1 - e2)) * degrees};
}

// Every tile of the tree, depth first, with its parent's error.
void eachTile(const json& tile, double parentError,
              const std::function<void(const json&, double)>& visit) {
  visit(tile, parentError);
  if (tile.contains("children"))
    for (const json& child : tile["children"])
      eachTile(child, tile["geometricError"].get<double>(), visit);
}

class Export3dTiles : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir = new TempDir;
    // 362 x 361 samples in EPSG:4326 around 146.95 W, 64.80 N, with generated colour.
    const RunResult r =
        runTerralod({"build", testData("n43w123_flat_64n.tif"), "-o", dir->file("flat.tlod")});
    ASSERT_EQ(r.exitCode, 0) << r.err;
  }
  static void TearDownTestSuite() { delete dir; }
  static inline TempDir* dir = nullptr;
};

TEST_F(Export3dTiles, EveryChunkAPlacedValidGltfUnderATreeOfTheirErrors) {
  const std::string out = dir->file("flat3d");
  const RunResult r =
      runTerralod({"export", dir->file("flat.tlod"), "--format", "3dtiles", "-o", out});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("tileset.json"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(out + ".partial"));
  const json tileset = json::parse(readWholeFile(out + "/tileset.json"));
  EXPECT_EQ(tileset["asset"]["version"], "1.1");
  const json& root = tileset["root"];
  // Placed where the DEM is: the root frame's origin at the data's centre.
  const auto where =
      roughlyWhere(root["transform"][12], root["transform"][13], root["transform"][14]);
  EXPECT_NEAR(where[0], -146.9497, 0.02);
  EXPECT_NEAR(where[1], 64.7999, 0.02);
  // The error of drawing nothing is the whole terrain (its box's diagonal, near enough), so a
  // client draws it from any distance.
  const json& box = root["boundingVolume"]["box"];
  double diagonal2 = 0;
  for (int k = 3; k < 12; ++k) diagonal2 += 4.0 * box[k].get<double>() * box[k].get<double>();
  EXPECT_GE(tileset["geometricError"].get<double>(), 0.9 * std::sqrt(diagonal2));
  // What placed it, for tools that put a terralod camera there.
  const json& extras = tileset["extras"];
  EXPECT_EQ(extras["placed_on_earth"], true);
  EXPECT_EQ(extras["source_grid"]["columns"], 362);
  EXPECT_EQ(extras["source_grid"]["geotransform"].size(), 6u);
  EXPECT_NE(extras["source_grid"]["crs_wkt"].get<std::string>().find("WGS 84"), std::string::npos);
  EXPECT_EQ(extras["root_frame_origin_local"].size(), 3u);
  // Each tile's content exists; errors shrink going down; refinement REPLACE.
  size_t tiles = 0, leaves = 0;
  std::string aLeaf;
  eachTile(root, tileset["geometricError"].get<double>(), [&](const json& t, double parent) {
    EXPECT_LE(t["geometricError"].get<double>(), parent);
    EXPECT_EQ(t["refine"], "REPLACE");
    EXPECT_EQ(t["boundingVolume"]["box"].size(), 12u);
    if (!t.contains("content")) return;
    ++tiles;
    const std::string uri = t["content"]["uri"];
    EXPECT_TRUE(fs::exists(out + "/" + uri)) << uri;
    if (!t.contains("children")) {
      ++leaves;
      aLeaf = uri;
    }
  });
  size_t files = 0;
  for (const auto& e : fs::recursive_directory_iterator(out + "/tiles"))
    files += e.path().extension() == ".glb";
  EXPECT_EQ(files, tiles);
  EXPECT_GT(leaves, 3u);
  uint64_t checked = 0;
  EXPECT_EQ(tiles3dProblems(out, &checked), std::vector<std::string>{});
  EXPECT_EQ(checked, tiles);
  expectValidGltf(out + "/tiles/0/0/0.glb");
  expectValidGltf(out + "/" + aLeaf);

  // Not over an export already there.
  expectOneErrorLine(
      runTerralod({"export", dir->file("flat.tlod"), "--format", "3dtiles", "-o", out}),
      "exists and is not an empty directory");
}

// Every file of an export, by path relative to it, with its bytes.
std::map<std::string, std::vector<uint8_t>> exportFiles(const std::string& dir) {
  std::map<std::string, std::vector<uint8_t>> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[fs::relative(e.path(), dir).string()] = fileBytes(e.path());
  return files;
}

TEST_F(Export3dTiles, ImplicitTilingDescribesTheSameTreeWithSubtreeFiles) {
  const std::string flat = dir->file("flat.tlod");
  const std::string explicitDir = dir->file("explicit3d"), implicitDir = dir->file("implicit3d");
  ASSERT_EQ(runTerralod({"export", flat, "--format", "3dtiles", "-o", explicitDir}).exitCode, 0);
  const RunResult r = runTerralod(
      {"export", flat, "--format", "3dtiles", "--tiling", "implicit", "-o", implicitDir});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(has(r.out, "implicit quadtree tiling")) << r.out;
  const json tileset = json::parse(readWholeFile(implicitDir + "/tileset.json"));
  const json& root = tileset["root"];
  ASSERT_TRUE(root.contains("implicitTiling"));
  EXPECT_EQ(root["implicitTiling"]["subdivisionScheme"], "QUADTREE");
  EXPECT_EQ(root["content"]["uri"], "tiles/{level}/{x}/{y}.glb");
  EXPECT_FALSE(root.contains("children"));
  // The same chunks, byte for byte, and the same root frame and place.
  const auto explicitFiles = exportFiles(explicitDir), implicitFiles = exportFiles(implicitDir);
  size_t glbs = 0, subtrees = 0;
  for (const auto& [path, bytes] : implicitFiles) {
    if (path.ends_with(".subtree")) ++subtrees;
    if (!path.ends_with(".glb")) continue;
    ++glbs;
    ASSERT_TRUE(explicitFiles.count(path)) << path;
    EXPECT_TRUE(explicitFiles.at(path) == bytes) << path;
  }
  EXPECT_GT(subtrees, 0u);
  const json explicitJson = json::parse(readWholeFile(explicitDir + "/tileset.json"));
  EXPECT_EQ(root["transform"], explicitJson["root"]["transform"]);
  EXPECT_EQ(root["geometricError"], explicitJson["root"]["geometricError"]);
  // Every tile the subtrees make available with content has its file, and no other.
  uint64_t content = 0;
  EXPECT_EQ(tiles3dProblems(implicitDir, &content), std::vector<std::string>{});
  EXPECT_EQ(content, glbs);
  // Alive: a subtree file that loses a tile's content bit is seen.
  for (const auto& e : fs::recursive_directory_iterator(implicitDir + "/subtrees"))
    if (e.path().extension() == ".subtree") {
      fs::remove(e.path());
      break;
    }
  EXPECT_NE(tiles3dProblems(implicitDir), std::vector<std::string>{});
}

TEST_F(Export3dTiles, FromAWebServerTheSameFiles) {
  TempDir served;
  fs::copy_file(dir->file("flat.tlod"), served.file("flat.tlod"));
  NginxServer server(served.path());
  ASSERT_TRUE(server.running()) << server.error();
  const std::string local = dir->file("local3d"), remote = dir->file("remote3d");
  ASSERT_EQ(
      runTerralod({"export", dir->file("flat.tlod"), "--format", "3dtiles", "-o", local}).exitCode,
      0);
  const RunResult r =
      runTerralod({"export", server.url("flat.tlod"), "--format", "3dtiles", "-o", remote});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto a = exportFiles(local), b = exportFiles(remote);
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [path, bytes] : a) {
    ASSERT_TRUE(b.count(path)) << path;
    EXPECT_TRUE(b.at(path) == bytes) << path;  // tileset.json too: it names flat.tlod
  }
}

// A VIPM tileset: every node at its finest level, coloured by its materials, flanges under its
// borders; leaves and roots in one tree, each leaf's error its level's.
TEST_F(Export3dTiles, VipmTilesetsExportEveryNodeAtItsFinestInItsMaterialsColours) {
  const std::string vipm = dir->file("crater_vipm.tlod"), out = dir->file("crater3d");
  ASSERT_EQ(runTerralod({"build", testData("crater_lake_0513.bt"), "--kind", "vipm", "-o", vipm})
                .exitCode,
            0);
  RunResult r = runTerralod({"export", vipm, "--format", "3dtiles", "-o", out});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  auto reader = TilesetReader::openFile(vipm);
  ASSERT_TRUE(reader.ok());
  const auto& nodes = (*reader)->nodes();
  uint64_t content = 0;
  EXPECT_EQ(tiles3dProblems(out, &content), std::vector<std::string>{});
  EXPECT_EQ(content, nodes.size());
  // Sixteen 128-cell roots under one tile without content, each over its leaves.
  const json tileset = json::parse(readWholeFile(out + "/tileset.json"));
  const json& top = tileset["root"];
  EXPECT_FALSE(top.contains("content"));
  ASSERT_EQ(top["children"].size(), 16u);
  const TilesetHeader& h = (*reader)->header();
  for (const json& root : top["children"]) {
    EXPECT_DOUBLE_EQ(root["geometricError"].get<double>(), h.levelError[0]);
    ASSERT_TRUE(root.contains("children"));
    for (const json& leaf : root["children"])
      EXPECT_DOUBLE_EQ(leaf["geometricError"].get<double>(), h.levelError[1]);
  }
  // A leaf: the finest mesh's vertices and triangles plus flanges, in its materials' colours.
  const std::string leaf = top["children"][5]["children"][0]["content"]["uri"];
  expectValidGltf(out + "/" + leaf);
  const std::vector<uint8_t> glb = fileBytes(out + "/" + leaf);
  ASSERT_GT(glb.size(), 20u);
  uint32_t jsonLength = 0;
  std::memcpy(&jsonLength, glb.data() + 12, 4);
  const json gltf = json::parse(glb.begin() + 20, glb.begin() + 20 + jsonLength);
  const json& attributes = gltf["meshes"][0]["primitives"][0]["attributes"];
  EXPECT_TRUE(attributes.contains("COLOR_0"));
  EXPECT_FALSE(attributes.contains("TEXCOORD_0"));
  expectValidGltf(out + "/" + top["children"][5]["content"]["uri"].get<std::string>());
}

// A 65² ESRI ASCII grid (no .prj) with `corner` (its xllcorner, yllcorner) and `cellsize`, built
// and exported to 3D Tiles: the export's stderr, where its root's origin lies (longitude,
// latitude) and whether the export placed it on Earth.
struct PlacedGrid {
  std::string err;
  std::array<double, 2> where{};
  json placedOnEarth;
};
PlacedGrid exportAsciiGrid(TempDir& dir, const std::string& name, std::array<double, 2> corner,
                           double cellsize) {
  const std::string asc = dir.file(name + ".asc");
  {
    std::ofstream f(asc);
    f.precision(17);
    f << "ncols 65\nnrows 65\nxllcorner " << corner[0] << "\nyllcorner " << corner[1]
      << "\ncellsize " << cellsize << "\n";
    for (int r = 0; r < 65; ++r)
      for (int c = 0; c < 65; ++c) f << (100 + r + c % 7) << (c + 1 < 65 ? " " : "\n");
  }
  PlacedGrid out;
  const RunResult built = runTerralod({"build", asc, "-o", dir.file(name + ".tlod")});
  EXPECT_EQ(built.exitCode, 0) << built.err;
  const RunResult r = runTerralod(
      {"export", dir.file(name + ".tlod"), "--format", "3dtiles", "-o", dir.file(name + "3d")});
  EXPECT_EQ(r.exitCode, 0) << r.err;
  if (built.exitCode != 0 || r.exitCode != 0) return out;
  out.err = r.err;
  const json tileset = json::parse(readWholeFile(dir.file(name + "3d/tileset.json")));
  const json& t = tileset["root"]["transform"];
  out.where = roughlyWhere(t[12], t[13], t[14]);
  out.placedOnEarth = tileset["extras"]["placed_on_earth"];
  return out;
}

TEST_F(Export3dTiles, ADemWithoutACrsGetsTheDefaultPlaceAndAWarning) {
  const PlacedGrid g = exportAsciiGrid(*dir, "plain", {0.0, 0.0}, 10.0);
  if (HasFailure()) return;
  EXPECT_NE(g.err.find("has no coordinate reference system; placed on a plane tangent"),
            std::string::npos)
      << g.err;
  EXPECT_NEAR(g.where[0], 0.0, 0.01);
  EXPECT_NEAR(g.where[1], 0.0, 0.01);
  EXPECT_EQ(g.placedOnEarth, false);
}

// A grid without a CRS whose bounds are longitudes and latitudes (an ESRI ASCII grid with no
// .prj): its spacing was taken as WGS 84 degrees, and so is its place.
TEST_F(Export3dTiles, ADemWithoutACrsInDegreesIsPlacedWhereItsDegreesSay) {
  const PlacedGrid g = exportAsciiGrid(*dir, "degrees", {-105.5, 40.0}, 0.0008333333);
  if (HasFailure()) return;
  EXPECT_EQ(g.err.find("placed on a plane tangent"), std::string::npos) << g.err;
  EXPECT_NEAR(g.where[0], -105.47, 0.05);
  EXPECT_NEAR(g.where[1], 40.03, 0.05);
  EXPECT_EQ(g.placedOnEarth, true);
}

TEST_F(Export3dTiles, BadRequestsGetOneLineAndLeaveNothing) {
  const std::string out = dir->file("bad3d");
  expectOneErrorLine(runTerralod({"export", dir->file("flat.tlod"), "--format", "3dtiles",
                                  "--level", "1", "-o", out}),
                     "do not apply");
  expectOneErrorLine(runTerralod({"export", dir->file("flat.tlod"), "--tiling", "implicit", "-o",
                                  dir->file("flat.glb")}),
                     "--tiling goes with --format 3dtiles");
  EXPECT_FALSE(fs::exists(dir->file("flat.glb")));
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".partial"));

  // A chunk damaged near the end (the last node's blob): the tiles before it are written, then
  // the export fails naming it, and what it wrote goes.
  const std::string damaged = dir->file("damaged.tlod");
  fs::copy_file(dir->file("flat.tlod"), damaged, fs::copy_options::overwrite_existing);
  {
    auto reader = TilesetReader::openFile(damaged);
    ASSERT_TRUE(reader.ok());
    const NodeRecord last = (*reader)->nodes().back();
    std::fstream f(damaged, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(std::streamoff(last.blobOffset + last.blobBytes / 2));
    f.put('\x5a').put('\xa5');
  }
  expectOneErrorLine(runTerralod({"export", damaged, "--format", "3dtiles", "-o", out}), "chunk");
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".partial"));
}

}  // namespace
}  // namespace terralod::test
