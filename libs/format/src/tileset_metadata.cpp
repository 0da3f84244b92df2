#include "terralod/format/tileset_metadata.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>

#include "terrain_edit_list.h"
#include "terralod/format/texture_codec.h"

namespace terralod {
namespace {

using json = nlohmann::json;

bool isTileSize(uint64_t v) {
  return v >= 2 && v <= kMaxTextureSize && ((v - 1) & (v - 2)) == 0;
}

std::optional<std::array<uint8_t, 3>> parseColorHex(const std::string& text) {
  if (text.size() != 7 || text[0] != '#') return std::nullopt;
  std::array<uint8_t, 3> color{};
  for (size_t i = 0; i < 6; ++i) {
    const char c = text[1 + i];
    int v = 0;
    if (c >= '0' && c <= '9')
      v = c - '0';
    else if (c >= 'a' && c <= 'f')
      v = c - 'a' + 10;
    else if (c >= 'A' && c <= 'F')
      v = c - 'A' + 10;
    else
      return std::nullopt;
    color[i / 2] = uint8_t(color[i / 2] * 16 + v);
  }
  return color;
}

}  // namespace

std::string colorHex(const std::array<uint8_t, 3>& color) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string s = "#";
  for (uint8_t c : color) {
    s += kDigits[c >> 4];
    s += kDigits[c & 15];
  }
  return s;
}

SourceGrid sourceGridOf(const TilesetHeader& header, const TilesetMetadata& metadata) {
  SourceGrid g;
  g.columns = int32_t(header.sourceColumns);
  g.rows = int32_t(header.sourceRows);
  g.spacingX = header.spacingX;
  g.spacingY = header.spacingY;
  g.crsWkt = metadata.sourceCrsWkt;
  if (metadata.sourceGeoTransform) {
    g.geoTransform = *metadata.sourceGeoTransform;
    g.hasGeoTransform = true;
  }
  return g;
}

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
    if (const auto f = source->find("file"); f != source->end()) {
      if (!f->is_string()) return bad("\"source\".\"file\" is not a string");
      m.sourceFile = f->get<std::string>();
    }
    if (const auto band = source->find("band"); band != source->end()) {
      if (!band->is_number_integer() || band->get<int64_t>() < 1 || band->get<int64_t>() > 65535)
        return bad("\"source\".\"band\" is not a band number");
      m.sourceBand = int(band->get<int64_t>());
    }
    if (const auto w = source->find("crs_wkt"); w != source->end()) {
      if (!w->is_string()) return bad("\"source\".\"crs_wkt\" is not a string");
      m.sourceCrsWkt = w->get<std::string>();
    }
    if (const auto g = source->find("geotransform"); g != source->end()) {
      std::array<double, 6> t{};
      bool ok = g->is_array() && g->size() == 6;
      for (size_t k = 0; ok && k < 6; ++k) {
        ok = (*g)[k].is_number() && std::isfinite((*g)[k].get<double>());
        if (ok) t[k] = (*g)[k].get<double>();
      }
      if (!ok || t[1] == 0.0 || t[5] == 0.0)
        return bad("\"source\".\"geotransform\" is not six finite numbers with non-zero steps");
      m.sourceGeoTransform = t;
    }
  }
  if (const auto build = j.find("build"); build != j.end()) {
    if (!build->is_object()) return bad("\"build\" is not an object");
    if (const auto s = build->find("vertical_scale"); s != build->end()) {
      if (!s->is_number() || !std::isfinite(s->get<double>()) || s->get<double>() == 0.0)
        return bad("\"build\".\"vertical_scale\" is not a non-zero number");
      m.verticalScale = s->get<double>();
    }
    if (const auto v = build->find("materials"); v != build->end()) {
      if (!v->is_string()) return bad("\"build\".\"materials\" is not a string");
      m.materialsSource = v->get<std::string>();
    }
    if (const auto v = build->find("morph_gap"); v != build->end()) {
      if (!v->is_number() || !(v->get<double>() >= 0.0 && v->get<double>() <= 1.0))
        return bad("\"build\".\"morph_gap\" is not a number from 0 to 1");
      m.morphGap = v->get<double>();
    }
    if (const auto v = build->find("material_rules"); v != build->end()) {
      if (!v->is_boolean()) return bad("\"build\".\"material_rules\" is not true or false");
      m.materialRules = v->get<bool>();
    }
  }
  if (const auto texture = j.find("texture"); texture != j.end()) {
    if (!texture->is_object()) return bad("\"texture\" is not an object");
    if (const auto color = texture->find("color"); color != texture->end()) {
      if (!color->is_string()) return bad("\"texture\".\"color\" is not text");
      m.textureColor = color->get<std::string>();
    }
    if (const auto snow = texture->find("snow_line"); snow != texture->end()) {
      const auto last = snow->is_object() ? snow->find("last_row") : snow->end();
      const auto metres = snow->is_object() ? snow->find("metres") : snow->end();
      if (last == snow->end() || !last->is_number_unsigned() ||
          last->get<uint64_t>() > 0xFFFFFFFFu || metres == snow->end() || !metres->is_array() ||
          metres->size() < 2 || metres->size() > 1024)
        return bad("\"texture\".\"snow_line\" is not a last row and 2 to 1024 heights");
      m.snowLineLastRow = last->get<uint32_t>();
      for (const json& v : *metres) {
        if (!v.is_number() || !(std::fabs(v.get<double>()) <= 1e5))
          return bad("\"texture\".\"snow_line\" has a height that is not a number of metres");
        m.snowLine.push_back(v.get<float>());
      }
    }
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
  const auto materials = j.find("materials");
  if (materials != j.end()) {
    if (!materials->is_array() || materials->size() > kMaxTilesetMaterials)
      return bad("\"materials\" is not an array of at most " +
                 std::to_string(kMaxTilesetMaterials) + " materials");
    for (size_t i = 0; i < materials->size(); ++i) {
      const json& e = (*materials)[i];
      const auto id = e.is_object() ? e.find("id") : e.end();
      const auto name = e.is_object() ? e.find("name") : e.end();
      const auto color = e.is_object() ? e.find("color") : e.end();
      const auto rgb = color != e.end() && color->is_string()
                           ? parseColorHex(color->get<std::string>())
                           : std::nullopt;
      if (id == e.end() || !id->is_number_unsigned() || id->get<uint64_t>() > 255 ||
          name == e.end() || !name->is_string() || !rgb)
        return bad("material " + std::to_string(i) +
                   " is not {\"id\": 0..255, \"name\": text, \"color\": \"#rrggbb\"}");
      m.materials.push_back({uint8_t(id->get<uint64_t>()), name->get<std::string>(), *rgb});
    }
  }
  if (const auto edits = j.find("edits"); edits != j.end()) {
    auto list = parseTerrainEditList(*edits, subject, "invalid tileset metadata: \"edits\"");
    if (!list) return list.error();
    m.edits = std::move(*list);
  }
  if (header.meshKind == MeshKind::kVipm && m.materials.empty())
    return bad("a VIPM tileset names no \"materials\"");
  return m;
}

}  // namespace terralod
