// terralod vegetation render-tile V.tlv --tile K --resolution R --direction D
//   [--view ldi|top|textures]
//   -o OUT.png

#include <cmath>
#include <cstdio>
#include <optional>

#include "commands.h"
#include "terralod/render/contact_sheet.h"
#include "terralod/render/image.h"
#include "terralod/vegetation/directional_textures.h"
#include "terralod/vegetation/ldi_baker.h"
#include "terralod/vegetation/ldi_picture.h"
#include "terralod/vegetation/vegetation_file.h"
#include "terralod/vegetation/wang_tiling.h"
#include "vegetation_commands.h"

namespace terralod::cli {
namespace {

constexpr std::array<uint8_t, 3> kSoil = {92, 76, 58};

Image toImage(veg::LdiPicture p) {
  return Image{p.width, p.height, std::move(p.rgba)};
}

// Looks straight down on the tile and a quarter tile around it, the tile's outline drawn.
veg::LdiCamera topDownCamera(float tileSize, float tileHeight, uint32_t pixelsAcrossTile) {
  const float margin = 0.25f * tileSize, extent = tileSize + 2 * margin;
  veg::LdiCamera c;
  c.pixelSize = tileSize / float(pixelsAcrossTile);
  c.width = c.height = uint32_t(std::ceil(extent / c.pixelSize));
  c.origin = {-margin, -margin, 0};
  c.axisU = {1, 0, 0};
  c.axisV = {0, 1, 0};
  c.direction = {0, 0, -1};
  c.depthMin = -(tileHeight + 0.01f);
  c.depthMax = 0.01f;
  return c;
}

void drawOutline(Image& image, const veg::LdiCamera& c, float tileSize) {
  auto toPixel = [&](float metres) {
    return int(std::lround((metres - c.origin.x) / c.pixelSize));
  };
  const int lo = toPixel(0), hi = toPixel(tileSize);
  auto put = [&](int x, int y) {
    if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
    uint8_t* p = &image.rgba[(size_t(image.height - 1 - y) * image.width + x) * 4];
    p[0] = p[1] = p[2] = 255;
  };
  for (int k = lo; k <= hi; ++k) put(k, lo), put(k, hi), put(lo, k), put(hi, k);
}

// One prototile's picture (RenderTileOptions::view).
Result<Image> renderTile(const veg::VegetationReader& r, const RenderTileOptions& o, int tile,
                         const veg::PlantLibrary& plants) {
  const veg::BakeSettings& s = r.header().settings;
  if (o.view == "ldi") {
    auto ldi = r.readLdi(tile, o.resolution, o.direction);
    if (!ldi) return ldi.error();
    return toImage(veg::compositeLdi(*ldi, kSoil));
  }
  // The plants are made again from the file's seed and placement, and ray cast.
  const std::vector<veg::PrototileContent> tiles(r.header().tiles.begin(), r.header().tiles.end());
  const veg::ContextScene scene(tiles, veg::contextAround(tile, s.seed), s.tileSize, plants);
  const veg::LdiCamera camera =
      topDownCamera(s.tileSize, s.tileHeight, s.resolutions[o.resolution]);
  veg::SamplingSettings sampling;
  sampling.centreTileOnly = false;
  uint64_t rays = 0;
  Image image =
      toImage(veg::compositeLdi(scene.bake(camera, sampling, veg::Lighting{}, rays), kSoil));
  drawOutline(image, camera, s.tileSize);
  return image;
}

// The directional textures (directional_textures.h) of one prototile: a row per elevation, a
// column per direction, each 4× enlarged over soil with the tile's outline.
Image textureSheet(const veg::DirectionalTextures& t, int tile) {
  constexpr int kScale = 4, kGap = 2;
  const int cell = t.size * kScale + kGap;
  Image image{cell * veg::kLdiDirections, cell * veg::kTextureElevationCount, {}};
  image.rgba.assign(size_t(image.width) * image.height * 4, 255);
  for (int e = 0; e < veg::kTextureElevationCount; ++e)
    for (int d = 0; d < veg::kLdiDirections; ++d) {
      const uint32_t* texels =
          &t.rgba[size_t(veg::DirectionalTextures::textureIndex(tile, d, e)) * t.size * t.size];
      for (int y = 0; y < t.size * kScale; ++y)
        for (int x = 0; x < t.size * kScale; ++x) {
          const uint32_t c = texels[(y / kScale) * t.size + x / kScale];
          const float a = float(c >> 24) / 255.0f;
          uint8_t* p = &image.rgba[(size_t(e * cell + y) * image.width + d * cell + x) * 4];
          for (int k = 0; k < 3; ++k)
            p[k] = uint8_t(std::lround(float(c >> (8 * k) & 0xff) + (1.0f - a) * kSoil[size_t(k)]));
        }
    }
  return image;
}

}  // namespace

int runVegetationRenderTile(const RenderTileOptions& o) {
  if (auto format = imageFormatFor(o.output); !format) return fail(format.error().message);
  auto opened = veg::VegetationReader::openPathOrUrl(o.input);
  if (!opened) return fail(opened.error().message);
  const veg::VegetationReader& r = **opened;
  // Pictures from above make the plants again from the file's seed; LDIs need none.
  const veg::PlantLibrary plants =
      o.view == "top" ? veg::PlantLibrary(r.header().settings.seed) : veg::PlantLibrary({});
  std::optional<veg::DirectionalTextures> textures;
  if (o.view == "textures") {
    auto made = veg::makeDirectionalTextures(r);
    if (!made) return fail(made.error().message);
    textures = std::move(made).value();
  }
  std::vector<Image> pictures;
  for (int tile = 0; tile < veg::kPrototiles; ++tile) {
    if (o.tile != "all" && o.tile != std::to_string(tile)) continue;
    if (textures) {
      pictures.push_back(textureSheet(*textures, tile));
      continue;
    }
    auto picture = renderTile(r, o, tile, plants);
    if (!picture) return fail(picture.error().message);
    pictures.push_back(std::move(*picture));
  }
  const Image image = pictures.size() == 1 ? std::move(pictures[0])
                                           : makeContactSheet(pictures, 4, pictures[0].width);
  if (Status written = writeImage(image, o.output); !written) return fail(written.error().message);
  std::printf("terralod: wrote %s (%dx%d)\n", o.output.c_str(), image.width, image.height);
  return 0;
}

}  // namespace terralod::cli
