// `terralod export`: the surface of one level as OBJ, PLY or GLB. The meshes are read back and
// checked against the tileset itself (read independently through the format library): every
// chunk of the level, no skirts, shared vertices welded, positions in the tileset's extent;
// GLB files must pass the Khronos glTF validator; bad inputs get one error line and no output.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "cli_expectations.h"
#include "cli_runner.h"
#include "terralod/format/tileset_reader.h"

namespace terralod::test {
namespace {

namespace fs = std::filesystem;

constexpr double kHeightTolerance = 1e-6;  // metres; what the exporter calls the same height

// How far a float32 coordinate may be from the double it was rounded from, with room to spare.
double floatSlack(double v) {
  return 1e-3 + 1e-6 * std::fabs(v);
}

struct Mesh {
  std::vector<std::array<float, 3>> positions;
  std::vector<uint32_t> indices;
};

// What the level should look like, straight from the tileset's chunks.
struct LevelFacts {
  uint64_t chunks = 0;
  uint64_t triangles = 0;                                 // node table
  std::map<std::pair<int64_t, int64_t>, double> heights;  // grid point -> first chunk's height
  uint64_t disagreeing = 0;  // later chunk vertices whose height differs from the first
  double zStep = 0;          // coarsest height quantisation among the level's chunks
  double minZ = INFINITY;    // lowest surface the node table promises (skirts excluded)
};

LevelFacts levelFacts(const std::string& path, uint32_t level) {
  LevelFacts facts;
  auto opened = TilesetReader::openFile(path);
  EXPECT_TRUE(opened.ok()) << opened.error().message;
  if (!opened) return facts;
  const TilesetReader& t = **opened;
  for (uint32_t i = 0; i < t.nodes().size(); ++i) {
    const NodeRecord& n = t.nodes()[i];
    if (n.level != level) continue;
    ++facts.chunks;
    facts.triangles += n.triangleCount;
    facts.minZ = std::min(facts.minZ, double(n.minZ));
    auto g = t.readChunk(i);
    EXPECT_TRUE(g.ok()) << g.error().message;
    if (!g) continue;
    const int64_t side = t.header().chunkCells(n.level);
    facts.zStep = std::max(facts.zStep, g->zStep);
    for (const ChunkPart& part : g->parts) {
      std::vector<bool> surface(part.vertices.size(), false);
      for (uint32_t k = 0; k < part.surfaceIndexCount; ++k) surface[part.indices[k]] = true;
      for (size_t v = 0; v < part.vertices.size(); ++v) {
        if (!surface[v]) continue;
        const ChunkVertex& cv = part.vertices[v];
        const double z = g->zBase + double(cv.z) * g->zStep;
        const auto [it, fresh] =
            facts.heights.try_emplace({n.x * side + cv.x, n.y * side + cv.y}, z);
        if (!fresh) facts.disagreeing += std::fabs(it->second - z) > kHeightTolerance;
      }
    }
  }
  return facts;
}

Mesh readObj(const std::string& path) {
  Mesh mesh;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string kind;
    words >> kind;
    if (kind == "v") {
      std::array<float, 3> p{};
      words >> p[0] >> p[1] >> p[2];
      EXPECT_FALSE(words.fail()) << line;
      mesh.positions.push_back(p);
    } else if (kind == "f") {
      uint64_t a = 0, b = 0, c = 0;
      words >> a >> b >> c;
      EXPECT_FALSE(words.fail()) << line;
      EXPECT_TRUE(a >= 1 && b >= 1 && c >= 1) << "OBJ indices are 1-based: " << line;
      for (uint64_t i : {a, b, c}) mesh.indices.push_back(uint32_t(i - 1));
    } else {
      EXPECT_TRUE(kind.empty() || kind[0] == '#') << "unexpected OBJ line: " << line;
    }
  }
  return mesh;
}

Mesh readPly(const std::string& path) {
  Mesh mesh;
  const std::string bytes = readWholeFile(path);
  const size_t end = bytes.find("end_header\n");
  if (end == std::string::npos) {
    ADD_FAILURE() << path << ": no PLY header";
    return mesh;
  }
  const std::string header = bytes.substr(0, end);
  EXPECT_EQ(header.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u) << header;
  for (const char* line : {"property float x\nproperty float y\nproperty float z\n",
                           "property list uchar uint vertex_indices\n"})
    EXPECT_NE(header.find(line), std::string::npos) << header;
  size_t vertices = 0, faces = 0;
  std::istringstream lines(header);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::string keyword, element;
    size_t count = 0;
    if (words >> keyword >> element >> count && keyword == "element")
      (element == "vertex" ? vertices : faces) = count;
  }
  const char* data = bytes.data() + end + std::strlen("end_header\n");
  EXPECT_EQ(size_t(bytes.data() + bytes.size() - data), vertices * 12 + faces * 13);
  if (size_t(bytes.data() + bytes.size() - data) != vertices * 12 + faces * 13) return mesh;
  mesh.positions.resize(vertices);
  std::memcpy(mesh.positions.data(), data, vertices * 12);
  data += vertices * 12;
  for (size_t f = 0; f < faces; ++f, data += 13) {
    EXPECT_EQ(uint8_t(data[0]), 3u) << "face " << f;
    uint32_t abc[3];
    std::memcpy(abc, data + 1, sizeof(abc));
    mesh.indices.insert(mesh.indices.end(), abc, abc + 3);
  }
  return mesh;
}

