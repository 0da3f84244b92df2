#include "terralod/tiles3d/implicit_tiling.h"

#include <algorithm>
#include <cstring>
#include <unordered_set>

namespace terralod::tiles3d {
namespace {

using nlohmann::json;

uint64_t keyOf(const TileKey& k) {
  return (uint64_t(k.level) << 58) | mortonIndex(k.x, k.y);
}

// One availability: a bitstream of `bits` bits, or a constant when all agree.
class Availability {
 public:
  explicit Availability(uint64_t bits) : mBits((bits + 7) / 8, 0), mCount(bits) {}
  void set(uint64_t i) {
    mBits[i / 8] |= uint8_t(1u << (i % 8));
    ++mSet;
  }
  // {"constant": 0|1} or {"bitstream": view, "availableCount": n}, the bits appended to `bin`.
  json describe(std::vector<uint8_t>& bin, json& views) const {
    if (mSet == 0 || mSet == mCount) return {{"constant", mSet == 0 ? 0 : 1}};
    while (bin.size() % 8) bin.push_back(0);  // bufferViews start 8-byte aligned
    views.push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", mBits.size()}});
    bin.insert(bin.end(), mBits.begin(), mBits.end());
    return {{"bitstream", views.size() - 1}, {"availableCount", mSet}};
  }

