#include "terralod/measure/mesh_writers.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <limits>
#include <nlohmann/json.hpp>
#include <span>

namespace terralod {
namespace {

// PLY and GLB data are the in-memory floats and integers copied as they are.
static_assert(std::endian::native == std::endian::little, "mesh writers assume little-endian");
static_assert(sizeof(std::array<float, 3>) == 12);

constexpr size_t kFlushBytes = 1 << 20;
constexpr uint32_t kGlbMagic = 0x46546C67;      // "glTF"
constexpr uint32_t kGlbJsonChunk = 0x4E4F534A;  // "JSON"
constexpr uint32_t kGlbBinChunk = 0x004E4942;   // "BIN\0"
constexpr int kGlFloat = 5126, kGlUnsignedInt = 5125;
constexpr int kGlArrayBuffer = 34962, kGlElementArrayBuffer = 34963;
constexpr int kGlTriangles = 4;
constexpr int kGlLinear = 9729, kGlLinearMipmapLinear = 9987, kGlClampToEdge = 33071;

template <typename T>
std::span<const uint8_t> bytesOf(const std::vector<T>& values) {
  return {reinterpret_cast<const uint8_t*>(values.data()), values.size() * sizeof(T)};
}

template <typename T>
void append(std::string& out, T value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

// Shortest text that reads back as the same float.
void appendNumber(std::string& out, float value) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof(text), value).ptr;
  out.append(text, end);
}

void appendNumber(std::string& out, uint64_t value) {
  char text[24];
  const auto end = std::to_chars(text, text + sizeof(text), value).ptr;
  out.append(text, end);
}

// Text gathered in memory and handed to the file a megabyte at a time.
class TextOut {
 public:
  explicit TextOut(AtomicFile& file) : mFile(file) {}
  std::string& text() { return mText; }
  Status maybeFlush() { return mText.size() >= kFlushBytes ? flush() : Status(); }
  Status flush() {
    Status st = mFile.write(mText);
    mText.clear();
    return st;
  }

