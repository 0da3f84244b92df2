// `terralod export`: the surface of one level as OBJ, PLY or GLB. The meshes are read back and
// checked against the tileset itself (read independently through the format library): every
// chunk of the level, no skirts, shared vertices welded, positions in the tileset's extent,
// unit normals that agree with the triangles, texture coordinates 0..1 over the extent, and the
// colour texture (embedded in GLB, beside OBJ and PLY) resembling the tileset's own tiles, the
// right way up; GLB files must pass the Khronos glTF validator; bad inputs get one error line
// and no output.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "cli_expectations.h"
#include "cli_runner.h"
#include "gltf_validator.h"
#include "shared_directory.h"
#include "terralod/format/chunk_position.h"
#include "terralod/format/node_colour.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/render/image.h"

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
  std::vector<std::array<float, 3>> normals;
  std::vector<std::array<float, 2>> texcoords;  // v north, as OBJ and PLY count it
  std::string textureFile;      // OBJ: the .mtl's map_Kd; PLY: its TextureFile comment
  std::string materialLibrary;  // OBJ: mtllib
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
    if (kind == "v" || kind == "vn") {
      std::array<float, 3> p{};
      words >> p[0] >> p[1] >> p[2];
      EXPECT_FALSE(words.fail()) << line;
      (kind == "v" ? mesh.positions : mesh.normals).push_back(p);
    } else if (kind == "vt") {
      std::array<float, 2> uv{};
      words >> uv[0] >> uv[1];
      EXPECT_FALSE(words.fail()) << line;
      mesh.texcoords.push_back(uv);
    } else if (kind == "f") {
      // v/vt/vn: the exporter gives every vertex one index for all three.
      for (int corner = 0; corner < 3; ++corner) {
        std::string triple;
        words >> triple;
        uint64_t v = 0, t = 0, n = 0;
        char slash1 = 0, slash2 = 0;
        std::istringstream parts(triple);
        parts >> v >> slash1 >> t >> slash2 >> n;
        EXPECT_TRUE(!parts.fail() && slash1 == '/' && slash2 == '/') << line;
        EXPECT_TRUE(v == t && t == n) << "one index per vertex: " << line;
        EXPECT_GE(v, 1u) << "OBJ indices are 1-based: " << line;
        mesh.indices.push_back(uint32_t(v - 1));
      }
    } else if (kind == "mtllib") {
      words >> mesh.materialLibrary;
    } else if (kind == "usemtl") {
      std::string material;
      words >> material;
      EXPECT_EQ(material, "terrain");
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
  for (const char* line :
       {"property float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float "
        "ny\nproperty float nz\nproperty float u\nproperty float v\nelement face",
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
    if (line.rfind("comment TextureFile ", 0) == 0) mesh.textureFile = line.substr(20);
  }
  constexpr size_t kVertexBytes = 32;  // x y z nx ny nz u v
  const char* data = bytes.data() + end + std::strlen("end_header\n");
  EXPECT_EQ(size_t(bytes.data() + bytes.size() - data), vertices * kVertexBytes + faces * 13);
  if (size_t(bytes.data() + bytes.size() - data) != vertices * kVertexBytes + faces * 13)
    return mesh;
  mesh.positions.resize(vertices);
  mesh.normals.resize(vertices);
  mesh.texcoords.resize(vertices);
  for (size_t v = 0; v < vertices; ++v, data += kVertexBytes) {
    std::memcpy(mesh.positions[v].data(), data, 12);
    std::memcpy(mesh.normals[v].data(), data + 12, 12);
    std::memcpy(mesh.texcoords[v].data(), data + 24, 8);
  }
  for (size_t f = 0; f < faces; ++f, data += 13) {
    EXPECT_EQ(uint8_t(data[0]), 3u) << "face " << f;
    uint32_t abc[3];
    std::memcpy(abc, data + 1, sizeof(abc));
    mesh.indices.insert(mesh.indices.end(), abc, abc + 3);
  }
  return mesh;
}

// A .glb's JSON and binary chunk.
struct Glb {
  nlohmann::json json;
  std::string bin;
};

Glb readGlb(const std::string& path) {
  Glb glb;
  const std::string bytes = readWholeFile(path);
  if (bytes.size() < 28) {
    ADD_FAILURE() << path << ": too short for a GLB";
    return glb;
  }
  uint32_t jsonBytes = 0, binBytes = 0;
  std::memcpy(&jsonBytes, bytes.data() + 12, 4);
  glb.json = nlohmann::json::parse(bytes.substr(20, jsonBytes), nullptr, false);
  EXPECT_FALSE(glb.json.is_discarded());
  if (20 + size_t(jsonBytes) + 8 <= bytes.size()) {
    std::memcpy(&binBytes, bytes.data() + 20 + jsonBytes, 4);
    glb.bin = bytes.substr(20 + jsonBytes + 8, binBytes);
  }
  return glb;
}

// The bytes of a buffer view of the GLB's binary chunk.
std::string bufferViewBytes(const Glb& glb, size_t view) {
  const auto& v = glb.json["bufferViews"][view];
  const size_t offset = v.value("byteOffset", size_t(0)), length = v["byteLength"].get<size_t>();
  EXPECT_LE(offset + length, glb.bin.size());
  return glb.bin.substr(offset, length);
}

template <size_t N>
std::vector<std::array<float, N>> floatAccessor(const Glb& glb, size_t accessor) {
  const auto& a = glb.json["accessors"][accessor];
  EXPECT_EQ(a["componentType"], 5126);
  EXPECT_EQ(a["type"], N == 2 ? "VEC2" : "VEC3");
  const std::string bytes = bufferViewBytes(glb, a["bufferView"].get<size_t>());
  std::vector<std::array<float, N>> out(a["count"].get<size_t>());
  EXPECT_EQ(bytes.size(), out.size() * N * 4);
  if (bytes.size() == out.size() * N * 4) std::memcpy(out.data(), bytes.data(), bytes.size());
  return out;
}

// The GLB's mesh back in terralod's axes: glTF (x, y, z) is terralod (x, -z, y), and its v
// counts from the image's northern row.
Mesh meshFromGlb(const Glb& glb) {
  Mesh mesh;
  const auto& primitive = glb.json["meshes"][0]["primitives"][0];
  const auto& attributes = primitive["attributes"];
  for (const char* name : {"POSITION", "NORMAL", "TEXCOORD_0"})
    EXPECT_TRUE(attributes.contains(name)) << name;
  if (!attributes.contains("POSITION") || !attributes.contains("NORMAL") ||
      !attributes.contains("TEXCOORD_0"))
    return mesh;
  for (const auto& p : floatAccessor<3>(glb, attributes["POSITION"].get<size_t>()))
    mesh.positions.push_back({p[0], 0.0f - p[2], p[1]});
  for (const auto& n : floatAccessor<3>(glb, attributes["NORMAL"].get<size_t>()))
    mesh.normals.push_back({n[0], 0.0f - n[2], n[1]});
  for (const auto& uv : floatAccessor<2>(glb, attributes["TEXCOORD_0"].get<size_t>()))
    mesh.texcoords.push_back({uv[0], 1.0f - uv[1]});
  const auto& indices = glb.json["accessors"][primitive["indices"].get<size_t>()];
  EXPECT_EQ(indices["componentType"], 5125);
  const std::string bytes = bufferViewBytes(glb, indices["bufferView"].get<size_t>());
  mesh.indices.resize(indices["count"].get<size_t>());
  EXPECT_EQ(bytes.size(), mesh.indices.size() * 4);
  if (bytes.size() == mesh.indices.size() * 4)
    std::memcpy(mesh.indices.data(), bytes.data(), bytes.size());
  return mesh;
}

// Normals: unit, up on average and where every triangle around a vertex faces (each vertex's is
// checked against the angle-weighted mean of its triangles' normals, worked out here again).
// Texture coordinates: u = x / width, v = y / height of the data's extent.
void expectNormalsAndTexcoords(const Mesh& mesh, const nlohmann::json& info) {
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  ASSERT_EQ(mesh.texcoords.size(), mesh.positions.size());
  using V = std::array<double, 3>;
  std::vector<V> expected(mesh.positions.size(), V{0, 0, 0});
  for (size_t k = 0; k + 2 < mesh.indices.size(); k += 3) {
    V p[3];
    for (int i = 0; i < 3; ++i)
      for (int c = 0; c < 3; ++c) p[i][c] = mesh.positions[mesh.indices[k + i]][c];
    for (int i = 0; i < 3; ++i) {
      const V& o = p[i];
      V a, b;
      for (int c = 0; c < 3; ++c) {
        a[c] = p[(i + 1) % 3][c] - o[c];
        b[c] = p[(i + 2) % 3][c] - o[c];
      }
      const V n = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
      const double nl = std::hypot(n[0], n[1], n[2]);
      const double angle =
          std::acos(std::clamp((a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) /
                                   (std::hypot(a[0], a[1], a[2]) * std::hypot(b[0], b[1], b[2])),
                               -1.0, 1.0));
      for (int c = 0; c < 3; ++c) expected[mesh.indices[k + i]][c] += angle * n[c] / nl;
    }
  }
  double upSum = 0, worst = 0;
  for (size_t v = 0; v < mesh.normals.size(); ++v) {
    const auto& n = mesh.normals[v];
    const double length = std::hypot(double(n[0]), double(n[1]), double(n[2]));
    ASSERT_NEAR(length, 1.0, 1e-5) << "vertex " << v;
    ASSERT_GT(n[2], 0.0f) << "vertex " << v << " faces down";
    upSum += n[2];
    const V& e = expected[v];
    const double el = std::hypot(e[0], e[1], e[2]);
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::fabs(n[c] - e[c] / el));
  }
  EXPECT_LT(worst, 1e-4) << "a normal differs from its triangles' angle-weighted mean";
  EXPECT_GT(upSum / double(mesh.normals.size()), 0.7) << "normals do not point up on average";

  const auto size = info["source_size"].get<std::array<double, 2>>();
  const auto spacing = info["spacing"].get<std::array<double, 2>>();
  const double width = (size[0] - 1) * spacing[0], height = (size[1] - 1) * spacing[1];
  std::array<float, 2> lo = {1, 1}, hi = {0, 0};
  for (size_t v = 0; v < mesh.texcoords.size(); ++v) {
    const auto& uv = mesh.texcoords[v];
    ASSERT_NEAR(uv[0], mesh.positions[v][0] / width, 1e-6) << "vertex " << v;
    ASSERT_NEAR(uv[1], mesh.positions[v][1] / height, 1e-6) << "vertex " << v;
    for (int c = 0; c < 2; ++c) {
      lo[c] = std::min(lo[c], uv[c]);
      hi[c] = std::max(hi[c], uv[c]);
    }
  }
  // The finest levels reach every edge of the data.
  for (int c = 0; c < 2; ++c) {
    EXPECT_GE(lo[c], 0.0f);
    EXPECT_LE(hi[c], 1.0f);
  }
}

