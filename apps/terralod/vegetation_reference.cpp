#include "vegetation_reference.h"

#include <epoxy/gl.h>

#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

#include "terralod/core/parallel.h"
#include "terralod/measure/image_similarity.h"

namespace terralod::cli {
namespace {

// The truth's rays a pixel: enough that a pixel's share of plant is known to a sixteenth. With 4,
// one ray of four grazing a petal decided a pixel of outline either way: on the low flight the
// coverage error was 6.1 % with 4 and 5.7 % with 16, and its two sides (plant only drawn, only
// traced) went from 3.8 / 2.2 % to 2.6 / 2.5 % (docs/benchmarks.md).
constexpr uint32_t kRaysPerPixel = 16;

// A channel difference above this between a picture and the bare terrain is a plant there
// (the warp and the tracer both write 8-bit colours; haze and blending move a few steps).
constexpr int kPlantThreshold = 8;

// The depth of the bound framebuffer as distances along the view axis (row 0 at the top;
// +infinity where nothing is).
std::vector<float> boundViewDepth(int width, int height) {
  std::vector<float> depth(size_t(width) * size_t(height));
  glReadPixels(0, 0, width, height, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
  std::vector<float> out(depth.size());
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float d = depth[size_t(height - 1 - y) * width + size_t(x)];
      out[size_t(y) * width + size_t(x)] =
          d > 0.0f ? float(kNearPlane / double(d)) : std::numeric_limits<float>::infinity();
    }
  return out;
}

bool differs(const Image& a, const Image& b, size_t i) {
  for (size_t c = 0; c < 3; ++c)
    if (std::abs(int(a.rgba[4 * i + c]) - int(b.rgba[4 * i + c])) > kPlantThreshold) return true;
  return false;
}

Image sideBySide(std::initializer_list<const Image*> images) {
  Image out{0, (*images.begin())->height, {}};
  for (const Image* i : images) out.width += i->width;
  out.rgba.resize(size_t(out.width) * out.height * 4);
  int x0 = 0;
  for (const Image* i : images) {
    for (int y = 0; y < i->height; ++y)
      std::copy_n(&i->rgba[size_t(y) * i->width * 4], size_t(i->width) * 4,
                  &out.rgba[(size_t(y) * out.width + size_t(x0)) * 4]);
    x0 += i->width;
  }
  return out;
}

// Distance at which the reference stops tracing: where a tile is 2 pixels wide.
double referenceDistance(const veg::FieldLayout& layout, const View& view) {
  return layout.tileSize * view.pixelsPerRadian / 2.0;
}

}  // namespace

VegetationReference::VegetationReference(SceneVegetation& vegetation, TerrainScene& scene)
    : mVegetation(vegetation),
      mTracer(vegetation.painter->file().header(),
              veg::PlantLibrary(vegetation.painter->file().header().settings.seed)),
      mHeights(scene.tileset(), scene.tree(), vegetation.painter->layout().tileSize,
               uint64_t{64} << 20) {}

PictureLayer::Painter VegetationReference::painter() {
  return [this](const FrameContext& frame, const LayerPicture& picture) {
    return trace(frame, picture);
  };
}

PaintedRows VegetationReference::trace(const FrameContext& frame, const LayerPicture& picture) {
  const View& view = frame.view;
  const veg::FieldLayout& layout = mVegetation.painter->layout();
  const std::vector<float> terrain = boundViewDepth(picture.width, picture.height);
  const std::vector<veg::TileDraw> tiles = veg::tilesWithin(
      layout, view, mHeights, mVegetation.where, referenceDistance(layout, view), layout.tileSize);
  std::vector<veg::TracedTile> traced;
  traced.reserve(tiles.size());
  for (const veg::TileDraw& t : tiles) traced.push_back({t.placement, t.prototile});
  mTracer.setTiles(traced);
  veg::TraceOptions options;
  options.threads = hardwareThreads();
  options.raysPerPixel = kRaysPerPixel;
  const veg::TraceStats stats = mTracer.trace(
      view, terrain, {picture.width, picture.height, picture.rgba, picture.viewDepth}, options);
  return {stats.top, stats.bottom};
}

Status VegetationReference::measure(const View& view, TerrainScene& scene,
                                    const TerrainStyle& style, const SelectionOptions& selection,
                                    FrameRecord& record) {
  const int w = view.camera.width, h = view.camera.height;
  if (Status s = bindFramebufferOfSize(mTarget, w, h); !s) return s;
  PictureLayer& layer = *mVegetation.layer;
  // As the flight drew it.
  scene.drawChunks(view, scene.selected(), style, selection);
  const Image drawn = mTarget->readPixels();
  // Bare, and where the terrain is.
  layer.setEnabled(false);
  if (mVegetation.far) mVegetation.far->setEnabled(false);
  scene.drawChunks(view, scene.selected(), style, selection);
  const Image bare = mTarget->readPixels();
  const std::vector<float> terrain = boundViewDepth(w, h);
  // Traced (its own plants to the reference distance; no textures).
  layer.setEnabled(true);
  layer.setPainter(painter());
  scene.drawChunks(view, scene.selected(), style, selection);
  const Image traced = mTarget->readPixels();
  layer.setPainter(mVegetation.warpPainter);
  if (mVegetation.far) mVegetation.far->setEnabled(true);

  // Counted: pixels where either shows a plant, and terrain within the reference distance.
  const double limit = referenceDistance(mVegetation.painter->layout(), view);
  std::vector<uint8_t> mask(size_t(w) * size_t(h), 0);
  size_t counted = 0, mismatched = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + size_t(x);
      const bool plantDrawn = differs(drawn, bare, i), plantTraced = differs(traced, bare, i);
      // Metres along the ray to the terrain from its distance along the view axis.
      const double sx = (x + 0.5) / w * 2 - 1, sy = 1 - (y + 0.5) / h * 2;
      const double stretch =
          std::sqrt(1 + std::pow(sx * view.tanHalfWidth, 2) + std::pow(sy * view.tanHalfHeight, 2));
      // Terrain within the distance the tracer covers counts, and plants against the sky;
      // beyond it the tracer draws nothing to compare with.
      const bool ground = std::isfinite(terrain[i]);
      const bool near = ground && terrain[i] * stretch <= limit;
      if (!(near || (!ground && (plantDrawn || plantTraced)))) continue;
      mask[i] = 1;
      ++counted;
      mismatched += plantDrawn != plantTraced;
    }
  record.vegetationSsim = structuralSimilarity(drawn, traced, mask).mean;
  if (mKeepPictures) {
    // Drawn | traced | where they differ (red: a plant only drawn, blue: only traced, light:
    // both, dark: neither, black: not counted).
    Image where = bare;
    for (size_t i = 0; i < mask.size(); ++i) {
      const bool d = differs(drawn, bare, i), t = differs(traced, bare, i);
      const uint8_t grey = !mask[i] ? 0 : (d && t) ? 200 : 100;
      uint8_t* q = &where.rgba[4 * i];
      q[0] = d && !t && mask[i] ? 255 : grey;
      q[1] = d != t && mask[i] ? 0 : grey;
      q[2] = t && !d && mask[i] ? 255 : grey;
    }
    mPictures.push_back(sideBySide({&drawn, &traced, &where}));
  }
  record.vegetationCoverageError = counted ? double(mismatched) / double(counted) : 0.0;
  return {};
}

Status VegetationReference::writePictures(const std::string& dir) const {
  for (size_t k = 0; k < mPictures.size(); ++k) {
    const std::string path =
        (std::filesystem::path(dir) / ("vegetation_reference_" + std::to_string(k) + ".png"))
            .string();
    if (Status s = writePng(mPictures[k], path); !s) return s;
  }
  return {};
}

}  // namespace terralod::cli
