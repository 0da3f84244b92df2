#include "mesh_writers.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <limits>
#include <nlohmann/json.hpp>
#include <span>

namespace terralod::cli {
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

Status writeObj(const LevelSurface& s, const std::string& description, AtomicFile& file) {
  std::string text = "# terralod export: " + description + "\n# " +
                     std::to_string(s.positions.size()) + " vertices, " +
                     std::to_string(s.indices.size() / 3) +
                     " triangles; metres, x east, y north, z up\n";
  for (const auto& p : s.positions) {
    text += 'v';
    for (float c : p) {
      text += ' ';
      appendNumber(text, c);
    }
    text += '\n';
    if (text.size() >= kFlushBytes) {
      if (Status st = file.write(text); !st) return st;
      text.clear();
    }
  }
  for (size_t k = 0; k < s.indices.size(); k += 3) {
    text += 'f';
    for (size_t j = 0; j < 3; ++j) {
      text += ' ';
      appendNumber(text, uint64_t(s.indices[k + j]) + 1);
    }
    text += '\n';
    if (text.size() >= kFlushBytes) {
      if (Status st = file.write(text); !st) return st;
      text.clear();
    }
  }
  return file.write(text);
}

Status writePly(const LevelSurface& s, const std::string& description, AtomicFile& file) {
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment terralod export: " + description +
      "\ncomment metres, x east, y north, z up\nelement vertex " +
      std::to_string(s.positions.size()) +
      "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
      std::to_string(s.indices.size() / 3) +
      "\nproperty list uchar uint vertex_indices\nend_header\n";
  if (Status st = file.write(header); !st) return st;
  if (Status st = file.write(bytesOf(s.positions)); !st) return st;
  std::string faces;
  for (size_t k = 0; k < s.indices.size(); k += 3) {
    append<uint8_t>(faces, 3);
    for (size_t j = 0; j < 3; ++j) append<uint32_t>(faces, s.indices[k + j]);
    if (faces.size() >= kFlushBytes) {
      if (Status st = file.write(faces); !st) return st;
      faces.clear();
    }
  }
  return file.write(faces);
}

Status writeGlb(const LevelSurface& s, const std::string& description, AtomicFile& file) {
  // glTF is y up with -z pointing north: terralod's (x, y, z) becomes (x, z, -y).
  std::vector<std::array<float, 3>> positions(s.positions.size());
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
  }
  const uint64_t positionBytes = positions.size() * sizeof(positions[0]);
  const uint64_t indexBytes = s.indices.size() * sizeof(uint32_t);
  nlohmann::json gltf = {
      {"asset", {{"version", "2.0"}, {"generator", "terralod"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}, {"name", description}}}},
      {"meshes",
       {{{"name", description},
         {"primitives",
          {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"mode", kGlTriangles}}}}}}},
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
         {"type", "SCALAR"}}}},
      {"bufferViews",
       {{{"buffer", 0},
         {"byteOffset", 0},
         {"byteLength", positionBytes},
         {"target", kGlArrayBuffer}},
        {{"buffer", 0},
         {"byteOffset", positionBytes},
         {"byteLength", indexBytes},
         {"target", kGlElementArrayBuffer}}}},
      {"buffers", {{{"byteLength", positionBytes + indexBytes}}}},
  };
  // GLB chunks start 4-byte aligned; the JSON chunk pads with spaces, the binary one with
  // zeros (needed none here: positions and indices are multiples of 4 bytes already).
  std::string json = gltf.dump();
  json.resize((json.size() + 3) & ~size_t(3), ' ');
  const uint64_t binBytes = positionBytes + indexBytes;
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
  if (Status st = file.write(head); !st) return st;
  if (Status st = file.write(bytesOf(positions)); !st) return st;
  return file.write(bytesOf(s.indices));
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

Status writeMesh(const LevelSurface& surface, MeshFormat format, const std::string& description,
                 AtomicFile& file) {
  switch (format) {
    case MeshFormat::kObj:
      return writeObj(surface, description, file);
    case MeshFormat::kPly:
      return writePly(surface, description, file);
    case MeshFormat::kGlb:
      return writeGlb(surface, description, file);
  }
  return makeError(file.path(), "unknown mesh format");
}

}  // namespace terralod::cli
