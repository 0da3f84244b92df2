#pragma once
// An OpenGL 4.5 core context: the one seam every way of getting GL goes through. Headless EGL
// serves tests, the CLI's render command and servers; a GLFW window (later) serves the viewer.
// Every GL call in libs/render assumes a GlContext is current on the calling thread.

#include <memory>
#include <string>

#include "terralod/core/result.h"

namespace terralod {

/// Which EGL platform createHeadless() may use. kAny tries the device platform
/// (EGL_EXT_platform_device: GPUs and Mesa's software device) and then Mesa's surfaceless
/// platform; the others try only one, so a test can exercise each path.
enum class HeadlessPlatform { kAny, kDevice, kSurfaceless };

/// What a context turned out to be, read from the context itself once it was current.
struct GlInfo {
  std::string platform;  ///< how it was created, e.g. "EGL device platform"
  std::string renderer;  ///< GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string version;   ///< GL_VERSION, e.g. "4.5 (Core Profile) Mesa 22.3.6"
  int major = 0;         ///< GL_MAJOR_VERSION
  int minor = 0;         ///< GL_MINOR_VERSION
  bool coreProfile = false;
};

/// Owns an OpenGL 4.5 core context (and whatever display or window it needs). GL objects
/// created while it is current belong to it: destroy them before the context.
/// A context is current on at most one thread at a time; that thread makes every GL call.
class GlContext {
 public:
  /// Creates a window-less context with EGL (device platform first, then surfaceless; no
  /// surface at all, rendering goes to Framebuffers) and makes it current on the calling
  /// thread. Fails with one line naming every platform tried and why it was unusable.
  static Result<std::unique_ptr<GlContext>> createHeadless(
      HeadlessPlatform platform = HeadlessPlatform::kAny);

  /// Releases the context and its display or window. Call it on the thread where the context
  /// is current, or after releaseCurrent(); the context's GL objects die with it.
  virtual ~GlContext() = default;
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  /// Makes this context current on the calling thread. It must not be current on another one.
  virtual Status makeCurrent() = 0;
  /// Detaches this context from the calling thread (if current there) so another may take it.
  virtual void releaseCurrent() = 0;
  /// What this context is; fixed at creation, callable from any thread.
  virtual const GlInfo& info() const = 0;
  /// A second context sharing this one's objects (buffers, textures), current nowhere, for a
  /// worker thread (GlWorker). Call it where this context was created (GLFW: the main thread).
  virtual Result<std::unique_ptr<GlContext>> createShared() = 0;

  /// One line for logs and bug reports: "<platform>, <renderer>, OpenGL <version>".
  std::string description() const;

 protected:
  GlContext() = default;
};

}  // namespace terralod
