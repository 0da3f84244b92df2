#pragma once
// What the 3D Tiles 1.1 specification requires of a tileset, checked field by field (no npm
// package here carries the specification's JSON schema): tileset.json's required properties
// and their types, every tile's bounding volume, error and refinement, content URIs that name
// files, implicit tiling's object and its subtree files (header, chunks, availabilities), and
// errors that do not grow from a tile to its children. Each problem is one line naming where.

#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace terralod::test {

inline bool isNumberArray(const nlohmann::json& v, size_t n) {
  if (!v.is_array() || v.size() != n) return false;
  for (const auto& e : v)
    if (!e.is_number()) return false;
  return true;
}

inline std::vector<uint8_t> fileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A subtree file's JSON and binary chunk; problems appended to `out`.
struct SubtreeChunks {
  nlohmann::json json;
  std::vector<uint8_t> binary;
  bool ok = false;
};
inline SubtreeChunks readSubtree(const std::filesystem::path& path, std::vector<std::string>& out) {
  SubtreeChunks s;
  const std::vector<uint8_t> b = fileBytes(path);
  if (b.size() < 24 || std::memcmp(b.data(), "subt", 4) != 0) {
    out.push_back(path.string() + ": not a subtree file");
    return s;
  }
  uint32_t version = 0;
  uint64_t jsonLength = 0, binaryLength = 0;
  std::memcpy(&version, b.data() + 4, 4);
  std::memcpy(&jsonLength, b.data() + 8, 8);
  std::memcpy(&binaryLength, b.data() + 16, 8);
  if (version != 1 || jsonLength % 8 || binaryLength % 8 ||
      24 + jsonLength + binaryLength != b.size()) {
    out.push_back(path.string() + ": bad subtree header or chunk lengths");
    return s;
  }
  s.json = nlohmann::json::parse(b.begin() + 24, b.begin() + 24 + long(jsonLength), nullptr, false);
  if (s.json.is_discarded()) {
    out.push_back(path.string() + ": subtree JSON does not parse");
    return s;
  }
  s.binary.assign(b.begin() + 24 + long(jsonLength), b.end());
  s.ok = true;
  return s;
}

// Bit `i` of an availability ({"constant"} or {"bitstream"}), or -1 when it is malformed.
inline int availableBit(const SubtreeChunks& s, const nlohmann::json& a, uint64_t i,
                        uint64_t bits) {
  if (a.contains("constant")) return a["constant"] == 1 ? 1 : a["constant"] == 0 ? 0 : -1;
  if (!a.contains("bitstream") || !s.json.contains("bufferViews")) return -1;
  const size_t v = a["bitstream"].get<size_t>();
  if (v >= s.json["bufferViews"].size()) return -1;
  const auto& view = s.json["bufferViews"][v];
  const uint64_t offset = view["byteOffset"], length = view["byteLength"];
  if (offset % 8 || length < (bits + 7) / 8 || offset + length > s.binary.size()) return -1;
  return (s.binary[offset + i / 8] >> (i % 8)) & 1;
}

inline std::string expand(std::string uri, uint32_t level, uint64_t x, uint64_t y) {
  for (auto [key, value] : {std::pair{std::string("{level}"), uint64_t(level)},
                            std::pair{std::string("{x}"), x}, std::pair{std::string("{y}"), y}})
    for (size_t at; (at = uri.find(key)) != std::string::npos;)
      uri.replace(at, key.size(), std::to_string(value));
  return uri;
}