// The welded surface of the level, no more and no less: one vertex per grid point the level's
// triangles use, at the first chunk's height, every surface triangle, nothing outside the
// extent and nothing below it (skirts hang below the surface). Heights are quantised, so the
// surface may leave the data's height range by half a quantisation step.
void expectLevelSurface(const Mesh& mesh, const LevelFacts& facts, const nlohmann::json& info) {
  EXPECT_EQ(mesh.indices.size(), 3 * facts.triangles);
  EXPECT_EQ(mesh.positions.size(), facts.heights.size());
  for (size_t k = 0; k < mesh.indices.size(); k += 3) {
    const uint32_t a = mesh.indices[k], b = mesh.indices[k + 1], c = mesh.indices[k + 2];
    ASSERT_LT(std::max({a, b, c}), mesh.positions.size());
    const auto &pa = mesh.positions[a], &pb = mesh.positions[b], &pc = mesh.positions[c];
    const double up = (double(pb[0]) - pa[0]) * (double(pc[1]) - pa[1]) -
                      (double(pb[1]) - pa[1]) * (double(pc[0]) - pa[0]);
    ASSERT_GT(up, 0.0) << "triangle " << k / 3 << " is not counter-clockwise seen from above";
  }
  const auto lo = info["extent"]["min"].get<std::array<double, 3>>();
  const auto hi = info["extent"]["max"].get<std::array<double, 3>>();
  const auto spacing = info["spacing"].get<std::array<double, 2>>();
  std::set<std::pair<int64_t, int64_t>> seen;
  for (const auto& p : mesh.positions) {
    for (int c = 0; c < 3; ++c) {
      const double quantised = c == 2 ? 0.5 * facts.zStep : 0.0;
      ASSERT_GE(p[c], lo[c] - quantised - floatSlack(lo[c])) << "axis " << c;
      ASSERT_LE(p[c], hi[c] + quantised + floatSlack(hi[c])) << "axis " << c;
    }
    ASSERT_GE(p[2], facts.minZ - floatSlack(facts.minZ)) << "below the surface: a skirt?";
    const std::pair<int64_t, int64_t> grid = {std::llround(p[0] / spacing[0]),
                                              std::llround(p[1] / spacing[1])};
    ASSERT_NEAR(p[0], grid.first * spacing[0], floatSlack(p[0])) << "not on a grid point";
    ASSERT_NEAR(p[1], grid.second * spacing[1], floatSlack(p[1])) << "not on a grid point";
    ASSERT_TRUE(seen.insert(grid).second)
        << "grid point " << grid.first << "," << grid.second << " exported twice (not welded)";
    const auto expected = facts.heights.find(grid);
    ASSERT_NE(expected, facts.heights.end())
        << "grid point " << grid.first << "," << grid.second << " is not on the level's surface";
    ASSERT_NEAR(p[2], expected->second, floatSlack(expected->second));
  }
}

nlohmann::json infoJson(const std::string& tileset) {
  const RunResult r = runTerralod({"info", tileset, "--json"});
  EXPECT_EQ(r.exitCode, 0) << r.err;
  return nlohmann::json::parse(r.out, nullptr, false);
}

struct Dem {
  std::string file;
  std::vector<std::string> options;  ///< for `terralod build`
};

// Names the case in ctest's output instead of dumping its bytes.
void PrintTo(const Dem& dem, std::ostream* out) {
  *out << dem.file;
}

