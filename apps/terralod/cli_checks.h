#pragma once
// Checks of the CLI's numeric options. Each failure is one plain line, "--max-error: must be
// greater than 0 (got 0)", where CLI11's own validators print their bounds in full (e.g. "Value
// 0 not in range 0.000000 to 1797693134862315...", 300 digits) and its conversions say "The
// value abc is not an allowed value". Every numeric option of every command takes one of these.

#include <CLI/CLI.hpp>

#include <charconv>
#include <limits>
#include <string>
#include <type_traits>

namespace terralod::cli {

/// A finite number greater than 0.
CLI::Validator positiveNumber();
/// A finite number greater than 0, or the word `word` (e.g. "off").
CLI::Validator positiveNumberOr(const std::string& word);
/// A finite number, 0 or more.
CLI::Validator nonNegativeNumber();
/// A finite number from lo to hi (inclusive).
CLI::Validator numberBetween(double lo, double hi);
/// Any finite number.
CLI::Validator finiteNumber();

namespace detail {
/// "a whole number", "a whole number, 1 or more" or "a whole number from 1 to 22".
std::string wholeNumberWording(const std::string& lo, const std::string& hi, bool boundedLo,
                               bool boundedHi);
}  // namespace detail

/// A whole number of type T from lo to hi (inclusive); by default anything T holds, so the
/// conversion after the check cannot fail either.
template <class T>
CLI::Validator wholeNumber(T lo = std::numeric_limits<T>::min(),
                           T hi = std::numeric_limits<T>::max()) {
  const std::string wording =
      detail::wholeNumberWording(std::to_string(lo), std::to_string(hi),
                                 lo != std::numeric_limits<T>::min() || std::is_unsigned_v<T>,
                                 hi != std::numeric_limits<T>::max());
  return CLI::Validator(
      [lo, hi, wording](std::string& text) -> std::string {
        T value{};
        const char* end = text.data() + text.size();
        const auto [at, error] = std::from_chars(text.data(), end, value);
        if (error != std::errc() || at != end || text.empty() || value < lo || value > hi)
          return "must be " + wording + " (got " + text + ")";
        return {};
      },
      "", "");
}

}  // namespace terralod::cli