// Implicit quadtree tiling under `root`: the object, then every subtree from the root's down,
// and that every tile with content has its file. Counts content tiles in `contentTiles`.
inline void checkImplicit(const nlohmann::json& root, const std::filesystem::path& dir,
                          std::vector<std::string>& out, uint64_t& contentTiles) {
  const auto& it = root["implicitTiling"];
  if (it.value("subdivisionScheme", "") != "QUADTREE" ||
      !it.value("subtreeLevels", nlohmann::json()).is_number_unsigned() ||
      !it.value("availableLevels", nlohmann::json()).is_number_unsigned() ||
      !it.contains("subtrees") || !it["subtrees"].value("uri", nlohmann::json()).is_string()) {
    out.push_back(
        "root.implicitTiling: needs subdivisionScheme, subtreeLevels, "
        "availableLevels and subtrees.uri");
    return;
  }
  if (root.contains("children")) out.push_back("root: an implicit root has no children");
  if (!root.contains("content") || !root["content"].value("uri", nlohmann::json()).is_string()) {
    out.push_back("root: implicit content needs a URI template");
    return;
  }
  const uint32_t levels = it["availableLevels"], per = it["subtreeLevels"];
  const std::string subtreeUri = it["subtrees"]["uri"], contentUri = root["content"]["uri"];
  struct Pending {
    uint32_t level;
    uint64_t x, y;
  };
  std::vector<Pending> todo = {{0, 0, 0}};
  while (!todo.empty()) {
    const Pending at = todo.back();
    todo.pop_back();
    const auto file = dir / expand(subtreeUri, at.level, at.x, at.y);
    if (!std::filesystem::exists(file)) {
      out.push_back(file.string() + ": a subtree the tree names is missing");
      continue;
    }
    const SubtreeChunks s = readSubtree(file, out);
    if (!s.ok) continue;
    if (!s.json.contains("tileAvailability") || !s.json.contains("childSubtreeAvailability")) {
      out.push_back(file.string() + ": needs tileAvailability and childSubtreeAvailability");
      continue;
    }
    const uint64_t tileBits = ((uint64_t(1) << (2 * per)) - 1) / 3;
    uint64_t bit = 0;
    for (uint32_t r = 0; r < per; ++r)
      for (uint64_t m = 0; m < (uint64_t(1) << (2 * r)); ++m, ++bit) {
        uint64_t lx = 0, ly = 0;
        for (uint32_t b = 0; b < r; ++b) {
          lx |= ((m >> (2 * b)) & 1u) << b;
          ly |= ((m >> (2 * b + 1)) & 1u) << b;
        }
        const int tile = availableBit(s, s.json["tileAvailability"], bit, tileBits);
        const int content = s.json.contains("contentAvailability")
                                ? availableBit(s, s.json["contentAvailability"][0], bit, tileBits)
                                : 0;
        if (tile < 0 || content < 0) {
          out.push_back(file.string() + ": malformed availability");
          break;
        }
        if (content && !tile) out.push_back(file.string() + ": content on an unavailable tile");
        if (tile && at.level + r >= levels) out.push_back(file.string() + ": tile below the tree");
        if (!content) continue;
        ++contentTiles;
        const auto glb = dir / expand(contentUri, at.level + r, (at.x << r) | lx, (at.y << r) | ly);
        if (!std::filesystem::exists(glb)) out.push_back(glb.string() + ": content missing");
      }
    for (uint64_t m = 0; m < (uint64_t(1) << (2 * per)); ++m) {
      const int child =
          availableBit(s, s.json["childSubtreeAvailability"], m, uint64_t(1) << (2 * per));
      if (child < 0) {
        out.push_back(file.string() + ": malformed childSubtreeAvailability");
        break;
      }
      if (!child) continue;
      uint64_t lx = 0, ly = 0;
      for (uint32_t b = 0; b < per; ++b) {
        lx |= ((m >> (2 * b)) & 1u) << b;
        ly |= ((m >> (2 * b + 1)) & 1u) << b;
      }
      todo.push_back({at.level + per, (at.x << per) | lx, (at.y << per) | ly});
    }
  }
}

/// The problems of the tileset in `dir` (empty: none). `contentTiles` counts tiles with content.
inline std::vector<std::string> tiles3dProblems(const std::filesystem::path& dir,
                                                uint64_t* contentTiles = nullptr) {
  std::vector<std::string> out;
  std::ifstream in(dir / "tileset.json");
  const auto t = nlohmann::json::parse(in, nullptr, false);
  if (t.is_discarded() || !t.is_object()) return {"tileset.json: not a JSON object"};
  if (!t.contains("asset") || !t["asset"].value("version", nlohmann::json()).is_string())
    out.push_back("asset.version: required, a string");
  if (!t.value("geometricError", nlohmann::json()).is_number() || t["geometricError"] < 0)
    out.push_back("geometricError: required, a number >= 0");
  if (!t.contains("root") || !t["root"].is_object()) {
    out.push_back("root: required, a tile");
    return out;
  }
  uint64_t count = 0;
  std::function<void(const nlohmann::json&, const std::string&, double, bool)> tile =
      [&](const nlohmann::json& j, const std::string& where, double parentError, bool isRoot) {
        const auto& bv = j.value("boundingVolume", nlohmann::json());
        const bool volume = (bv.contains("box") && isNumberArray(bv["box"], 12)) ||
                            (bv.contains("region") && isNumberArray(bv["region"], 6)) ||
                            (bv.contains("sphere") && isNumberArray(bv["sphere"], 4));
        if (!volume) out.push_back(where + ".boundingVolume: required: box, region or sphere");
        const auto& e = j.value("geometricError", nlohmann::json());
        if (!e.is_number() || e.get<double>() < 0) {
          out.push_back(where + ".geometricError: required, a number >= 0");
        } else if (e.get<double>() > parentError) {
          out.push_back(where + ".geometricError: larger than its parent's");
        }
        if (j.contains("refine") && j["refine"] != "ADD" && j["refine"] != "REPLACE")
          out.push_back(where + ".refine: ADD or REPLACE");
        if (isRoot && !j.contains("refine")) out.push_back(where + ".refine: required at the root");
        if (j.contains("transform") && !isNumberArray(j["transform"], 16))
          out.push_back(where + ".transform: 16 numbers");
        if (j.contains("implicitTiling")) {
          checkImplicit(j, dir, out, count);
          return;
        }
        if (j.contains("content")) {
          if (!j["content"].value("uri", nlohmann::json()).is_string()) {
            out.push_back(where + ".content.uri: required, a string");
          } else {
            ++count;
            if (!std::filesystem::exists(dir / j["content"]["uri"].get<std::string>()))
              out.push_back(where + ".content.uri: no such file");
          }
        }
        if (j.contains("children")) {
          if (!j["children"].is_array() || j["children"].empty())
            out.push_back(where + ".children: a non-empty array");
          else
            for (size_t i = 0; i < j["children"].size(); ++i)
              tile(j["children"][i], where + ".children[" + std::to_string(i) + "]",
                   e.is_number() ? e.get<double>() : 1e300, false);
        }
      };
  tile(t["root"], "root",
       t["geometricError"].is_number() ? t["geometricError"].get<double>() : 1e300, true);
  if (contentTiles) *contentTiles = count;
  return out;
}

}  // namespace terralod::test