// The tileset's colour averaged over a grid x grid of regions of the data's extent, from every
// texel the finest level draws (its own tile or its part of its parent's), row 0 south.
using RegionColours = std::vector<std::array<double, 3>>;
constexpr int kRegions = 8;

RegionColours tilesetRegionColours(const std::string& path) {
  RegionColours sums(kRegions * kRegions, {0, 0, 0});
  std::vector<double> counts(kRegions * kRegions, 0);
  auto opened = TilesetReader::openFile(path);
  EXPECT_TRUE(opened.ok());
  if (!opened) return sums;
  const TilesetReader& t = **opened;
  const TilesetHeader& h = t.header();
  const double cellsX = h.sourceColumns - 1, cellsY = h.sourceRows - 1;
  for (uint32_t i = 0; i < t.nodes().size(); ++i) {
    const NodeRecord& n = t.nodes()[i];
    if (n.level + 1u != h.levelCount) continue;
    auto colour = readNodeColour(t, i);  // its own, or its part of its parent's
    EXPECT_TRUE(colour.ok() && !colour->rgb.empty()) << i;
    if (!colour.ok() || colour->rgb.empty()) continue;
    const std::vector<uint8_t>& rgb = colour->rgb;
    const double side = h.chunkCells(n.level), step = side / (colour->size - 1);
    const auto [x0, y0] = chunkCellOrigin(h, n);
    for (uint32_t y = 0; y < colour->size; ++y)
      for (uint32_t x = 0; x < colour->size; ++x) {
        const double cx = x0 + x * step, cy = y0 + y * step;
        if (cx > cellsX || cy > cellsY) continue;
        const int rx = std::min(kRegions - 1, int(cx / cellsX * kRegions));
        const int ry = std::min(kRegions - 1, int(cy / cellsY * kRegions));
        for (int c = 0; c < 3; ++c)
          sums[ry * kRegions + rx][c] += rgb[(y * colour->size + x) * 3 + c];
        counts[ry * kRegions + rx] += 1;
      }
  }
  for (size_t r = 0; r < sums.size(); ++r)
    for (double& c : sums[r]) c /= std::max(1.0, counts[r]);
  return sums;
}