 private:
  std::vector<uint8_t> mBits;
  uint64_t mCount = 0, mSet = 0;
};

// The descendant `depth` levels below `root` whose Morton index among them is `m`.
TileKey descendant(const TileKey& root, uint32_t depth, uint64_t m) {
  uint32_t x = 0, y = 0;
  for (uint32_t b = 0; b < depth; ++b) {
    x |= uint32_t((m >> (2 * b)) & 1u) << b;
    y |= uint32_t((m >> (2 * b + 1)) & 1u) << b;
  }
  return {root.level + depth, (root.x << depth) | x, (root.y << depth) | y};
}

void appendU32(std::vector<uint8_t>& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(uint8_t(v >> (8 * i)));
}
void appendU64(std::vector<uint8_t>& out, uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(uint8_t(v >> (8 * i)));
}

}  // namespace

uint64_t mortonIndex(uint32_t x, uint32_t y) {
  uint64_t m = 0;
  for (int b = 0; b < 32; ++b) {
    m |= uint64_t((x >> b) & 1u) << (2 * b);
    m |= uint64_t((y >> b) & 1u) << (2 * b + 1);
  }
  return m;
}

Result<std::vector<SubtreeFile>> subtreeFiles(std::span<const TileKey> content,
                                              uint32_t availableLevels, uint32_t subtreeLevels) {
  if (availableLevels == 0 || availableLevels > 29 || subtreeLevels == 0 || subtreeLevels > 12)
    return Error{"implicit tiling: levels out of range"};
  std::unordered_set<uint64_t> withContent, available;
  for (const TileKey& k : content) {
    if (k.level >= availableLevels || k.x >> k.level != 0 || k.y >> k.level != 0)
      return Error{"implicit tiling: tile " + std::to_string(k.level) + "/" + std::to_string(k.x) +
                   "/" + std::to_string(k.y) + " lies outside the tree"};
    if (!withContent.insert(keyOf(k)).second)
      return Error{"implicit tiling: tile " + std::to_string(k.level) + "/" + std::to_string(k.x) +
                   "/" + std::to_string(k.y) + " is listed twice"};
    for (TileKey a = k;; a = {a.level - 1, a.x / 2, a.y / 2}) {
      if (!available.insert(keyOf(a)).second || a.level == 0) break;
    }
  }
  std::vector<SubtreeFile> files;
  // Subtree roots: available tiles at levels 0, S, 2S, ... (in a stable order).
  std::vector<TileKey> roots;
  for (const TileKey& k : content)
    for (TileKey a = k;; a = {a.level - 1, a.x / 2, a.y / 2}) {
      if (a.level % subtreeLevels == 0) roots.push_back(a);
      if (a.level == 0) break;
    }
  std::sort(roots.begin(), roots.end(), [](const TileKey& a, const TileKey& b) {
    return a.level != b.level ? a.level < b.level : mortonIndex(a.x, a.y) < mortonIndex(b.x, b.y);
  });
  roots.erase(std::unique(roots.begin(), roots.end()), roots.end());
  const uint64_t tileBits = ((uint64_t(1) << (2 * subtreeLevels)) - 1) / 3;
  const uint64_t childBits = uint64_t(1) << (2 * subtreeLevels);
  for (const TileKey& root : roots) {
    Availability tiles(tileBits), contents(tileBits), children(childBits);
    uint64_t bit = 0;
    for (uint32_t r = 0; r < subtreeLevels; ++r) {
      const uint32_t level = root.level + r;
      const uint64_t count = uint64_t(1) << (2 * r);
      for (uint64_t m = 0; m < count; ++m, ++bit) {
        if (level >= availableLevels) continue;
        const TileKey k = descendant(root, r, m);
        if (available.count(keyOf(k))) tiles.set(bit);
        if (withContent.count(keyOf(k))) contents.set(bit);
      }
    }
    const uint32_t below = root.level + subtreeLevels;
    if (below < availableLevels)
      for (uint64_t m = 0; m < childBits; ++m) {
        const TileKey k = descendant(root, subtreeLevels, m);
        if (available.count(keyOf(k))) children.set(m);
      }
    std::vector<uint8_t> bin;
    json views = json::array();
    json subtree = {{"tileAvailability", tiles.describe(bin, views)},
                    {"contentAvailability", {contents.describe(bin, views)}},
                    {"childSubtreeAvailability", children.describe(bin, views)}};
    while (bin.size() % 8) bin.push_back(0);
    if (!bin.empty()) {
      subtree["buffers"] = {{{"byteLength", bin.size()}}};
      subtree["bufferViews"] = views;
    }
    std::string text = subtree.dump();
    while (text.size() % 8) text.push_back(' ');
    SubtreeFile file;
    file.root = root;
    file.uri = "subtrees/" + std::to_string(root.level) + "/" + std::to_string(root.x) + "/" +
               std::to_string(root.y) + ".subtree";
    auto& out = file.bytes;
    out.insert(out.end(), {'s', 'u', 'b', 't'});
    appendU32(out, 1);
    appendU64(out, text.size());
    appendU64(out, bin.size());
    out.insert(out.end(), text.begin(), text.end());
    out.insert(out.end(), bin.begin(), bin.end());
    files.push_back(std::move(file));
  }
  return files;
}

nlohmann::json implicitRootTile(const std::array<double, 12>& box, double rootError,
                                const glm::dmat4& rootFrame, uint32_t availableLevels,
                                uint32_t subtreeLevels) {
  json transform = json::array();
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) transform.push_back(rootFrame[c][r]);
  return {{"boundingVolume", {{"box", box}}},
          {"geometricError", rootError},
          {"refine", "REPLACE"},
          {"transform", std::move(transform)},
          {"content", {{"uri", "tiles/{level}/{x}/{y}.glb"}}},
          {"implicitTiling",
           {{"subdivisionScheme", "QUADTREE"},
            {"availableLevels", availableLevels},
            {"subtreeLevels", subtreeLevels},
            {"subtrees", {{"uri", "subtrees/{level}/{x}/{y}.subtree"}}}}}};
}

std::array<double, 12> implicitTileBox(const std::array<double, 12>& rootBox, const TileKey& key) {
  std::array<double, 12> box = rootBox;
  const double n = double(uint64_t(1) << key.level);
  // The tile's centre in the root box's x and y half-axis units: -1 + (2i + 1) / n.
  const double fx = -1.0 + (2.0 * key.x + 1.0) / n, fy = -1.0 + (2.0 * key.y + 1.0) / n;
  for (int k = 0; k < 3; ++k) {
    box[k] = rootBox[k] + fx * rootBox[3 + k] + fy * rootBox[6 + k];
    box[3 + k] = rootBox[3 + k] / n;
    box[6 + k] = rootBox[6 + k] / n;
  }
  return box;
}

}  // namespace terralod::tiles3d