 private:
  AtomicFile& mFile;
  std::string mText;
};

template <size_t N>
Status writeObjLines(TextOut& out, const char* keyword,
                     const std::vector<std::array<float, N>>& rows) {
  for (const auto& row : rows) {
    std::string& text = out.text();
    text += keyword;
    for (float c : row) {
      text += ' ';
      appendNumber(text, c);
    }
    text += '\n';
    if (Status st = out.maybeFlush(); !st) return st;
  }
  return {};
}

Status writeObj(const LevelSurface& s, const MeshExtras& extras, AtomicFile& file) {
  const bool textured = !extras.materialLibrary.empty();
  TextOut out(file);
  out.text() = "# terralod export: " + extras.description + "\n# " +
               std::to_string(s.positions.size()) + " vertices, " +
               std::to_string(s.indices.size() / 3) +
               " triangles; metres, x east, y north, z up; unit normals; texture coordinates "
               "0..1 over the data's extent\n";
  if (textured) out.text() += "mtllib " + extras.materialLibrary + "\n";
  if (Status st = writeObjLines(out, "v", s.positions); !st) return st;
  if (Status st = writeObjLines(out, "vt", s.texcoords); !st) return st;
  if (Status st = writeObjLines(out, "vn", s.normals); !st) return st;
  if (textured) out.text() += "usemtl terrain\n";
  for (size_t k = 0; k < s.indices.size(); k += 3) {
    std::string& text = out.text();
    text += 'f';
    for (size_t j = 0; j < 3; ++j) {
      // Position, texture coordinate and normal share the vertex's index.
      std::string index;
      appendNumber(index, uint64_t(s.indices[k + j]) + 1);
      text += ' ';
      text += index;
      text += '/';
      text += index;
      text += '/';
      text += index;
    }
    text += '\n';
    if (Status st = out.maybeFlush(); !st) return st;
  }
  return out.flush();
}

Status writePly(const LevelSurface& s, const MeshExtras& extras, AtomicFile& file) {
  std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment terralod export: " + extras.description +
      "\ncomment metres, x east, y north, z up; unit normals; texture "
      "coordinates 0..1 over the data's extent\n";
  if (!extras.textureFile.empty()) header += "comment TextureFile " + extras.textureFile + "\n";
  header += "element vertex " + std::to_string(s.positions.size()) +
            "\nproperty float x\nproperty float y\nproperty float z\nproperty float "
            "nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float "
            "v\nelement face " +
            std::to_string(s.indices.size() / 3) +
            "\nproperty list uchar uint vertex_indices\nend_header\n";
  if (Status st = file.write(header); !st) return st;
  std::string bytes;
  for (size_t i = 0; i < s.positions.size(); ++i) {
    for (float c : s.positions[i]) append<float>(bytes, c);
    for (float c : s.normals[i]) append<float>(bytes, c);
    for (float c : s.texcoords[i]) append<float>(bytes, c);
    if (bytes.size() >= kFlushBytes) {
      if (Status st = file.write(bytes); !st) return st;
      bytes.clear();
    }
  }
  for (size_t k = 0; k < s.indices.size(); k += 3) {
    append<uint8_t>(bytes, 3);
    for (size_t j = 0; j < 3; ++j) append<uint32_t>(bytes, s.indices[k + j]);
    if (bytes.size() >= kFlushBytes) {
      if (Status st = file.write(bytes); !st) return st;
      bytes.clear();
    }
  }
  return file.write(bytes);
}

Status writeGlb(const LevelSurface& s, const MeshExtras& extras, AtomicFile& file) {
  // glTF is y up with -z pointing north: terralod's (x, y, z) becomes (x, z, -y), for
  // positions and normals alike; its texture coordinates count v from the image's first
  // (northern) row, so v becomes 1 - v.
  std::vector<std::array<float, 3>> positions(s.positions.size()), normals(s.normals.size());
  std::vector<std::array<float, 2>> texcoords(s.texcoords.size());
  std::array<float, 3> lo, hi;
  lo.fill(std::numeric_limits<float>::infinity());
  hi.fill(-std::numeric_limits<float>::infinity());
  for (size_t i = 0; i < positions.size(); ++i) {
    const auto& p = s.positions[i];
    positions[i] = {p[0], p[2], 0.0f - p[1]};  // 0 - y, not -y: no -0 at the southern edge
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], positions[i][c]);
      hi[c] = std::max(hi[c], positions[i][c]);
    }
    const auto& n = s.normals[i];
    normals[i] = {n[0], n[2], 0.0f - n[1]};
    texcoords[i] = {s.texcoords[i][0], 1.0f - s.texcoords[i][1]};
  }
  const bool textured = !extras.png.empty();
  // The binary chunk: positions, normals, texture coordinates, indices, then the PNG; every
  // piece a multiple of 4 bytes long but the PNG, which the chunk pads with zeros.
  const uint64_t vec3Bytes = positions.size() * sizeof(positions[0]);
  const uint64_t vec2Bytes = texcoords.size() * sizeof(texcoords[0]);
  const uint64_t indexBytes = s.indices.size() * sizeof(uint32_t);
  const uint64_t pngBytes = extras.png.size();
  const uint64_t normalOffset = vec3Bytes, texcoordOffset = 2 * vec3Bytes,
                 indexOffset = texcoordOffset + vec2Bytes, pngOffset = indexOffset + indexBytes;
  const uint64_t bufferBytes = pngOffset + pngBytes;
  nlohmann::json material = {
      {"name", "terrain"},
      {"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}}};
  nlohmann::json gltf = {
      {"asset", {{"version", "2.0"}, {"generator", "terralod"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}, {"name", extras.description}}}},
      {"meshes",
       {{{"name", extras.description},
         {"primitives",
          {{{"attributes", {{"POSITION", 0}, {"NORMAL", 2}, {"TEXCOORD_0", 3}}},
            {"indices", 1},
            {"material", 0},
            {"mode", kGlTriangles}}}}}}},
      {"accessors",
       {{{"bufferView", 0},
         {"componentType", kGlFloat},
         {"count", positions.size()},
         {"type", "VEC3"},
         {"min", lo},
         {"max", hi}},
        {{"bufferView", 1},
         {"componentType", kGlUnsignedInt},
         {"count", s.indices.size()},
         {"type", "SCALAR"}},
        {{"bufferView", 2},
         {"componentType", kGlFloat},
         {"count", normals.size()},
         {"type", "VEC3"}},
        {{"bufferView", 3},
         {"componentType", kGlFloat},
         {"count", texcoords.size()},
         {"type", "VEC2"}}}},
      {"bufferViews",
       {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", vec3Bytes}, {"target", kGlArrayBuffer}},
        {{"buffer", 0},
         {"byteOffset", indexOffset},
         {"byteLength", indexBytes},
         {"target", kGlElementArrayBuffer}},
        {{"buffer", 0},
         {"byteOffset", normalOffset},
         {"byteLength", vec3Bytes},
         {"target", kGlArrayBuffer}},
        {{"buffer", 0},
         {"byteOffset", texcoordOffset},
         {"byteLength", vec2Bytes},
         {"target", kGlArrayBuffer}}}},
      {"buffers", {{{"byteLength", bufferBytes}}}},
  };
  if (textured) {
    gltf["bufferViews"].push_back(
        {{"buffer", 0}, {"byteOffset", pngOffset}, {"byteLength", pngBytes}});
    gltf["images"] = {{{"bufferView", 4}, {"mimeType", "image/png"}}};
    gltf["samplers"] = {{{"magFilter", kGlLinear},
                         {"minFilter", kGlLinearMipmapLinear},
                         {"wrapS", kGlClampToEdge},
                         {"wrapT", kGlClampToEdge}}};
    gltf["textures"] = {{{"sampler", 0}, {"source", 0}}};
    material["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}, {"texCoord", 0}};
  }
  gltf["materials"] = nlohmann::json::array({material});
  // GLB chunks start 4-byte aligned; the JSON chunk pads with spaces, the binary one with
  // zeros.
  std::string json = gltf.dump();
  json.resize((json.size() + 3) & ~size_t(3), ' ');
  const uint64_t binBytes = (bufferBytes + 3) & ~uint64_t(3);
  const uint64_t total = 12 + 8 + json.size() + 8 + binBytes;
  if (total > std::numeric_limits<uint32_t>::max())
    return makeError(file.path(), "mesh of " + std::to_string(total) +
                                      " bytes exceeds GLB's 4 GiB limit; export a coarser "
                                      "level or use .ply");
  std::string head;
  append<uint32_t>(head, kGlbMagic);
  append<uint32_t>(head, 2);
  append<uint32_t>(head, uint32_t(total));
  append<uint32_t>(head, uint32_t(json.size()));
  append<uint32_t>(head, kGlbJsonChunk);
  head += json;
  append<uint32_t>(head, uint32_t(binBytes));
  append<uint32_t>(head, kGlbBinChunk);
  for (const std::span<const uint8_t> piece :
       {std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(head.data()), head.size()),
        bytesOf(positions), bytesOf(normals), bytesOf(texcoords), bytesOf(s.indices),
        std::span<const uint8_t>(extras.png)})
    if (Status st = file.write(piece); !st) return st;
  const uint8_t zeros[3] = {0, 0, 0};
  return file.write(std::span<const uint8_t>(zeros, binBytes - bufferBytes));
}

}  // namespace