// The same regions of an exported image (its top row north).
RegionColours imageRegionColours(const Image& image) {
  RegionColours sums(kRegions * kRegions, {0, 0, 0});
  std::vector<double> counts(kRegions * kRegions, 0);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const int rx = std::min(kRegions - 1, int((x + 0.5) / image.width * kRegions));
      const int ry = std::min(kRegions - 1, int((1 - (y + 0.5) / image.height) * kRegions));
      const auto p = image.pixel(x, y);
      for (int c = 0; c < 3; ++c) sums[ry * kRegions + rx][c] += p[c];
      counts[ry * kRegions + rx] += 1;
    }
  for (size_t r = 0; r < sums.size(); ++r)
    for (double& c : sums[r]) c /= std::max(1.0, counts[r]);
  return sums;
}

// Mean absolute difference (0..255) between two region grids, the second optionally mirrored
// north-south or east-west.
double regionDifference(const RegionColours& a, const RegionColours& b, bool flipY, bool flipX) {
  double total = 0;
  for (int y = 0; y < kRegions; ++y)
    for (int x = 0; x < kRegions; ++x) {
      const auto& p = a[y * kRegions + x];
      const auto& q = b[(flipY ? kRegions - 1 - y : y) * kRegions + (flipX ? kRegions - 1 - x : x)];
      for (int c = 0; c < 3; ++c) total += std::fabs(p[c] - q[c]);
    }
  return total / (3 * kRegions * kRegions);
}

