#include "terralod/vegetation/vegetation_where.h"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace terralod::veg {
namespace {

constexpr std::string_view kOption = "--vegetation-where";

Error termError(std::string_view term, const std::string& problem) {
  return makeError(std::string(kOption), "'" + std::string(term) + "': " + problem);
}

std::vector<std::string_view> split(std::string_view text, char separator) {
  std::vector<std::string_view> parts;
  for (size_t start = 0;;) {
    const size_t end = text.find(separator, start);
    parts.push_back(text.substr(start, end == std::string_view::npos ? end : end - start));
    if (end == std::string_view::npos) return parts;
    start = end + 1;
  }
}

Result<double> numberIn(std::string_view term, std::string_view text) {
  double v = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (error != std::errc() || end != text.data() + text.size() || text.empty() || !std::isfinite(v))
    return termError(term, "not a number");
  return v;
}

}  // namespace

bool VegetationWhere::allowsMaterialAt(glm::dvec2 centre) const {
  return materials.empty() || (materialMask && materialMask->allowsAt(centre.x, centre.y));
}

bool VegetationWhere::allowsGround(double height, double slope) const {
  if (heightBelow && !(height < *heightBelow)) return false;
  if (heightAbove && !(height > *heightAbove)) return false;
  if (slopeBelow && !(slope < *slopeBelow)) return false;
  if (slopeAbove && !(slope > *slopeAbove)) return false;
  return true;
}

Result<VegetationWhere> parseVegetationWhere(std::string_view text) {
  VegetationWhere w;
  if (text.empty()) return makeError(std::string(kOption), "empty (e.g. height<2400,slope<30)");
  for (std::string_view term : split(text, ',')) {
    const size_t op = term.find_first_of("<>=");
    if (op == std::string_view::npos || op == 0)
      return termError(term, "expected height<H, height>H, slope<S, slope>S or material=NAME");
    const std::string_view key = term.substr(0, op), value = term.substr(op + 1);
    const char relation = term[op];
    if (key == "material") {
      if (relation != '=') return termError(term, "materials are named with =");
      if (!w.materials.empty()) return termError(term, "material given twice (use A|B)");
      for (std::string_view name : split(value, '|')) {
        if (name.empty()) return termError(term, "an empty material name");
        w.materials.emplace_back(name);
      }
      continue;
    }
    if (key != "height" && key != "slope")
      return termError(term,
                       "unknown quantity '" + std::string(key) + "' (height, slope, material)");
    if (relation == '=') return termError(term, "heights and slopes take < or >");
    auto v = numberIn(term, value);
    if (!v) return v.error();
    if (key == "slope" && (*v < 0 || *v > 90)) return termError(term, "a slope is 0 to 90 degrees");
    std::optional<double>& bound = key == "height"
                                       ? (relation == '<' ? w.heightBelow : w.heightAbove)
                                       : (relation == '<' ? w.slopeBelow : w.slopeAbove);
    if (bound) return termError(term, "given twice");
    bound = *v;
  }
  return w;
}

}  // namespace terralod::veg
