#pragma once
// An offscreen render target, so rendering needs no window: headless tests, `terralod render`
// and golden images all draw into one of these and read it back.

#include <cstdint>
#include <optional>

#include "terralod/core/result.h"
#include "terralod/render/depth_texture.h"
#include "terralod/render/image.h"

namespace terralod {

/// RGBA8 colour plus 32-bit float depth, the depth always in a texture later passes can read
/// (depth()). With samples > 0 drawing goes to multisampled buffers and resolve() (or readPixels())
/// averages them into the single-sample colour texture. Owns its GL objects: create, use and
/// destroy it on the thread where its GlContext is current, and destroy it before that context.
/// Movable, not copyable.
class Framebuffer {
 public:
  /// Creates a width x height target with `samples` samples per pixel (0: no multisampling).
  /// Fails, naming the size, when it is empty, larger than the GL limits or incomplete.
  static Result<Framebuffer> create(int width, int height, int samples = 0);

  ~Framebuffer();
  Framebuffer(Framebuffer&& other) noexcept;
  Framebuffer& operator=(Framebuffer&& other) noexcept;
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;

  /// Binds it as GL_FRAMEBUFFER and sets the viewport to cover it.
  void bind() const;
  /// Brings the single-sample colour texture up to date after multisampled drawing.
  /// Does nothing without multisampling. Leaves the framebuffer bindings untouched.
  void resolve() const;
  /// Resolves, then copies the colour buffer into an Image (top row first). Waits for the GPU.
  Image readPixels() const;

  int width() const { return mWidth; }
  int height() const { return mHeight; }
  int samples() const { return mSamples; }
  /// The framebuffer to draw into (GL name).
  uint32_t framebufferId() const { return mDrawFramebuffer; }
  /// The single-sample RGBA8 colour texture (GL name), valid for sampling after resolve().
  uint32_t colorTexture() const { return mColorTexture; }
  /// The depth texture drawing writes (multisampled like the colour when samples() > 0).
  DepthTexture depth() const { return {mDepthTexture, mSamples}; }

 private:
  Framebuffer() = default;
  void release();

  int mWidth = 0;
  int mHeight = 0;
  int mSamples = 0;
  uint32_t mDrawFramebuffer = 0;     // what bind() binds: multisampled when mSamples > 0
  uint32_t mResolveFramebuffer = 0;  // wraps mColorTexture; 0 without multisampling
  uint32_t mColorTexture = 0;
  uint32_t mDepthTexture = 0;      // multisampled when mSamples > 0
  uint32_t mMultisampleColor = 0;  // a renderbuffer, only with multisampling
};

/// Makes `target` a width x height single-sample Framebuffer, creating it when it is empty or
/// of another size (as a flight's frames may ask), and binds it.
Status bindFramebufferOfSize(std::optional<Framebuffer>& target, int width, int height);

}  // namespace terralod