// The exported image is `width` x `height` and looks like the tileset's colour, the right way
// up: region by region within a few grey levels, and much closer than mirrored either way.
void expectImageResemblesTileset(const Image& image, const std::string& tileset, int width,
                                 int height) {
  EXPECT_EQ(image.width, width);
  EXPECT_EQ(image.height, height);
  const RegionColours expected = tilesetRegionColours(tileset);
  const RegionColours actual = imageRegionColours(image);
  const double same = regionDifference(actual, expected, false, false);
  const double flippedY = regionDifference(actual, expected, true, false);
  const double flippedX = regionDifference(actual, expected, false, true);
  std::printf(
      "texture %dx%d: mean |difference| to the tileset's colour %.2f per region and "
      "channel (mirrored north-south %.2f, east-west %.2f)\n",
      image.width, image.height, same, flippedY, flippedX);
  EXPECT_LT(same, 3.0);
  EXPECT_GT(flippedY, 3 * same + 1);
  EXPECT_GT(flippedX, 3 * same + 1);
}

Image readPngBytes(const TempDir& dir, const std::string& bytes) {
  const std::string path = dir.file("embedded-texture.png");
  std::ofstream(path, std::ios::binary) << bytes;
  auto image = readPng(path);
  EXPECT_TRUE(image.ok()) << image.error().message;
  fs::remove(path);
  return image ? *image : Image{};
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

// Runs `terralod export` and checks its summary lines; returns the facts the mesh must match.
// `level` defaults to the finest; `extra` are further options.
LevelFacts runExport(const std::string& tileset, uint32_t levels, const std::string& output,
                     std::optional<uint32_t> level = std::nullopt,
                     std::vector<std::string> extra = {}) {
  std::vector<std::string> args = {"export", tileset, "-o", output};
  if (level) args.insert(args.end(), {"--level", std::to_string(*level)});
  args.insert(args.end(), extra.begin(), extra.end());
  const uint32_t exported = level.value_or(levels - 1);
  const LevelFacts facts = levelFacts(tileset, exported);
  const RunResult r = runTerralod(args);
  EXPECT_EQ(r.exitCode, 0) << r.err;
  // The exporter warns exactly when neighbouring chunks disagree about a shared height.
  if (facts.disagreeing)
    EXPECT_NE(r.err.find(std::to_string(facts.disagreeing) + " of "), std::string::npos) << r.err;
  else
    EXPECT_EQ(r.err, "");
  EXPECT_NE(r.out.find("terralod: wrote " + output + ": level " + std::to_string(exported) + ", " +
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

// A real tileset per case.
class Export : public ::testing::TestWithParam<Dem> {
 protected:
  // The tileset is built once per DEM for every test of the suite (and every process).
  void SetUp() override {
    const Dem& dem = GetParam();
    std::string options;  // part of the stamp: other options, another tileset
    for (const std::string& o : dem.options) options += " " + o;
    const SharedDirectory shared = sharedDirectory(
        "export-" + dem.file.substr(0, dem.file.find('_')), programStamp(TERRALOD_CLI) + options,
        [&dem](const std::string& dir) {
          std::vector<std::string> build = {"build", testData(dem.file), "-o", dir + "/t.tlod"};
          build.insert(build.end(), dem.options.begin(), dem.options.end());
          const RunResult built = runTerralod(build);
          return built.exitCode == 0 ? std::string() : built.err;
        });
    ASSERT_EQ(shared.error, "");
    mTileset = shared.file("t.tlod");
    mInfo = infoJson(mTileset);
    ASSERT_FALSE(mInfo.is_discarded());
    mLevels = mInfo["levels"].get<uint32_t>();
  }
  LevelFacts exportLevel(const std::string& output, std::optional<uint32_t> level = std::nullopt,
                         std::vector<std::string> extra = {}) {
    return runExport(mTileset, mLevels, output, level, std::move(extra));
  }

  TempDir mDir;          // what a test writes
  std::string mTileset;  // shared: never modified
  nlohmann::json mInfo;
  uint32_t mLevels = 0;
};

// The embedded image of a .glb, through its material: baseColorTexture -> texture -> image ->
// buffer view holding a PNG.
std::string embeddedPng(const Glb& glb) {
  const auto& j = glb.json;
  const auto& primitive = j["meshes"][0]["primitives"][0];
  EXPECT_TRUE(primitive.contains("material"));
  if (!primitive.contains("material")) return {};
  const auto& material = j["materials"][primitive["material"].get<size_t>()];
  const auto& pbr = material["pbrMetallicRoughness"];
  EXPECT_EQ(pbr["metallicFactor"].get<double>(), 0.0) << "terrain is not metal";
  EXPECT_TRUE(pbr.contains("baseColorTexture")) << material.dump();
  if (!pbr.contains("baseColorTexture")) return {};
  EXPECT_EQ(pbr["baseColorTexture"].value("texCoord", 0), 0);
  const auto& texture = j["textures"][pbr["baseColorTexture"]["index"].get<size_t>()];
  const auto& image = j["images"][texture["source"].get<size_t>()];
  EXPECT_EQ(image["mimeType"], "image/png");
  const std::string png = bufferViewBytes(glb, image["bufferView"].get<size_t>());
  EXPECT_EQ(png.rfind("\x89PNG\r\n\x1a\n", 0), 0u);
  return png;
}

// The tilesets these DEMs give are textured (generated colour), so the OBJ comes with a .mtl
// and a .png beside it.
TEST_P(Export, ObjIsTheWeldedSurfaceOfTheFinestLevel) {
  const std::string obj = mDir.file("surface.obj");
  const LevelFacts facts = exportLevel(obj, std::nullopt, {"--texture-size", "64"});
  const Mesh mesh = readObj(obj);
  expectLevelSurface(mesh, facts, mInfo);
  expectNormalsAndTexcoords(mesh, mInfo);
  EXPECT_EQ(mesh.materialLibrary, "surface.mtl");
  const std::string mtl = readWholeFile(mDir.file("surface.mtl"));
  EXPECT_NE(mtl.find("newmtl terrain\n"), std::string::npos) << mtl;
  EXPECT_NE(mtl.find("\nmap_Kd surface.png\n"), std::string::npos) << mtl;
  auto image = readPng(mDir.file("surface.png"));
  ASSERT_TRUE(image.ok()) << image.error().message;
  EXPECT_EQ(std::max(image->width, image->height), 64);
  EXPECT_EQ(filesIn(mDir.path()),
            (std::vector<std::string>{"surface.mtl", "surface.obj", "surface.png"}));
}

TEST_P(Export, PlyIsTheWeldedSurfaceOfEveryLevel) {
  for (uint32_t level = 0; level < mLevels; ++level) {
    SCOPED_TRACE("level " + std::to_string(level));
    const std::string name = "level" + std::to_string(level);
    const std::string ply = mDir.file(name + ".PLY");
    const LevelFacts facts = exportLevel(ply, level, {"--texture-size", "32"});
    const Mesh mesh = readPly(ply);
    expectLevelSurface(mesh, facts, mInfo);
    expectNormalsAndTexcoords(mesh, mInfo);
    EXPECT_EQ(mesh.textureFile, name + ".png");
    EXPECT_TRUE(readPng(mDir.file(name + ".png")).ok());
  }
}

TEST_P(Export, GlbPassesTheKhronosValidator) {
  for (uint32_t level : {0u, mLevels - 1}) {
    SCOPED_TRACE("level " + std::to_string(level));
    const std::string glb = mDir.file("level" + std::to_string(level) + ".glb");
    const LevelFacts facts = exportLevel(glb, level, {"--texture-size", "128"});
    expectValidGltf(glb);

    // The validator checks the file is well formed; the counts and axes are ours to check.
    const Glb parsed = readGlb(glb);
    const auto& gltf = parsed.json;
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

    const Mesh mesh = meshFromGlb(parsed);
    expectLevelSurface(mesh, facts, mInfo);
    expectNormalsAndTexcoords(mesh, mInfo);
    const Image image = readPngBytes(mDir, embeddedPng(parsed));
    EXPECT_EQ(std::max(image.width, image.height), 128);
  }
  EXPECT_EQ(
      filesIn(mDir.path()),
      (std::vector<std::string>{"level0.glb", "level" + std::to_string(mLevels - 1) + ".glb"}))
      << "a .glb needs no side files";
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
  // The texture's side file cannot be written: neither it nor the mesh may appear.
  fs::create_directory(mDir.file("blocked.png"));
  fs::create_directory(mDir.file("blocked2.mtl"));
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
      {{"export", mTileset, "-o", d + "/blocked.obj"}, "blocked.png: is a directory"},
      {{"export", mTileset, "-o", d + "/blocked.ply"}, "blocked.png: is a directory"},
      {{"export", mTileset, "-o", d + "/blocked2.obj"}, "blocked2.mtl: is a directory"},
      {{"export", mTileset, "--texture-size", "0", "-o", d + "/mesh.glb"},
       "--texture-size 0: must be 1 to 16384 pixels"},
      {{"export", mTileset, "--texture-size", "20000", "-o", d + "/mesh.glb"},
       "--texture-size 20000: must be 1 to 16384 pixels"},
      {{"export", mTileset, "--texture-size", "64", "--no-texture", "-o", d + "/mesh.glb"},
       "--texture-size excludes --no-texture"},
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
  std::ofstream(mDir.file("old.mtl")) << "# an earlier material\n";
  std::ofstream(mDir.file("old.png")) << "an earlier texture";
  const std::vector<std::string> before = filesIn(mDir.path());
  expectOneErrorLine(runTerralod({"export", mDir.file("corrupt.tlod"), "-o", mDir.file("old.obj")}),
                     "corrupt.tlod");
  EXPECT_EQ(readWholeFile(mDir.file("old.obj")), "# an earlier export\n");
  EXPECT_EQ(readWholeFile(mDir.file("old.mtl")), "# an earlier material\n");
  EXPECT_EQ(readWholeFile(mDir.file("old.png")), "an earlier texture");
  EXPECT_EQ(filesIn(mDir.path()), before);
  // ...and a successful export replaces them.
  exportLevel(mDir.file("old.obj"), 0u, {"--texture-size", "16"});
  EXPECT_NE(readWholeFile(mDir.file("old.obj")).find("\nv "), std::string::npos);
  EXPECT_NE(readWholeFile(mDir.file("old.mtl")).find("map_Kd old.png"), std::string::npos);
  EXPECT_TRUE(readPng(mDir.file("old.png")).ok());
}

// Square and power-of-two sized; small, odd-sized and mostly void; and a real SRTM tile of 414
// chunks at its finest level, at --max-error 8 so the meshes the tests read back stay small (at
// the default 1 m its finest level is a 188 MB OBJ of 1.78 M triangles, whose parsing took
// most of this suite's time).
INSTANTIATE_TEST_SUITE_P(Dems, Export,
                         ::testing::Values(Dem{"gzcommon_dem_squared_129.tif", {}},
                                           Dem{"landlab_west_bijou_gully_3m.asc",
                                               {"--max-error", "0.1"}},
                                           Dem{"zion_srtm3_utm12_30m.tif", {"--max-error", "8"}}),
                         [](const ::testing::TestParamInfo<Dem>& param) {
                           return param.param.file.substr(0, param.param.file.find('_'));
                         });

// Zion with its Landsat image draped: a real picture, not symmetric, so an image upside down
// or mirrored would show. Built once for the suite, at --max-error 8 (the meshes read back stay
// small; the textures are the same).
class ExportDrapedTexture : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sDir = new TempDir;
    sTileset = sDir->file("zion.tlod");
    const RunResult built = runTerralod({"build", testData("zion_srtm3_utm12_30m.tif"), "--texture",
                                         testData("zion_landsat8_rgb_utm12_30m.tif"), "--max-error",
                                         "8", "-o", sTileset});
    ASSERT_EQ(built.exitCode, 0) << built.err;
    sInfo = infoJson(sTileset);
    sLevels = sInfo["levels"].get<uint32_t>();
  }
  static void TearDownTestSuite() {
    delete sDir;
    sDir = nullptr;
  }
  void SetUp() override { ASSERT_FALSE(sInfo.is_discarded() || sLevels == 0); }
  // The image's size for `longSide` pixels along the data's longer side.
  static std::array<int, 2> imageSize(int longSide) {
    const auto size = sInfo["source_size"].get<std::array<double, 2>>();
    const double w = size[0] - 1, h = size[1] - 1;
    return w >= h ? std::array<int, 2>{longSide, int(std::max(1L, std::lround(longSide * h / w)))}
                  : std::array<int, 2>{int(std::max(1L, std::lround(longSide * w / h))), longSide};
  }

  static inline TempDir* sDir = nullptr;
  static inline std::string sTileset;
  static inline nlohmann::json sInfo;
  static inline uint32_t sLevels = 0;
  TempDir mDir;
};

TEST_F(ExportDrapedTexture, GlbEmbedsTheImageAtTheRequestedSize) {
  const std::string glb = mDir.file("zion.glb");
  runExport(sTileset, sLevels, glb, std::nullopt, {"--texture-size", "300"});
  expectValidGltf(glb);
  const Glb parsed = readGlb(glb);
  expectNormalsAndTexcoords(meshFromGlb(parsed), sInfo);
  const auto [w, h] = imageSize(300);
  expectImageResemblesTileset(readPngBytes(mDir, embeddedPng(parsed)), sTileset, w, h);
}

TEST_F(ExportDrapedTexture, ObjAndPlyWriteTheImageBeside) {
  const auto [w, h] = imageSize(200);
  for (const char* name : {"zion.obj", "zion.ply"}) {
    SCOPED_TRACE(name);
    runExport(sTileset, sLevels, mDir.file(name), 1u, {"--texture-size", "200"});
    auto image = readPng(mDir.file("zion.png"));
    ASSERT_TRUE(image.ok()) << image.error().message;
    expectImageResemblesTileset(*image, sTileset, w, h);
    fs::remove(mDir.file("zion.png"));
  }
  EXPECT_EQ(readObj(mDir.file("zion.obj")).materialLibrary, "zion.mtl");
  EXPECT_EQ(readPly(mDir.file("zion.ply")).textureFile, "zion.png");
}

// Without --texture-size the image has the tileset's full resolution (here one texel per DEM
// cell, less than the 2048 cap).
TEST_F(ExportDrapedTexture, DefaultSizeIsTheFullResolution) {
  const std::string glb = mDir.file("full.glb");
  const RunResult r = runTerralod({"export", sTileset, "--level", "0", "-o", glb});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto size = sInfo["source_size"].get<std::array<int, 2>>();
  const Image image = readPngBytes(mDir, embeddedPng(readGlb(glb)));
  EXPECT_EQ(image.width, size[0] - 1) << r.out;
  EXPECT_EQ(image.height, size[1] - 1) << r.out;
}

// --no-texture: normals and texture coordinates all the same, but no image anywhere, no
// material library, and a .glb that still validates. (Level 1, to keep it quick.)
TEST_F(ExportDrapedTexture, NoTextureWritesNoImage) {
  for (const char* name : {"plain.obj", "plain.ply", "plain.glb"}) {
    SCOPED_TRACE(name);
    const std::string path = mDir.file(name);
    const LevelFacts facts = runExport(sTileset, sLevels, path, 1u, {"--no-texture"});
    const Mesh mesh = std::string(name).ends_with(".obj")   ? readObj(path)
                      : std::string(name).ends_with(".ply") ? readPly(path)
                                                            : meshFromGlb(readGlb(path));
    expectLevelSurface(mesh, facts, sInfo);
    expectNormalsAndTexcoords(mesh, sInfo);
    EXPECT_EQ(mesh.materialLibrary, "");
    EXPECT_EQ(mesh.textureFile, "");
  }
  const Glb glb = readGlb(mDir.file("plain.glb"));
  for (const char* key : {"images", "textures", "samplers"}) EXPECT_FALSE(glb.json.contains(key));
  EXPECT_FALSE(glb.json["materials"][0]["pbrMetallicRoughness"].contains("baseColorTexture"));
  expectValidGltf(mDir.file("plain.glb"));
  EXPECT_EQ(filesIn(mDir.path()),
            (std::vector<std::string>{"plain.glb", "plain.obj", "plain.ply"}));
}

// An untextured tileset exports its mesh and says there is no texture to write.
TEST(ExportUntextured, WritesNoImageAndSaysSo) {
  TempDir dir;
  const std::string tileset = dir.file("plain.tlod");
  ASSERT_EQ(runTerralod(
                {"build", testData("gzcommon_dem_squared_129.tif"), "--no-texture", "-o", tileset})
                .exitCode,
            0);
  const RunResult r = runTerralod({"export", tileset, "-o", dir.file("plain.obj")});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("no texture (the tileset has none)"), std::string::npos) << r.out;
  const Mesh mesh = readObj(dir.file("plain.obj"));
  EXPECT_EQ(mesh.materialLibrary, "");
  EXPECT_EQ(mesh.normals.size(), mesh.positions.size());
  EXPECT_EQ(filesIn(dir.path()), (std::vector<std::string>{"plain.obj", "plain.tlod"}));
}

}  // namespace
}  // namespace terralod::test