std::optional<MeshFormat> meshFormatForPath(const std::string& path) {
  const size_t dot = path.find_last_of("./");
  if (dot == std::string::npos || path[dot] != '.') return std::nullopt;
  std::string extension = path.substr(dot + 1);
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (extension == "obj") return MeshFormat::kObj;
  if (extension == "ply") return MeshFormat::kPly;
  if (extension == "glb") return MeshFormat::kGlb;
  return std::nullopt;
}

Status writeMesh(const LevelSurface& surface, MeshFormat format, const MeshExtras& extras,
                 AtomicFile& file) {
  switch (format) {
    case MeshFormat::kObj:
      return writeObj(surface, extras, file);
    case MeshFormat::kPly:
      return writePly(surface, extras, file);
    case MeshFormat::kGlb:
      return writeGlb(surface, extras, file);
  }
  return makeError(file.path(), "unknown mesh format");
}

std::string objMaterialLibrary(const std::string& description, const std::string& textureFile) {
  // White, matte, unlit by any ambient or specular term: the texture is the colour.
  return "# terralod export: " + description +
         "\nnewmtl terrain\nKa 0 0 0\nKd 1 1 1\nKs 0 0 0\nNs 1\nd 1\nillum 1\nmap_Kd " +
         textureFile + "\n";
}

}  // namespace terralod
