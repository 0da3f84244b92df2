#pragma once
// The headless GlContext: EGL with no surface, on the device platform or Mesa's surfaceless
// platform. Private to libs/render; callers go through GlContext::createHeadless().

#include <epoxy/egl.h>

#include <memory>

#include "terralod/render/gl_context.h"

namespace terralod {

/// An EGL context made current with EGL_NO_SURFACE (EGL_KHR_surfaceless_context). Owns the
/// context and one reference to its display; the display is terminated with its last context.
class EglHeadlessContext final : public GlContext {
 public:
  /// Tries the platforms `platform` allows, in order, and returns the first context that is
  /// OpenGL 4.5 core, current on the calling thread.
  static Result<std::unique_ptr<GlContext>> create(HeadlessPlatform platform);

  ~EglHeadlessContext() override;
  Status makeCurrent() override;
  void releaseCurrent() override;
  const GlInfo& info() const override { return mInfo; }
  Result<std::unique_ptr<GlContext>> createShared() override;

 private:
  EglHeadlessContext(EGLDisplay display, EGLConfig config, EGLContext context) noexcept
      : mDisplay(display), mConfig(config), mContext(context) {}
  // Initialises `display`, creates a context on it and makes it current; `platform` names
  // the display in GlInfo and in errors.
  static Result<std::unique_ptr<GlContext>> open(EGLDisplay display, const std::string& platform);

  EGLDisplay mDisplay;
  EGLConfig mConfig;
  EGLContext mContext;
  GlInfo mInfo;
};

}  // namespace terralod
