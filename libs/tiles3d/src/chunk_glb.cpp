#include "terralod/tiles3d/chunk_glb.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>

#include <glm/mat4x4.hpp>
#include <nlohmann/json.hpp>

namespace terralod::tiles3d {
namespace {

using nlohmann::json;

constexpr int kByte = 5120, kUnsignedByte = 5121, kUnsignedShort = 5123, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

// One bufferView's data, uncompressed, and how meshopt encodes it.
struct Stream {
  std::vector<uint8_t> data;
  size_t stride = 0, count = 0;
  bool indices = false;
};

void append(std::vector<uint8_t>& out, const void* data, size_t size) {
  const auto* p = static_cast<const uint8_t*>(data);
  out.insert(out.end(), p, p + size);
}
void padTo4(std::vector<uint8_t>& out, uint8_t fill) {
  while (out.size() % 4) out.push_back(fill);
}

std::vector<uint8_t> encodeVertices(const Stream& s) {
  meshopt_encodeVertexVersion(0);  // the only version EXT_meshopt_compression knows
  std::vector<uint8_t> out(meshopt_encodeVertexBufferBound(s.count, s.stride));
  out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), s.data.data(), s.count, s.stride));
  return out;
}

// The index codec does not depend on the width the decoder writes (the view's stride).
std::vector<uint8_t> encodeIndices(const std::vector<uint32_t>& indices, size_t vertices) {
  meshopt_encodeIndexVersion(1);  // what EXT_meshopt_compression's TRIANGLES mode decodes
  std::vector<uint8_t> out(meshopt_encodeIndexBufferBound(indices.size(), vertices));
  out.resize(meshopt_encodeIndexBuffer(out.data(), out.size(), indices.data(), indices.size()));
  return out;
}

}  // namespace

