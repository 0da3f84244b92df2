#include "terralod/vegetation/ldi_picture.h"

#include <cmath>

namespace terralod::veg {

LdiPicture compositeLdi(const Ldi& ldi, std::array<uint8_t, 3> background) {
  const LdiCamera& c = ldi.camera;
  LdiPicture p{int(c.width), int(c.height), std::vector<uint8_t>(size_t(c.width) * c.height * 4)};
  size_t next = 0;
  for (uint32_t row = 0; row < c.height; ++row)
    for (uint32_t col = 0; col < c.width; ++col) {
      float rgb[3] = {0, 0, 0}, left = 1;  // colour so far, transmittance left
      for (uint8_t k = 0; k < ldi.layerCounts[size_t(row) * c.width + col]; ++k) {
        const uint32_t v = ldi.pixels[next++].rgba;
        const float a = float(v >> 24) / 255.0f;
        for (int i = 0; i < 3; ++i) rgb[i] += left * a * float(v >> (8 * i) & 0xff);
        left *= 1 - a;
      }
      uint8_t* out = &p.rgba[(size_t(c.height - 1 - row) * c.width + col) * 4];
      for (int i = 0; i < 3; ++i) out[i] = uint8_t(std::lround(rgb[i] + left * background[i]));
      out[3] = 255;
    }
  return p;
}

}  // namespace terralod::veg