// A real tileset per case, built fresh for every test.
class Export : public ::testing::TestWithParam<Dem> {
 protected:
  void SetUp() override {
    std::vector<std::string> build = {"build", testData(GetParam().file), "-o", mTileset};
    build.insert(build.end(), GetParam().options.begin(), GetParam().options.end());
    const RunResult built = runTerralod(build);
    ASSERT_EQ(built.exitCode, 0) << built.err;
    mInfo = infoJson(mTileset);
    ASSERT_FALSE(mInfo.is_discarded());
    mLevels = mInfo["levels"].get<uint32_t>();
  }
  // Exports and checks the summary line; returns the facts the mesh must match.
  LevelFacts exportLevel(const std::string& output, std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"export", mTileset, "-o", output};
    args.insert(args.end(), extra.begin(), extra.end());
    const uint32_t level = extra.empty() ? mLevels - 1 : uint32_t(std::stoul(extra.back()));
    const LevelFacts facts = levelFacts(mTileset, level);
    const RunResult r = runTerralod(args);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    // The exporter warns exactly when neighbouring chunks disagree about a shared height.
    if (facts.disagreeing)
      EXPECT_NE(r.err.find(std::to_string(facts.disagreeing) + " of "), std::string::npos) << r.err;
    else
      EXPECT_EQ(r.err, "");
    EXPECT_NE(r.out.find("terralod: wrote " + output + ": level " + std::to_string(level) + ", " +
                         std::to_string(facts.chunks) + " chunks, " +
                         std::to_string(facts.heights.size()) + " vertices"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find(std::to_string(facts.triangles) + " triangles, " +
                         std::to_string(fs::file_size(output)) + " bytes"),
              std::string::npos)
        << r.out;
    return facts;
  }

  TempDir mDir;
  std::string mTileset = mDir.file("t.tlod");
  nlohmann::json mInfo;
  uint32_t mLevels = 0;
};

TEST_P(Export, ObjIsTheWeldedSurfaceOfTheFinestLevel) {
  const std::string obj = mDir.file("surface.obj");
  const LevelFacts facts = exportLevel(obj);
  expectLevelSurface(readObj(obj), facts, mInfo);
}

TEST_P(Export, PlyIsTheWeldedSurfaceOfEveryLevel) {
  for (uint32_t level = 0; level < mLevels; ++level) {
    SCOPED_TRACE("level " + std::to_string(level));
    const std::string ply = mDir.file("level" + std::to_string(level) + ".PLY");
    const LevelFacts facts = exportLevel(ply, {"--level", std::to_string(level)});
    expectLevelSurface(readPly(ply), facts, mInfo);
  }
}

TEST_P(Export, GlbPassesTheKhronosValidator) {
  const std::string node = TERRALOD_NODE;
  const std::string tools = std::string(TERRALOD_SOURCE_DIR) + "/tests/tools";
  ASSERT_FALSE(node.empty()) << "node was not found when configuring; it runs the glTF validator";
  ASSERT_TRUE(fs::exists(tools + "/node_modules/gltf-validator/package.json"))
      << "the Khronos glTF validator is not installed: run scripts/install-deps.sh (make test "
         "does), which runs `npm ci` in tests/tools";
  for (uint32_t level : {0u, mLevels - 1}) {
    SCOPED_TRACE("level " + std::to_string(level));
    const std::string glb = mDir.file("level" + std::to_string(level) + ".glb");
    const LevelFacts facts = exportLevel(glb, {"--level", std::to_string(level)});
    const RunResult validated = runProgram(node, {tools + "/validate-gltf.mjs", glb});
    const auto report = nlohmann::json::parse(validated.out, nullptr, false);
    ASSERT_FALSE(report.is_discarded()) << validated.out << validated.err;
    EXPECT_EQ(report["errors"].get<int>(), 0) << report.dump(2);
    EXPECT_EQ(report["warnings"].get<int>(), 0) << report.dump(2);
    EXPECT_EQ(validated.exitCode, 0) << validated.err;
    std::printf("glTF validator %s on %s: %d errors, %d warnings, %d infos, %d hints\n",
                report["validator"].get<std::string>().c_str(), glb.c_str(),
                report["errors"].get<int>(), report["warnings"].get<int>(),
                report["infos"].get<int>(), report["hints"].get<int>());

    // The validator checks the file is well formed; the counts and axes are ours to check.
    const std::string bytes = readWholeFile(glb);
    ASSERT_GT(bytes.size(), 20u);
    uint32_t jsonBytes = 0;
    std::memcpy(&jsonBytes, bytes.data() + 12, 4);
    const auto gltf = nlohmann::json::parse(bytes.substr(20, jsonBytes));
    EXPECT_EQ(gltf["asset"]["generator"], "terralod");
    const auto& accessors = gltf["accessors"];
    EXPECT_EQ(accessors[0]["count"].get<uint64_t>(), facts.heights.size());
    EXPECT_EQ(accessors[1]["count"].get<uint64_t>(), 3 * facts.triangles);
    // y up: glTF (x, y, z) is terralod (x, z, -y).
    const auto lo = mInfo["extent"]["min"].get<std::array<double, 3>>();
    const auto hi = mInfo["extent"]["max"].get<std::array<double, 3>>();
    const auto min = accessors[0]["min"].get<std::array<double, 3>>();
    const auto max = accessors[0]["max"].get<std::array<double, 3>>();
    EXPECT_NEAR(min[0], lo[0], floatSlack(lo[0]));
    EXPECT_NEAR(max[0], hi[0], floatSlack(hi[0]));
    EXPECT_GE(min[1], lo[2] - 0.5 * facts.zStep - floatSlack(lo[2]));
    EXPECT_LE(max[1], hi[2] + 0.5 * facts.zStep + floatSlack(hi[2]));
    EXPECT_NEAR(min[2], -hi[1], floatSlack(hi[1]));
    EXPECT_NEAR(max[2], -lo[1], floatSlack(lo[1]));
  }
}

