#include "terralod/format/tileset_metadata.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "terralod/format/texture_codec.h"

namespace terralod {
namespace {

using json = nlohmann::json;

bool isTileSize(uint64_t v) {
  return v >= 2 && v <= kMaxTextureSize && ((v - 1) & (v - 2)) == 0;
}

}  // namespace

Result<TilesetMetadata> parseTilesetMetadata(std::string_view text, const TilesetHeader& header,
                                             const std::string& subject) {
  auto bad = [&](const std::string& what) {
    return makeError(subject, "invalid tileset metadata: " + what);
  };
  const json j = json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return bad("not a JSON object");
  TilesetMetadata m;

  if (const auto source = j.find("source"); source != j.end()) {
    if (!source->is_object()) return bad("\"source\" is not an object");
    if (const auto e = source->find("encoding"); e != source->end()) {
      if (!e->is_string()) return bad("\"source\".\"encoding\" is not a string");
      m.sourceEncoding = e->get<std::string>();
    }
    if (const auto band = source->find("band"); band != source->end()) {
      if (!band->is_number_integer() || band->get<int64_t>() < 1 || band->get<int64_t>() > 65535)
        return bad("\"source\".\"band\" is not a band number");
      m.sourceBand = int(band->get<int64_t>());
    }
  }
  if (const auto build = j.find("build"); build != j.end()) {
    if (!build->is_object()) return bad("\"build\" is not an object");
    if (const auto s = build->find("vertical_scale"); s != build->end()) {
      if (!s->is_number() || !std::isfinite(s->get<double>()) || s->get<double>() == 0.0)
        return bad("\"build\".\"vertical_scale\" is not a non-zero number");
      m.verticalScale = s->get<double>();
    }
  }
  if (const auto texture = j.find("texture"); texture != j.end()) {
    if (!texture->is_object()) return bad("\"texture\" is not an object");
    if (const auto levels = texture->find("levels"); levels != texture->end()) {
      if (!levels->is_array() || levels->size() != header.levelCount)
        return bad("\"texture\".\"levels\" is not one entry per level (" +
                   std::to_string(header.levelCount) + ")");
      for (size_t level = 0; level < levels->size(); ++level) {
        const json& l = (*levels)[level];
        TextureLevelSizes sizes;
        for (auto [key, out] :
             {std::pair{"color_size", &sizes.color}, std::pair{"normal_size", &sizes.normal}}) {
          const auto v = l.is_object() ? l.find(key) : l.end();
          if (!l.is_object() || v == l.end() || !v->is_number_unsigned() ||
              !isTileSize(v->get<uint64_t>()))
            return bad("texture level " + std::to_string(level) + " has no valid \"" + key +
                       "\" (2^k + 1 texels, at most " + std::to_string(kMaxTextureSize) + ")");
          *out = uint32_t(v->get<uint64_t>());
        }
        m.textureLevels.push_back(sizes);
      }
    }
  }
  return m;
}

}  // namespace terralod
