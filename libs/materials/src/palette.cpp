#include "terralod/materials/palette.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <set>
#include <sstream>

namespace terralod {
namespace {

bool parseHexColor(const std::string& text, std::array<uint8_t, 3>& color) {
  if (text.size() != 7 || text[0] != '#') return false;
  for (int c = 0; c < 3; ++c) {
    unsigned value = 0;
    for (int k = 0; k < 2; ++k) {
      const char ch = text[size_t(1 + 2 * c + k)];
      unsigned digit;
      if (ch >= '0' && ch <= '9')
        digit = unsigned(ch - '0');
      else if (ch >= 'a' && ch <= 'f')
        digit = unsigned(ch - 'a' + 10);
      else if (ch >= 'A' && ch <= 'F')
        digit = unsigned(ch - 'A' + 10);
      else
        return false;
      value = value * 16 + digit;
    }
    color[size_t(c)] = uint8_t(value);
  }
  return true;
}

bool wholeNumber(const nlohmann::json& j, int64_t lo, int64_t hi, int64_t& out) {
  if (j.is_number_integer()) {
    out = j.get<int64_t>();
  } else if (j.is_number_float()) {
    const double d = j.get<double>();
    if (d != double(int64_t(d))) return false;
    out = int64_t(d);
  } else {
    return false;
  }
  return out >= lo && out <= hi;
}

}  // namespace

Result<std::vector<Material>> readPalette(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError(path, "cannot read the palette file");
  std::stringstream text;
  text << in.rdbuf();
  const nlohmann::json doc = nlohmann::json::parse(text.str(), nullptr, false);
  if (doc.is_discarded()) return makeError(path, "palette is not valid JSON");
  const std::string schema =
      " (expected {\"classes\": [{\"value\": 0..255, \"name\": \"...\", \"color\": [r, g, b] or "
      "\"#rrggbb\"}, ...]})";
  if (!doc.is_object() || !doc.contains("classes") || !doc["classes"].is_array())
    return makeError(path, "palette has no \"classes\" array" + schema);
  const auto& classes = doc["classes"];
  if (classes.empty()) return makeError(path, "palette has no classes");
  std::vector<Material> out;
  std::set<int64_t> seen;
  for (size_t i = 0; i < classes.size(); ++i) {
    const auto& c = classes[i];
    const std::string where = "palette class " + std::to_string(i + 1);
    if (!c.is_object()) return makeError(path, where + " is not an object" + schema);
    int64_t value = 0;
    if (!c.contains("value") || !wholeNumber(c["value"], 0, 255, value))
      return makeError(path, where + ": \"value\" must be a whole number 0..255");
    if (!seen.insert(value).second)
      return makeError(path, "palette lists class value " + std::to_string(value) + " twice");
    if (!c.contains("name") || !c["name"].is_string() || c["name"].get<std::string>().empty())
      return makeError(path, where + " (value " + std::to_string(value) +
                                 "): \"name\" must be a non-empty string");
    Material m;
    m.id = uint8_t(value);
    m.name = c["name"].get<std::string>();
    bool colorOk = false;
    if (c.contains("color")) {
      const auto& color = c["color"];
      if (color.is_string()) {
        colorOk = parseHexColor(color.get<std::string>(), m.color);
      } else if (color.is_array() && color.size() == 3) {
        colorOk = true;
        for (size_t k = 0; k < 3; ++k) {
          int64_t channel = 0;
          colorOk = colorOk && wholeNumber(color[k], 0, 255, channel);
          m.color[k] = uint8_t(channel);
        }
      }
    }
    if (!colorOk)
      return makeError(path, where + " (value " + std::to_string(value) +
                                 "): \"color\" must be [r, g, b] with 0..255 each or \"#rrggbb\"");
    out.push_back(std::move(m));
  }
  return out;
}

std::array<uint8_t, 3> distinctColor(size_t index) {
  static constexpr std::array<std::array<uint8_t, 3>, 12> kColors{{
      {31, 119, 180},
      {255, 127, 14},
      {44, 160, 44},
      {214, 39, 40},
      {148, 103, 189},
      {140, 86, 75},
      {227, 119, 194},
      {127, 127, 127},
      {188, 189, 34},
      {23, 190, 207},
      {255, 221, 113},
      {0, 80, 60},
  }};
  return kColors[index % kColors.size()];
}

}  // namespace terralod
