#include "terralod/tiles3d/chunk_glb.h"

#include <gtest/gtest.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include <glm/mat4x4.hpp>
#include <nlohmann/json.hpp>

namespace terralod::tiles3d {
namespace {

using nlohmann::json;

// A 1 x 1 PNG.
const std::vector<uint8_t> kPng = {
    0x89, 0x50, 0x4E, 0x47, 0x0D, 0x0A, 0x1A, 0x0A, 0x00, 0x00, 0x00, 0x0D, 0x49, 0x48,
    0x44, 0x52, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x06, 0x00, 0x00,
    0x00, 0x1F, 0x15, 0xC4, 0x89, 0x00, 0x00, 0x00, 0x0A, 0x49, 0x44, 0x41, 0x54, 0x78,
    0x9C, 0x63, 0x00, 0x01, 0x00, 0x00, 0x05, 0x00, 0x01, 0x0D, 0x0A, 0x2D, 0xB4, 0x00,
    0x00, 0x00, 0x00, 0x49, 0x45, 0x4E, 0x44, 0xAE, 0x42, 0x60, 0x82};

// A 5 x 5 grid, 10 m apart, on a slope, far from the frame's origin.
ChunkMesh grid() {
  ChunkMesh m;
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 5; ++x) {
      m.positions.push_back({1000.0 + 10 * x, -2000.0 + 10 * y, 100.0 + 3.7 * x + 0.013 * y});
      const float n[3] = {-0.35f, 0.0f, 0.94f};
      const float l = std::sqrt(n[0] * n[0] + n[2] * n[2]);
      m.normals.push_back({n[0] / l, n[1] / l, n[2] / l});
      m.texcoords.push_back({x / 4.0f, 1.0f - y / 4.0f});
    }
  for (uint32_t y = 0; y < 4; ++y)
    for (uint32_t x = 0; x < 4; ++x) {
      const uint32_t a = y * 5 + x;
      m.indices.insert(m.indices.end(), {a, a + 1, a + 6, a, a + 6, a + 5});
    }
  m.image = kPng;
  m.imageMimeType = "image/png";
  m.name = "chunk 7";
  return m;
}

struct Parsed {
  json gltf;
  std::vector<uint8_t> bin;
};
Parsed parse(const std::vector<uint8_t>& glb) {
  Parsed p;
  uint32_t header[3], chunk[2];
  std::memcpy(header, glb.data(), 12);
  EXPECT_EQ(header[0], 0x46546C67u);
  EXPECT_EQ(header[2], glb.size());
  std::memcpy(chunk, glb.data() + 12, 8);
  p.gltf = json::parse(std::string(glb.begin() + 20, glb.begin() + 20 + chunk[0]));
  const size_t binAt = 20 + chunk[0];
  std::memcpy(chunk, glb.data() + binAt, 8);
  EXPECT_EQ(chunk[1], 0x004E4942u);
  p.bin.assign(glb.begin() + long(binAt) + 8, glb.begin() + long(binAt) + 8 + chunk[0]);
  return p;
}

// The uncompressed bytes of bufferView `v`, through meshopt's decoders.
std::vector<uint8_t> decodeView(const Parsed& p, int v) {
  const json& e = p.gltf["bufferViews"][v]["extensions"]["EXT_meshopt_compression"];
  const size_t count = e["count"], stride = e["byteStride"];
  std::vector<uint8_t> out(count * stride);
  const uint8_t* src = p.bin.data() + e["byteOffset"].get<size_t>();
  const size_t size = e["byteLength"];
  const int rc = e["mode"] == "TRIANGLES"
                     ? meshopt_decodeIndexBuffer(out.data(), count, stride, src, size)
                     : meshopt_decodeVertexBuffer(out.data(), count, stride, src, size);
  EXPECT_EQ(rc, 0);
  return out;
}

TEST(ChunkGlb, QuantisedCompressedAndPlacedBackWhereItWas) {
  const ChunkMesh mesh = grid();
  auto glb = chunkGlb(mesh);
  ASSERT_TRUE(glb.ok()) << glb.error().message;
  EXPECT_LT(glb->quantisationError, 40.0 / 65535);
  EXPECT_EQ(glb->min[0], 1000.0);
  EXPECT_EQ(glb->max[1], -1960.0);
  const Parsed p = parse(glb->bytes);
  EXPECT_EQ(p.gltf["extensionsRequired"],
            json::array({"KHR_mesh_quantization", "EXT_meshopt_compression"}));
  const json& node = p.gltf["nodes"][0];
  EXPECT_EQ(node["name"], "chunk 7");
  glm::dmat4 matrix;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) matrix[c][r] = node["matrix"][c * 4 + r];
  // Positions: the node's matrix takes the decoded integers to glTF's y-up; (x, z, −y) back.
  const std::vector<uint8_t> positions = decodeView(p, 0);
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    uint16_t q[4];
    std::memcpy(q, positions.data() + 8 * i, 8);
    const glm::dvec4 g = matrix * glm::dvec4(q[0], q[1], q[2], 1);
    EXPECT_NEAR(g.x, mesh.positions[i][0], glb->quantisationError + 1e-9);
    EXPECT_NEAR(-g.z, mesh.positions[i][1], glb->quantisationError + 1e-9);
    EXPECT_NEAR(g.y, mesh.positions[i][2], glb->quantisationError + 1e-9);
  }
  // Normals: through the matrix's inverse transpose, as a renderer takes them, back to ours.
  const std::vector<uint8_t> normals = decodeView(p, 1);
  const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(matrix)));
  for (size_t i = 0; i < mesh.normals.size(); ++i) {
    const auto* q = reinterpret_cast<const int8_t*>(normals.data() + 4 * i);
    glm::dvec3 n = normalMatrix * glm::dvec3(q[0] / 127.0, q[1] / 127.0, q[2] / 127.0);
    n /= std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    EXPECT_NEAR(n.x, mesh.normals[i][0], 0.02);
    EXPECT_NEAR(-n.z, mesh.normals[i][1], 0.02);
    EXPECT_NEAR(n.y, mesh.normals[i][2], 0.02);
  }
  // Indices: the same triangles in the same order, each possibly rotated (the codec may start
  // a triangle at another corner; the winding stays).
  const std::vector<uint8_t> indices = decodeView(p, 3);
  for (size_t t = 0; t < mesh.indices.size(); t += 3) {
    uint16_t v[3];
    std::memcpy(v, indices.data() + 2 * t, 6);
    bool same = false;
    for (size_t r = 0; r < 3; ++r)
      same |= v[r] == mesh.indices[t] && v[(r + 1) % 3] == mesh.indices[t + 1] &&
              v[(r + 2) % 3] == mesh.indices[t + 2];
    EXPECT_TRUE(same) << "triangle " << t / 3;
  }
  EXPECT_EQ(p.gltf["images"][0]["mimeType"], "image/png");
  if (const char* keep = std::getenv("TERRALOD_KEEP_GLB"))
    std::ofstream(keep, std::ios::binary)
        .write(reinterpret_cast<const char*>(glb->bytes.data()), long(glb->bytes.size()));
}

