#pragma once
// Golden image comparison for render tests (link terralod_render). An actual render is
// compared with tests/golden/expected/<name>.png within a tolerance; on failure (or when no
// expected image exists yet) <name>.actual.png and <name>.diff.png go to $TERRALOD_GOLDEN_OUT,
// else the build tree's golden-out/, and scripts/approve-goldens.sh turns them into the new
// expected images once someone has looked at them.

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

#include "terralod/render/image.h"

namespace terralod::test {

/// How far an image may stray from its expected one. A pixel differs when any channel differs
/// by more than channelThreshold; the images match when at most maxDifferingFraction of the
/// pixels differ. The defaults absorb interpolation rounding between GL drivers, not edges.
struct ImageTolerance {
  int channelThreshold = 2;
  double maxDifferingFraction = 0.001;
};

/// The outcome of a comparison; message says why it failed and where the evidence went.
struct ImageComparison {
  bool matches = false;
  double meanAbsoluteError = 0.0;  ///< mean |actual - expected| over all channels, 0..255
  double differingFraction = 0.0;  ///< fraction of pixels beyond the threshold
  int maxChannelDifference = 0;
  std::string message;
};

/// Where failing comparisons write their images: $TERRALOD_GOLDEN_OUT, else the build tree.
inline std::filesystem::path goldenOutputDir() {
  if (const char* dir = std::getenv("TERRALOD_GOLDEN_OUT"); dir && *dir) return dir;
#ifdef TERRALOD_GOLDEN_OUT_DIR
  return TERRALOD_GOLDEN_OUT_DIR;
#else
  return std::filesystem::current_path() / "golden-out";
#endif
}

/// Compares two images of equal size pixel by pixel (no files involved).
inline ImageComparison compareImages(const Image& actual, const Image& expected,
                                     const ImageTolerance& tolerance = {}) {
  ImageComparison result;
  if (actual.width != expected.width || actual.height != expected.height) {
    result.differingFraction = 1.0;
    result.message = "size differs: expected " + std::to_string(expected.width) + "x" +
                     std::to_string(expected.height) + ", got " + std::to_string(actual.width) +
                     "x" + std::to_string(actual.height);
    return result;
  }
  const size_t pixels = size_t(actual.width) * size_t(actual.height);
  size_t differing = 0;
  double sum = 0.0;
  for (size_t i = 0; i < pixels; ++i) {
    int worst = 0;
    for (size_t c = 0; c < 4; ++c) {
      const int d = std::abs(int(actual.rgba[i * 4 + c]) - int(expected.rgba[i * 4 + c]));
      sum += d;
      worst = std::max(worst, d);
    }
    result.maxChannelDifference = std::max(result.maxChannelDifference, worst);
    if (worst > tolerance.channelThreshold) ++differing;
  }
  result.meanAbsoluteError = pixels ? sum / double(pixels * 4) : 0.0;
  result.differingFraction = pixels ? double(differing) / double(pixels) : 0.0;
  result.matches = result.differingFraction <= tolerance.maxDifferingFraction;
  char summary[256];
  std::snprintf(summary, sizeof summary,
                "%.3f%% of pixels differ by more than %d (allowed %.3f%%), largest channel "
                "difference %d, mean absolute error %.3f",
                100.0 * result.differingFraction, tolerance.channelThreshold,
                100.0 * tolerance.maxDifferingFraction, result.maxChannelDifference,
                result.meanAbsoluteError);
  result.message = summary;
  return result;
}

/// A picture of where two same-sized images differ: pixels beyond the threshold in red (the
/// larger the difference, the brighter), smaller differences in blue, amplified so one step
/// shows, and matching pixels as a dim grey copy of the expected image for orientation.
inline Image diffImage(const Image& actual, const Image& expected, int channelThreshold) {
  constexpr int kAmplify = 16;
  Image diff{actual.width, actual.height, std::vector<uint8_t>(actual.rgba.size())};
  for (size_t i = 0; i < diff.rgba.size(); i += 4) {
    int worst = 0;
    for (size_t c = 0; c < 4; ++c)
      worst = std::max(worst, std::abs(int(actual.rgba[i + c]) - int(expected.rgba[i + c])));
    uint8_t* out = &diff.rgba[i];
    const int amplified = std::min(255, worst * kAmplify);
    if (worst > channelThreshold) {
      out[0] = uint8_t(std::max(128, amplified));
      out[1] = out[2] = 0;
    } else if (worst > 0) {
      out[0] = out[1] = 0;
      out[2] = uint8_t(std::max(96, amplified));
    } else {
      const int grey = (expected.rgba[i] + expected.rgba[i + 1] + expected.rgba[i + 2]) / 12;
      out[0] = out[1] = out[2] = uint8_t(grey);
    }
    out[3] = 255;
  }
  return diff;
}

/// Compares `actual` with TERRALOD_GOLDEN_DIR/<name>.png. `name` is a plain file stem such as
/// "foundation_triangle". On a match, stale <name>.actual.png and <name>.diff.png from an
/// earlier failure are removed so approving cannot pick them up.
inline ImageComparison compareWithGolden(const Image& actual, const std::string& name,
                                         const ImageTolerance& tolerance = {}) {
  namespace fs = std::filesystem;
  const fs::path expectedPath = fs::path(TERRALOD_GOLDEN_DIR) / (name + ".png");
  const fs::path outDir = goldenOutputDir();
  const fs::path actualPath = outDir / (name + ".actual.png");
  const fs::path diffPath = outDir / (name + ".diff.png");
  const std::string approve = "scripts/approve-goldens.sh " + outDir.string();
  std::error_code ec;

  auto writeEvidence = [&](const Image* expected, ImageComparison& result) {
    fs::create_directories(outDir, ec);
    if (Status s = writePng(actual, actualPath.string()); !s) {
      result.message += "; could not write the actual image: " + s.error().message;
      return false;
    }
    fs::remove(diffPath, ec);
    if (expected && expected->width == actual.width && expected->height == actual.height) {
      if (Status s =
              writePng(diffImage(actual, *expected, tolerance.channelThreshold), diffPath.string());
          !s)
        result.message += "; could not write the diff image: " + s.error().message;
    }
    return true;
  };

  ImageComparison result;
  if (!fs::exists(expectedPath, ec)) {
    result.message = name + ": no expected image " + expectedPath.string();
    if (writeEvidence(nullptr, result))
      result.message +=
          "; wrote " + actualPath.string() + " - look at it, then approve it with " + approve;
    return result;
  }
  auto expected = readPng(expectedPath.string());
  if (!expected) {
    result.message = name + ": " + expected.error().message;
    return result;
  }
  result = compareImages(actual, *expected, tolerance);
  if (result.matches) {
    fs::remove(actualPath, ec);
    fs::remove(diffPath, ec);
    return result;
  }
  result.message = name + " does not match " + expectedPath.string() + ": " + result.message;
  if (writeEvidence(&expected.value(), result)) {
    result.message += "; wrote " + actualPath.string();
    if (fs::exists(diffPath, ec)) result.message += " and " + diffPath.string();
    result.message += "; if the change is intended, approve it with " + approve;
  }
  return result;
}

}  // namespace terralod::test