Result<ChunkGlb> chunkGlb(const ChunkMesh& m) {
  const size_t n = m.positions.size();
  if (n == 0 || m.indices.empty() || m.indices.size() % 3 != 0)
    return Error{"3D Tiles: " + m.name + ": no triangles"};
  if (m.normals.size() != n) return Error{"3D Tiles: " + m.name + ": a normal per position"};
  if (!m.colors.empty() && m.colors.size() != n)
    return Error{"3D Tiles: " + m.name + ": a colour per position, or none"};
  if (!m.image.empty() && m.texcoords.size() != n)
    return Error{"3D Tiles: " + m.name + ": texture coordinates per position with an image"};
  if (!m.image.empty() && m.imageMimeType != "image/png" && m.imageMimeType != "image/jpeg")
    return Error{"3D Tiles: " + m.name + ": the image is neither PNG nor JPEG"};
  for (uint32_t i : m.indices)
    if (i >= n) return Error{"3D Tiles: " + m.name + ": an index past the positions"};

  ChunkGlb out;
  out.min = out.max = m.positions[0];
  for (const auto& p : m.positions)
    for (size_t k = 0; k < 3; ++k) {
      out.min[k] = std::min(out.min[k], p[k]);
      out.max[k] = std::max(out.max[k], p[k]);
    }
  std::array<double, 3> scale{};
  for (size_t k = 0; k < 3; ++k)
    scale[k] = out.max[k] > out.min[k] ? (out.max[k] - out.min[k]) / 65535.0 : 1.0;

  // Positions: unsigned 16-bit, padded to 8 bytes (meshopt's strides are multiples of 4).
  Stream positions{{}, 8, n, false};
  for (const auto& p : m.positions) {
    uint16_t q[4] = {0, 0, 0, 0};
    double error2 = 0;
    for (size_t k = 0; k < 3; ++k) {
      q[k] = uint16_t(std::clamp(std::lround((p[k] - out.min[k]) / scale[k]), 0l, 65535l));
      const double d = out.min[k] + q[k] * scale[k] - p[k];
      error2 += d * d;
    }
    out.quantisationError = std::max(out.quantisationError, std::sqrt(error2));
    append(positions.data, q, sizeof q);
  }
  // Normals: signed 8-bit, scaled by the quantisation's scale first, since the node's matrix
  // takes normals through its inverse transpose (which divides by it).
  Stream normals{{}, 4, n, false};
  for (const auto& v : m.normals) {
    double s[3] = {v[0] * scale[0], v[1] * scale[1], v[2] * scale[2]};
    const double length = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    int8_t q[4] = {0, 0, 127, 0};
    if (length > 0)
      for (size_t k = 0; k < 3; ++k) q[k] = int8_t(std::lround(s[k] / length * 127.0));
    append(normals.data, q, sizeof q);
  }
  Stream texcoords{{}, 4, n, false};
  for (const auto& t : m.texcoords) {
    const uint16_t q[2] = {uint16_t(std::lround(std::clamp(t[0], 0.0f, 1.0f) * 65535.0)),
                           uint16_t(std::lround(std::clamp(t[1], 0.0f, 1.0f) * 65535.0))};
    append(texcoords.data, q, sizeof q);
  }
  // Colours: normalised unsigned 8-bit RGBA (4 bytes: vertex strides are multiples of 4).
  Stream colors{{}, 4, n, false};
  for (const auto& c : m.colors) {
    const uint8_t q[4] = {c[0], c[1], c[2], 255};
    append(colors.data, q, sizeof q);
  }
  const bool shortIndices = n <= 65536;
  Stream indices{{}, shortIndices ? 2u : 4u, m.indices.size(), true};
  for (uint32_t i : m.indices) {
    if (shortIndices) {
      const uint16_t s = uint16_t(i);
      append(indices.data, &s, 2);
    } else {
      append(indices.data, &i, 4);
    }
  }

  // Buffer 0 (the GLB's binary chunk): the compressed streams, then the image. Buffer 1: the
  // fallback the extension asks for, never stored (its views are all compressed).
  std::vector<const Stream*> streams;
  const auto viewOf = [&](const Stream& s) {
    streams.push_back(&s);
    return int(streams.size()) - 1;
  };
  const int positionView = viewOf(positions), normalView = viewOf(normals);
  const int texcoordView = m.image.empty() ? -1 : viewOf(texcoords);
  const int colorView = m.colors.empty() ? -1 : viewOf(colors);
  const int indexView = viewOf(indices);
  std::vector<uint8_t> bin;
  json views = json::array(), accessors = json::array();
  size_t fallbackBytes = 0;
  for (const Stream* s : streams) {
    const std::vector<uint8_t> compressed =
        s->indices ? encodeIndices(m.indices, n) : encodeVertices(*s);
    json meshopt = {{"buffer", 0},
                    {"byteOffset", bin.size()},
                    {"byteLength", compressed.size()},
                    {"byteStride", s->stride},
                    {"count", s->count},
                    {"mode", s->indices ? "TRIANGLES" : "ATTRIBUTES"}};
    json view = {{"buffer", 1},
                 {"byteOffset", fallbackBytes},
                 {"byteLength", s->data.size()},
                 {"target", s->indices ? kElementArrayBuffer : kArrayBuffer},
                 {"extensions", {{"EXT_meshopt_compression", meshopt}}}};
    if (!s->indices) view["byteStride"] = s->stride;
    views.push_back(view);
    append(bin, compressed.data(), compressed.size());
    padTo4(bin, 0);
    fallbackBytes += (s->data.size() + 3) / 4 * 4;
    out.uncompressedBytes += s->data.size();
  }
  json qmin = json::array({0, 0, 0}), qmax = json::array();
  for (size_t k = 0; k < 3; ++k) qmax.push_back(out.max[k] > out.min[k] ? 65535 : 0);
  accessors.push_back({{"bufferView", positionView},
                       {"componentType", kUnsignedShort},
                       {"count", n},
                       {"type", "VEC3"},
                       {"min", qmin},
                       {"max", qmax}});
  accessors.push_back({{"bufferView", normalView},
                       {"componentType", kByte},
                       {"normalized", true},
                       {"count", n},
                       {"type", "VEC3"}});
  json attributes = {{"POSITION", 0}, {"NORMAL", 1}};
  if (texcoordView >= 0) {
    accessors.push_back({{"bufferView", texcoordView},
                         {"componentType", kUnsignedShort},
                         {"normalized", true},
                         {"count", n},
                         {"type", "VEC2"}});
    attributes["TEXCOORD_0"] = int(accessors.size()) - 1;
  }
  if (colorView >= 0) {
    accessors.push_back({{"bufferView", colorView},
                         {"componentType", kUnsignedByte},
                         {"normalized", true},
                         {"count", n},
                         {"type", "VEC4"}});
    attributes["COLOR_0"] = int(accessors.size()) - 1;
  }
  accessors.push_back({{"bufferView", indexView},
                       {"componentType", shortIndices ? kUnsignedShort : kUnsignedInt},
                       {"count", m.indices.size()},
                       {"type", "SCALAR"}});
  json primitive = {{"attributes", attributes},
                    {"indices", int(accessors.size()) - 1},
                    {"mode", 4},
                    {"material", 0}};
  json material = {{"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}}};
  json gltf = {{"asset", {{"version", "2.0"}, {"generator", "terralod"}}},
               {"extensionsUsed", {"KHR_mesh_quantization", "EXT_meshopt_compression"}},
               {"extensionsRequired", {"KHR_mesh_quantization", "EXT_meshopt_compression"}},
               {"scene", 0},
               {"scenes", {{{"nodes", {0}}}}}};
  if (!m.image.empty()) {
    views.push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", m.image.size()}});
    append(bin, m.image.data(), m.image.size());
    padTo4(bin, 0);
    gltf["images"] = {{{"bufferView", int(views.size()) - 1}, {"mimeType", m.imageMimeType}}};
    gltf["samplers"] = {
        {{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 33071}, {"wrapT", 33071}}};
    gltf["textures"] = {{{"source", 0}, {"sampler", 0}}};
    material["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  }
  if (m.light == MaterialLight::kUnlit) {
    material["extensions"] = {{"KHR_materials_unlit", json::object()}};
    gltf["extensionsUsed"].push_back("KHR_materials_unlit");
  }
  gltf["materials"] = {material};
  gltf["meshes"] = {{{"primitives", {primitive}}}};
  // Root frame (z up) from quantised units: translate to the minimum, scale; then glTF's y up:
  // (x, y, z) → (x, z, −y).
  glm::dmat4 yUp(0.0);
  yUp[0][0] = 1;
  yUp[1][2] = -1;
  yUp[2][1] = 1;
  yUp[3][3] = 1;
  glm::dmat4 quantised(1.0);
  for (int k = 0; k < 3; ++k) {
    quantised[k][k] = scale[size_t(k)];
    quantised[3][k] = out.min[size_t(k)];
  }
  const glm::dmat4 matrix = yUp * quantised;
  json node = {{"mesh", 0}, {"matrix", json::array()}};
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) node["matrix"].push_back(matrix[c][r]);
  if (!m.name.empty()) node["name"] = m.name;
  gltf["nodes"] = {node};
  gltf["bufferViews"] = views;
  gltf["accessors"] = accessors;
  gltf["buffers"] = {{{"byteLength", bin.size()}},
                     {{"byteLength", fallbackBytes},
                      {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}};

  std::string text = gltf.dump();
  while (text.size() % 4) text.push_back(' ');
  const uint32_t total = uint32_t(12 + 8 + text.size() + 8 + bin.size());
  const uint32_t header[3] = {0x46546C67u, 2u, total};
  append(out.bytes, header, sizeof header);
  const uint32_t jsonChunk[2] = {uint32_t(text.size()), 0x4E4F534Au};
  append(out.bytes, jsonChunk, sizeof jsonChunk);
  append(out.bytes, text.data(), text.size());
  const uint32_t binChunk[2] = {uint32_t(bin.size()), 0x004E4942u};
  append(out.bytes, binChunk, sizeof binChunk);
  append(out.bytes, bin.data(), bin.size());
  return out;
}

}  // namespace terralod::tiles3d