// Vertex colours and an unlit material: COLOR_0 decodes back to the colours, the indices
// still come last, KHR_materials_unlit is on the material and in extensionsUsed.
TEST(ChunkGlb, ColoursAndUnlitMaterials) {
  ChunkMesh mesh = grid();
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    mesh.colors.push_back({uint8_t(10 * i), uint8_t(255 - i), uint8_t(i % 3)});
  mesh.light = MaterialLight::kUnlit;
  auto glb = chunkGlb(mesh);
  ASSERT_TRUE(glb.ok()) << glb.error().message;
  const Parsed p = parse(glb->bytes);
  const json& primitive = p.gltf["meshes"][0]["primitives"][0];
  const json& color = p.gltf["accessors"][primitive["attributes"]["COLOR_0"].get<int>()];
  EXPECT_EQ(color["type"], "VEC4");
  EXPECT_EQ(color["normalized"], true);
  const std::vector<uint8_t> colors = decodeView(p, color["bufferView"].get<int>());
  for (size_t i = 0; i < mesh.colors.size(); ++i)
    for (size_t k = 0; k < 3; ++k) EXPECT_EQ(colors[4 * i + k], mesh.colors[i][k]) << i;
  const json& indices = p.gltf["accessors"][primitive["indices"].get<int>()];
  EXPECT_EQ(indices["bufferView"].get<size_t>() + 1,
            p.gltf["bufferViews"].size() - 1);  // then the image
  EXPECT_TRUE(p.gltf["materials"][0]["extensions"].contains("KHR_materials_unlit"));
  EXPECT_NE(std::find(p.gltf["extensionsUsed"].begin(), p.gltf["extensionsUsed"].end(),
                      "KHR_materials_unlit"),
            p.gltf["extensionsUsed"].end());
  // Lit (the default): no such extension.
  mesh.light = MaterialLight::kLit;
  EXPECT_FALSE(parse(chunkGlb(mesh)->bytes).gltf["materials"][0].contains("extensions"));
}

TEST(ChunkGlb, RefusesMeshesItCannotWrite) {
  ChunkMesh m = grid();
  m.indices.push_back(99);
  m.indices.push_back(0);
  m.indices.push_back(1);
  EXPECT_EQ(chunkGlb(m).error().message, "3D Tiles: chunk 7: an index past the positions");
  m = grid();
  m.texcoords.clear();
  EXPECT_FALSE(chunkGlb(m).ok());
  m = grid();
  m.imageMimeType = "image/ktx2";
  EXPECT_FALSE(chunkGlb(m).ok());
  m = grid();
  m.normals.pop_back();
  EXPECT_FALSE(chunkGlb(m).ok());
  m = grid();
  m.colors.assign(m.positions.size() - 1, {1, 2, 3});
  EXPECT_FALSE(chunkGlb(m).ok());
}

}  // namespace
}  // namespace terralod::tiles3d
