#pragma once
// An 8-bit RGBA image in memory and its PNG (and JPEG) files: what renders come back as, what
// golden tests compare and what the CLI writes.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "terralod/core/result.h"

namespace terralod {

/// Pixels row by row, top row first, 4 bytes (R, G, B, A) per pixel, no row padding.
/// A plain value: copy it, move it, use it on any thread.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgba;  ///< width * height * 4 bytes

  /// The pixel in column x of row y (row 0 is the top). Both must be inside the image.
  std::array<uint8_t, 4> pixel(int x, int y) const;
};

/// Writes `image` as an RGBA PNG. The file appears complete or not at all (written beside
/// the target, then renamed over it). Fails with a message naming `path`. Any thread.
Status writePng(const Image& image, const std::string& path);

/// Writes `image` as a baseline JPEG of `quality` (1..100), alpha dropped, atomically like
/// writePng: for pictures of frames, where PNG would be several times larger. Any thread.
Status writeJpeg(const Image& image, const std::string& path, int quality = 85);

enum class ImageFormat { kPng, kJpeg };

/// The format a file name asks for: `.png`, or `.jpg`/`.jpeg` (any case). Any other name is
/// refused with one line naming the file. Touches nothing.
Result<ImageFormat> imageFormatFor(const std::string& path);

/// Writes `image` as its name asks (imageFormatFor): PNG, or JPEG of quality 90; atomically,
/// like writePng. Refuses other names before encoding anything. Any thread.
Status writeImage(const Image& image, const std::string& path);

/// Reads a PNG into RGBA8 (grey, grey-alpha and RGB are expanded; 16-bit is reduced).
/// Fails with a message naming `path` when it is missing or not a readable PNG. Any thread.
Result<Image> readPng(const std::string& path);

}  // namespace terralod
