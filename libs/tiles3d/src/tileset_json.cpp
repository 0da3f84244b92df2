#include "terralod/tiles3d/tileset_json.h"

#include <algorithm>
#include <vector>

namespace terralod::tiles3d {

std::array<double, 12> boxOf(const std::array<double, 3>& min, const std::array<double, 3>& max) {
  std::array<double, 12> box{};
  for (size_t k = 0; k < 3; ++k) {
    box[k] = 0.5 * (min[k] + max[k]);
    box[3 + 4 * k] = 0.5 * (max[k] - min[k]);  // half-axis k: along axis k only
  }
  return box;
}

Result<nlohmann::json> tilesetJson(std::span<const ExportTile> tiles, const glm::dmat4& rootFrame,
                                   double tilesetError, const nlohmann::json& extras) {
  using nlohmann::json;
  if (tiles.empty()) return Error{"3D Tiles: no tiles to write"};
  std::vector<std::vector<uint32_t>> children(tiles.size());
  std::vector<uint32_t> roots;
  for (uint32_t i = 0; i < tiles.size(); ++i) {
    const ExportTile& t = tiles[i];
    for (size_t k = 0; k < 3; ++k)
      if (!(t.min[k] <= t.max[k]))
        return Error{"3D Tiles: tile " + std::to_string(i) + " has an empty box"};
    if (t.parent == kNoParent) {
      roots.push_back(i);
      continue;
    }
    if (t.parent >= i)
      return Error{"3D Tiles: tile " + std::to_string(i) + " is listed before its parent"};
    if (t.geometricError > tiles[t.parent].geometricError)
      return Error{"3D Tiles: tile " + std::to_string(i) + "'s error exceeds its parent's"};
    children[t.parent].push_back(i);
  }
  // Built from the leaves up: every tile's JSON is done before its parent's.
  std::vector<json> built(tiles.size());
  for (uint32_t i = uint32_t(tiles.size()); i-- > 0;) {
    const ExportTile& t = tiles[i];
    json tile = {{"boundingVolume", {{"box", boxOf(t.min, t.max)}}},
                 {"geometricError", t.geometricError},
                 {"refine", "REPLACE"}};
    if (!t.contentUri.empty()) tile["content"] = {{"uri", t.contentUri}};
    if (!children[i].empty()) {
      json list = json::array();
      for (uint32_t c : children[i]) list.push_back(std::move(built[c]));
      tile["children"] = std::move(list);
    }
    built[i] = std::move(tile);
  }
  json root;
  if (roots.size() == 1) {
    root = std::move(built[roots[0]]);
  } else {
    std::array<double, 3> lo = tiles[roots[0]].min, hi = tiles[roots[0]].max;
    json list = json::array();
    double error = 0;
    for (uint32_t r : roots) {
      for (size_t k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], tiles[r].min[k]);
        hi[k] = std::max(hi[k], tiles[r].max[k]);
      }
      error = std::max(error, tiles[r].geometricError);
      list.push_back(std::move(built[r]));
    }
    root = {{"boundingVolume", {{"box", boxOf(lo, hi)}}},
            {"geometricError", std::max(error, tilesetError)},
            {"refine", "REPLACE"},
            {"children", std::move(list)}};
  }
  json transform = json::array();
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) transform.push_back(rootFrame[c][r]);
  root["transform"] = std::move(transform);
  json out = {{"asset", {{"version", "1.1"}, {"generator", "terralod"}}},
              {"geometricError", std::max(tilesetError, root["geometricError"].get<double>())},
              {"root", std::move(root)}};
  if (!extras.is_null()) out["extras"] = extras;
  return out;
}

}  // namespace terralod::tiles3d
