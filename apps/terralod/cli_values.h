#pragma once
// Parsing the CLI's compound values ("1024x768", "X,Y,Z", "RRGGBB"): one place, one wording of
// the error each gives.

#include <array>
#include <glm/glm.hpp>
#include <string>

#include "terralod/core/result.h"

namespace terralod::cli {

/// "WxH" with both in 1..16384.
Result<std::array<int, 2>> parseSize(const std::string& text, const std::string& option);
/// "X,Y,Z", three finite numbers.
Result<glm::dvec3> parsePoint(const std::string& text, const std::string& option);
/// "RRGGBB" (or "#RRGGBB"), hexadecimal sRGB.
Result<std::array<uint8_t, 3>> parseColor(const std::string& text, const std::string& option);

}  // namespace terralod::cli