TEST_P(Export, BadInputsGetOneErrorLineAndNoOutput) {
  const std::string d = mDir.path().string();
  // A tileset whose finest level has a damaged chunk (the node table still reads).
  {
    auto opened = TilesetReader::openFile(mTileset);
    ASSERT_TRUE(opened.ok());
    const NodeRecord& leaf = (*opened)->nodes().back();
    std::string bytes = readWholeFile(mTileset);
    bytes[leaf.blobOffset + leaf.blobBytes / 2] ^= 0x40;
    std::ofstream(mDir.file("corrupt.tlod"), std::ios::binary) << bytes;
  }
  fs::create_directory(mDir.file("folder.glb"));
  const std::vector<std::string> before = filesIn(mDir.path());
  struct Case {
    std::vector<std::string> args;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {{"export", mTileset, "-o", d + "/mesh.stl"}, "mesh.stl: unknown output format '.stl'"},
      {{"export", mTileset, "-o", d + "/mesh"}, "mesh: unknown output format (no extension)"},
      {{"export", mTileset, "--level", std::to_string(mLevels), "-o", d + "/mesh.obj"},
       "t.tlod: no level " + std::to_string(mLevels) + "; this tileset has levels 0 to " +
           std::to_string(mLevels - 1)},
      {{"export", mTileset, "--level", "-1", "-o", d + "/mesh.obj"}, "t.tlod: no level -1"},
      {{"export", d + "/missing.tlod", "-o", d + "/mesh.glb"}, "missing.tlod: no such file"},
      {{"export", d + "/corrupt.tlod", "-o", d + "/mesh.ply"}, "corrupt.tlod"},
      {{"export", mTileset, "-o", d + "/no/dir/mesh.obj"}, "does not exist"},
      {{"export", mTileset, "-o", d + "/folder.glb"}, "folder.glb: is a directory"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.expected);
    expectOneErrorLine(runTerralod(c.args), c.expected);
    EXPECT_EQ(filesIn(mDir.path()), before) << "partial output left behind";
  }
}

TEST_P(Export, FailureNeverTouchesAnExistingOutput) {
  {
    auto opened = TilesetReader::openFile(mTileset);
    ASSERT_TRUE(opened.ok());
    const NodeRecord& leaf = (*opened)->nodes().back();
    std::string bytes = readWholeFile(mTileset);
    bytes[leaf.blobOffset + leaf.blobBytes / 2] ^= 0x40;
    std::ofstream(mDir.file("corrupt.tlod"), std::ios::binary) << bytes;
  }
  std::ofstream(mDir.file("old.obj")) << "# an earlier export\n";
  const std::vector<std::string> before = filesIn(mDir.path());
  expectOneErrorLine(runTerralod({"export", mDir.file("corrupt.tlod"), "-o", mDir.file("old.obj")}),
                     "corrupt.tlod");
  EXPECT_EQ(readWholeFile(mDir.file("old.obj")), "# an earlier export\n");
  EXPECT_EQ(filesIn(mDir.path()), before);
  // ...and a successful export replaces it.
  exportLevel(mDir.file("old.obj"));
  EXPECT_NE(readWholeFile(mDir.file("old.obj")).find("\nv "), std::string::npos);
}

// Square and power-of-two sized; small, odd-sized and mostly void; and one whose neighbouring
// chunks at the finest level round a few shared heights differently (the exporter warns).
INSTANTIATE_TEST_SUITE_P(Dems, Export,
                         ::testing::Values(Dem{"gzcommon_dem_squared_129.tif", {}},
                                           Dem{"landlab_west_bijou_gully_3m.asc",
                                               {"--max-error", "0.1"}},
                                           Dem{"zion_srtm3_utm12_30m.tif", {}}),
                         [](const ::testing::TestParamInfo<Dem>& param) {
                           return param.param.file.substr(0, param.param.file.find('_'));
                         });

}  // namespace
}  // namespace terralod::test
