#include "terralod/format/terrain_edits_json.h"

#include <cmath>
#include <optional>

#include "terrain_edit_list.h"

namespace terralod {
namespace {

using json = nlohmann::json;

std::optional<Brush> parseBrush(const std::string& name) {
  for (Brush b : {Brush::kRaise, Brush::kLower, Brush::kSmooth, Brush::kPaint})
    if (brushName(b) == name) return b;
  return std::nullopt;
}

bool isFinite(const json& v) {
  return v.is_number() && std::isfinite(v.get<double>());
}

// One entry, or the problem with it.
Result<TerrainEdit> parseEntry(const json& e) {
  if (!e.is_object()) return Error{"is not an object"};
  for (const auto& [key, value] : e.items())
    if (key != "brush" && key != "center" && key != "radius" && key != "amount" &&
        key != "material")
      return Error{"unknown field \"" + key +
                   "\" (brush, center, radius, amount and material are known)"};
  TerrainEdit edit;
  const auto brush = e.find("brush");
  const std::optional<Brush> b =
      brush != e.end() && brush->is_string() ? parseBrush(brush->get<std::string>()) : std::nullopt;
  if (!b) return Error{"\"brush\" is not one of \"raise\", \"lower\", \"smooth\", \"paint\""};
  edit.brush = *b;
  const auto center = e.find("center");
  if (center == e.end() || !center->is_array() || center->size() != 2 || !isFinite((*center)[0]) ||
      !isFinite((*center)[1]))
    return Error{"\"center\" is not [x, y] in metres"};
  edit.centerX = (*center)[0].get<double>();
  edit.centerY = (*center)[1].get<double>();
  const auto radius = e.find("radius");
  if (radius == e.end() || !isFinite(*radius) || radius->get<double>() <= 0.0)
    return Error{"\"radius\" is not a number of metres greater than 0"};
  edit.radius = radius->get<double>();
  const auto amount = e.find("amount");
  const auto material = e.find("material");
  if (edit.brush == Brush::kPaint) {
    if (material == e.end() || !material->is_number_unsigned() || material->get<uint64_t>() > 255)
      return Error{"a paint edit's \"material\" is not a material id 0..255"};
    edit.material = uint8_t(material->get<uint64_t>());
    if (amount != e.end() && !isFinite(*amount)) return Error{"\"amount\" is not a number"};
    if (amount != e.end()) edit.amount = amount->get<double>();
    return edit;
  }
  if (material != e.end())
    return Error{"\"material\" belongs to paint edits, not " + std::string(brushName(edit.brush))};
  if (amount == e.end() || !isFinite(*amount) || amount->get<double>() <= 0.0)
    return Error{edit.brush == Brush::kSmooth
                     ? "\"amount\" is not a strength in (0, 1]"
                     : "\"amount\" is not a number of metres greater than 0"};
  edit.amount = amount->get<double>();
  if (edit.brush == Brush::kSmooth && edit.amount > 1.0)
    return Error{"\"amount\" is not a strength in (0, 1]"};
  return edit;
}

}  // namespace

Result<std::vector<TerrainEdit>> parseTerrainEditList(const json& list, const std::string& subject,
                                                      const std::string& where) {
  if (!list.is_array()) return makeError(subject, where + " is not an array");
  std::vector<TerrainEdit> edits;
  for (size_t i = 0; i < list.size(); ++i) {
    auto edit = parseEntry(list[i]);
    if (!edit)
      return makeError(subject, where + "[" + std::to_string(i) + "]: " + edit.error().message);
    edits.push_back(*edit);
  }
  return edits;
}

json terrainEditList(const std::vector<TerrainEdit>& edits) {
  json list = json::array();
  for (const TerrainEdit& e : edits) {
    json entry = {{"brush", std::string(brushName(e.brush))},
                  {"center", {e.centerX, e.centerY}},
                  {"radius", e.radius}};
    if (e.brush == Brush::kPaint)
      entry["material"] = e.material;
    else
      entry["amount"] = e.amount;
    list.push_back(entry);
  }
  return list;
}

Result<std::vector<TerrainEdit>> parseTerrainEditScript(std::string_view text,
                                                        const std::string& subject) {
  const json j = json::parse(text, nullptr, false);
  if (j.is_discarded()) return makeError(subject, "is not valid JSON");
  if (!j.is_object() || !j.contains("edits"))
    return makeError(subject, "is not {\"edits\": [...]}");
  return parseTerrainEditList(j["edits"], subject, "edits");
}

std::string terrainEditScript(const std::vector<TerrainEdit>& edits) {
  return json{{"edits", terrainEditList(edits)}}.dump(2);
}

}  // namespace terralod
