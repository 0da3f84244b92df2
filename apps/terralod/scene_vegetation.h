#pragma once
// `--vegetation V.tlv [--vegetation-where RULES]` for render, bench and the viewer: a
// vegetation painter over the scene's tileset and the render layer that composites its
// pictures over the terrain.

#include <memory>
#include <optional>

#include "render_options.h"
#include "terralod/core/result.h"
#include "terralod/render/framebuffer.h"
#include "terralod/render/picture_layer.h"
#include "terralod/render/terrain_scene.h"
#include "terralod/vegetation/far_vegetation_layer.h"
#include "terralod/vegetation/vegetation_painter.h"

namespace terralod::cli {

struct SceneVegetation {
  std::unique_ptr<veg::VegetationPainter> painter;  ///< none without --vegetation
  PictureLayer* layer = nullptr;                    ///< owned by the scene's renderer
  veg::FarVegetationLayer* far = nullptr;  ///< the directional textures (none if switched off)
  PictureLayer::Painter warpPainter;       ///< the layer's painter: the LDI warp
  veg::VegetationWhere where;              ///< --vegetation-where
};

/// The frame's pop from the vegetation's choices of LDIs alone (FrameRecord::vegetationPop):
/// `view` drawn from the scene's resident chunks with the last frame's choices and with its
/// own, into `target`; NaN when no tile chose differently.
Result<double> vegetationPop(SceneVegetation& vegetation, TerrainScene& scene, const View& view,
                             const TerrainStyle& style, const SelectionOptions& selection,
                             std::optional<Framebuffer>& target);

/// Opens --vegetation and adds its layer to `scene` (which must outlive the result); nothing
/// without the option. Errors are one line naming the file or the option.
Result<SceneVegetation> addSceneVegetation(const RenderOptions& options, TerrainScene& scene);

}  // namespace terralod::cli
