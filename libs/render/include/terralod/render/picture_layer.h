#pragma once
// A composited layer painted on the CPU every frame: colour with alpha and a depth per pixel
// (a software renderer's output, such as the vegetation's LDI warper), uploaded and
// z-composited over the opaque terrain: each pixel is kept where its depth is nearer than the
// terrain's and blended `over` what is there. Render thread only.

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/render/composited_layer.h"
#include "terralod/render/frame_context.h"
#include "terralod/runtime/view.h"

namespace terralod {

/// What a painter fills: premultiplied RGBA8 (red in the low byte) and each pixel's distance
/// along the view axis in metres (+infinity or 0 alpha: nothing), row 0 at the top.
struct LayerPicture {
  int width = 0, height = 0;
  std::span<uint32_t> rgba;
  std::span<float> viewDepth;
};

/// The rows [top, bottom) a painter wrote; the picture holds nothing outside them.
struct PaintedRows {
  int top = 0, bottom = 0;
};

struct PictureLayerTimes {
  double paintMs = 0;      ///< the painter
  double compositeMs = 0;  ///< upload and the compositing draw, to glFinish
  int rows = 0;            ///< picture rows uploaded and composited
};

class PictureLayer final : public CompositedLayer {
 public:
  /// Paints the frame's picture; the terrain is drawn (frame.depth holds its depth when
  /// readable).
  using Painter =
      std::function<PaintedRows(const FrameContext& frame, const LayerPicture& picture)>;
  /// Compiles the compositing shader.
  static Result<std::unique_ptr<PictureLayer>> create(Painter painter);
  ~PictureLayer() override;

  uint32_t draw(const FrameContext& frame) override;
  /// The last frame's.
  const PictureLayerTimes& times() const { return mTimes; }
  /// Switches the layer off (draws nothing, paints nothing) or on again.
  void setEnabled(bool enabled) { mEnabled = enabled; }
  /// Paints with another painter from the next frame on.
  void setPainter(Painter painter) { mPainter = std::move(painter); }
  /// Off: the picture goes over the terrain wherever it has something, nearer or not (shows
  /// what the depth composite hides).
  void setDepthTest(bool on) { mDepthTest = on; }

 private:
  struct Gl;
  PictureLayer(Painter painter, std::unique_ptr<Gl> gl);
  Painter mPainter;
  std::unique_ptr<Gl> mGl;
  std::vector<uint32_t> mRgba;
  std::vector<float> mDepth;
  PictureLayerTimes mTimes;
  bool mEnabled = true;
  bool mDepthTest = true;
};

}  // namespace terralod
