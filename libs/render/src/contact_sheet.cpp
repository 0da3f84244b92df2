#include "terralod/render/contact_sheet.h"

#include <algorithm>
#include <cstring>

namespace terralod {

Image downscale(const Image& image, int width, int height) {
  Image out{width, height, std::vector<uint8_t>(size_t(width) * size_t(height) * 4)};
  for (int y = 0; y < height; ++y) {
    const int y0 = y * image.height / height,
              y1 = std::max(y0 + 1, (y + 1) * image.height / height);
    for (int x = 0; x < width; ++x) {
      const int x0 = x * image.width / width, x1 = std::max(x0 + 1, (x + 1) * image.width / width);
      uint32_t sum[4] = {0, 0, 0, 0};
      for (int sy = y0; sy < y1; ++sy)
        for (int sx = x0; sx < x1; ++sx)
          for (int c = 0; c < 4; ++c) sum[c] += image.rgba[(size_t(sy) * image.width + sx) * 4 + c];
      const uint32_t n = uint32_t((y1 - y0) * (x1 - x0));
      for (int c = 0; c < 4; ++c)
        out.rgba[(size_t(y) * width + x) * 4 + c] = uint8_t((sum[c] + n / 2) / n);
    }
  }
  return out;
}

Image makeContactSheet(std::span<const Image> frames, int columns, int thumbnailWidth) {
  constexpr int kGutter = 4;
  if (frames.empty() || columns <= 0 || thumbnailWidth <= 0) return {};
  columns = std::min(columns, int(frames.size()));
  const int rows = (int(frames.size()) + columns - 1) / columns;
  int thumbnailHeight = 1;
  for (const Image& f : frames)
    thumbnailHeight = std::max(thumbnailHeight, f.height * thumbnailWidth / std::max(f.width, 1));
  Image sheet;
  sheet.width = columns * thumbnailWidth + (columns + 1) * kGutter;
  sheet.height = rows * thumbnailHeight + (rows + 1) * kGutter;
  sheet.rgba.assign(size_t(sheet.width) * size_t(sheet.height) * 4, 0);
  for (size_t i = 3; i < sheet.rgba.size(); i += 4) sheet.rgba[i] = 255;
  for (size_t k = 0; k < frames.size(); ++k) {
    const Image& f = frames[k];
    const int h = std::max(1, f.height * thumbnailWidth / std::max(f.width, 1));
    const Image thumb = downscale(f, thumbnailWidth, h);
    const int left = kGutter + int(k) % columns * (thumbnailWidth + kGutter);
    const int top = kGutter + int(k) / columns * (thumbnailHeight + kGutter);
    for (int y = 0; y < h; ++y)
      std::memcpy(&sheet.rgba[(size_t(top + y) * sheet.width + left) * 4],
                  &thumb.rgba[size_t(y) * thumbnailWidth * 4], size_t(thumbnailWidth) * 4);
  }
  return sheet;
}

}  // namespace terralod
