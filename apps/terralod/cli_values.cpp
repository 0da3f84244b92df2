#include "cli_values.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace terralod::cli {

Result<std::array<int, 2>> parseSize(const std::string& text, const std::string& option) {
  const size_t x = text.find('x');
  char* end = nullptr;
  if (x != std::string::npos) {
    const long w = std::strtol(text.c_str(), &end, 10);
    if (end == text.c_str() + x) {
      const long h = std::strtol(text.c_str() + x + 1, &end, 10);
      if (*end == '\0' && end != text.c_str() + x + 1 && w >= 1 && w <= 16384 && h >= 1 &&
          h <= 16384)
        return std::array<int, 2>{int(w), int(h)};
    }
  }
  return Error{option + " must be WIDTHxHEIGHT in pixels (1 to 16384 each), not '" + text + "'"};
}

Result<glm::dvec3> parsePoint(const std::string& text, const std::string& option) {
  glm::dvec3 p;
  const char* s = text.c_str();
  for (int k = 0; k < 3; ++k) {
    char* end = nullptr;
    p[k] = std::strtod(s, &end);
    const char expected = k < 2 ? ',' : '\0';
    if (end == s || *end != expected || !std::isfinite(p[k]))
      return Error{option + " must be X,Y,Z: three finite numbers in metres, not '" + text + "'"};
    s = end + (k < 2 ? 1 : 0);
  }
  return p;
}

Result<std::array<uint8_t, 3>> parseColor(const std::string& text, const std::string& option) {
  const std::string hex = !text.empty() && text[0] == '#' ? text.substr(1) : text;
  char* end = nullptr;
  const unsigned long v = std::strtoul(hex.c_str(), &end, 16);
  if (hex.size() != 6 || hex.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos ||
      *end != '\0')
    return Error{option + " must be a colour RRGGBB in hexadecimal, not '" + text + "'"};
  return std::array<uint8_t, 3>{uint8_t(v >> 16), uint8_t(v >> 8), uint8_t(v)};
}

}  // namespace terralod::cli
