#include "cli_checks.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>

namespace terralod::cli {
namespace {

// The whole text as a finite number, or nothing.
std::optional<double> parseNumber(const std::string& text) {
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::string shortest(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

}  // namespace

CLI::Validator positiveNumber() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const auto value = parseNumber(text);
        if (!value) return "must be a number greater than 0 (got " + text + ")";
        if (!(*value > 0)) return "must be greater than 0 (got " + text + ")";
        return {};
      },
      "", "");
}

CLI::Validator positiveNumberOr(const std::string& word) {
  return CLI::Validator(
      [word](std::string& text) -> std::string {
        if (text == word) return {};
        const auto value = parseNumber(text);
        if (!value || !(*value > 0))
          return "must be a number greater than 0 or " + word + " (got " + text + ")";
        return {};
      },
      "", "");
}

CLI::Validator nonNegativeNumber() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const auto value = parseNumber(text);
        if (!value) return "must be a number, 0 or more (got " + text + ")";
        if (!(*value >= 0)) return "must be 0 or more (got " + text + ")";
        return {};
      },
      "", "");
}

CLI::Validator numberBetween(double lo, double hi) {
  const std::string range = shortest(lo) + " to " + shortest(hi);
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        const auto value = parseNumber(text);
        if (!value) return "must be a number from " + range + " (got " + text + ")";
        if (*value < lo || *value > hi) return "must be from " + range + " (got " + text + ")";
        return {};
      },
      "", "");
}

CLI::Validator finiteNumber() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        return parseNumber(text) ? std::string() : "must be a finite number (got " + text + ")";
      },
      "", "");
}

namespace detail {
std::string wholeNumberWording(const std::string& lo, const std::string& hi, bool boundedLo,
                               bool boundedHi) {
  if (boundedLo && boundedHi) return "a whole number from " + lo + " to " + hi;
  if (boundedLo) return "a whole number, " + lo + " or more";
  if (boundedHi) return "a whole number, " + hi + " or less";
  return "a whole number";
}
}  // namespace detail

}  // namespace terralod::cli
