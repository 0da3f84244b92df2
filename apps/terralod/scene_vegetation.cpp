#include "scene_vegetation.h"

#include <algorithm>
#include <cstdio>
#include <limits>

#include "terralod/core/parallel.h"
#include "terralod/core/progress.h"
#include "terralod/measure/texture_metrics.h"
#include "terralod/vegetation/tileset_materials.h"

namespace terralod::cli {
namespace {

// --vegetation-where's material names against the tileset's materials (its own, or
// --vegetation-materials').
Result<veg::MaterialMask> materialMask(const RenderOptions& options, const TilesetReader& tileset,
                                       const std::vector<std::string>& names) {
  TerminalProgress progress;
  auto map = veg::tilesetMaterials(
      tileset, {options.vegetationMaterials, options.vegetationPalette}, progress);
  if (!map) return map.error();
  const std::string source =
      options.vegetationMaterials.empty() ? tileset.name() : options.vegetationMaterials;
  return veg::MaterialMask::from(*map, tileset.header().spacingX, tileset.header().spacingY, names,
                                 source);
}

}  // namespace

Result<SceneVegetation> addSceneVegetation(const RenderOptions& options, TerrainScene& scene) {
  SceneVegetation out;
  if (options.vegetation.empty()) {
    for (const auto& [given, name] : {std::pair{&options.vegetationWhere, "--vegetation-where"},
                                      {&options.vegetationMaterials, "--vegetation-materials"},
                                      {&options.vegetationPalette, "--vegetation-palette"}})
      if (!given->empty()) return Error{std::string(name) + " needs --vegetation V.tlv"};
    for (const auto& [given, name] :
         {std::pair{options.vegetationRange, "--vegetation-range"},
          {options.vegetationOversampling, "--vegetation-oversampling"}})
      if (given > 0) return Error{std::string(name) + " needs --vegetation V.tlv"};
    return out;
  }
  veg::VegetationOptions o;
  if (!options.vegetationWhere.empty()) {
    auto where = veg::parseVegetationWhere(options.vegetationWhere);
    if (!where) return where.error();
    o.field.where = *where;
  }
  if (o.field.where.materials.empty() && !options.vegetationMaterials.empty())
    return Error{"--vegetation-materials: no material=... in --vegetation-where to use it for"};
  if (options.vegetationMaterials.empty() && !options.vegetationPalette.empty())
    return Error{"--vegetation-palette needs --vegetation-materials RASTER"};
  if (!o.field.where.materials.empty()) {
    auto mask = materialMask(options, scene.tileset(), o.field.where.materials);
    if (!mask) return mask.error();
    o.field.where.materialMask = std::make_shared<const veg::MaterialMask>(std::move(mask).value());
  }
  o.warp.threads = std::min(hardwareThreads(), 16u);
  o.field.blend = !options.noVegetationBlend;
  if (options.vegetationRange > 0) o.field.range = options.vegetationRange;
  if (options.vegetationOversampling > 0)
    o.field.pixelsPerScreenPixel = options.vegetationOversampling;
  const double budget = options.cacheMB * vegetationBudgetShare(options) * 1024.0 * 1024.0;
  o.heightBudgetBytes = uint64_t(budget / 16);
  o.ldiBudgetBytes = uint64_t(budget) - o.heightBudgetBytes;
  o.log = [](const std::string& line) {
    std::fprintf(stderr, "terralod: warning: %s\n", line.c_str());
  };
  auto painter = veg::VegetationPainter::open(options.vegetation, scene.tileset(), scene.tree(), o);
  if (!painter) return painter.error();
  out.painter = std::move(painter).value();
  veg::VegetationPainter* p = out.painter.get();
  if (!options.noVegetationTextures) {
    // Beyond the LDI range: drawn first, on the ground under the LDI tiles.
    auto textures = veg::makeDirectionalTextures(p->file());
    if (!textures) return textures.error();
    auto far = veg::FarVegetationLayer::create(*textures, p->layout(), o.field);
    if (!far) return far.error();
    out.far =
        static_cast<veg::FarVegetationLayer*>(&scene.renderer().addLayer(std::move(far).value()));
  }
  out.where = o.field.where;
  out.warpPainter = [p](const FrameContext& frame, const LayerPicture& picture) {
    p->paint(frame.view, {picture.width, picture.height, picture.rgba, picture.viewDepth});
    const veg::FrameWarpStats& w = p->lastFrame().warp;
    return PaintedRows{w.top, w.bottom};
  };
  auto layer = PictureLayer::create(out.warpPainter);
  if (!layer) return layer.error();
  out.layer = static_cast<PictureLayer*>(&scene.renderer().addLayer(std::move(layer).value()));
  out.layer->setDepthTest(!options.noVegetationDepth);
  return out;
}

Result<double> vegetationPop(SceneVegetation& vegetation, TerrainScene& scene, const View& view,
                             const TerrainStyle& style, const SelectionOptions& selection,
                             std::optional<Framebuffer>& target) {
  veg::VegetationPainter& painter = *vegetation.painter;
  if (!painter.choicesChanged()) return std::numeric_limits<double>::quiet_NaN();
  if (Status s = bindFramebufferOfSize(target, view.camera.width, view.camera.height); !s)
    return s.error();
  painter.setMode(veg::PaintMode::kPreviousChoices);
  scene.drawChunks(view, scene.selected(), style, selection);
  const Image before = target->readPixels();
  painter.setMode(veg::PaintMode::kRepaint);
  scene.drawChunks(view, scene.selected(), style, selection);
  const Image now = target->readPixels();
  painter.setMode(veg::PaintMode::kFrame);
  return meanAbsoluteDifference(before, now);
}

}  // namespace terralod::cli
