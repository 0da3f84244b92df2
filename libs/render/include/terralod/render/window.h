#pragma once
// An on-screen OpenGL 4.5 core context: a GLFW window, for the interactive viewer. The same
// GlContext seam as the headless one, so everything that renders works in both.

#include <array>
#include <memory>
#include <string>

#include "terralod/render/gl_context.h"

struct GLFWwindow;

namespace terralod {

/// Owns a GLFW window and its OpenGL 4.5 core context. GLFW is initialised with the first
/// window and terminated with the last. Main thread only (GLFW's rule for windows and events);
/// the context may still be made current on another thread.
class Window final : public GlContext {
 public:
  /// Opens a width x height window titled `title` and makes its context current. Fails with
  /// one line when there is no display (e.g. no X server) or no OpenGL 4.5 core.
  static Result<std::unique_ptr<Window>> open(const std::string& title, int width, int height);

  ~Window() override;
  Status makeCurrent() override;
  void releaseCurrent() override;
  const GlInfo& info() const override { return mInfo; }
  /// A hidden 1x1 window whose context shares this one's objects.
  Result<std::unique_ptr<GlContext>> createShared() override;

  /// Shows what was drawn into the default framebuffer.
  void swapBuffers();
  /// True once the user asked to close it.
  bool shouldClose() const;
  /// The default framebuffer's size in pixels (may differ from the window's on high-DPI).
  std::array<int, 2> framebufferSize() const;
  /// For input handling (GLFW callbacks, key and cursor state).
  GLFWwindow* handle() const { return mWindow; }

 private:
  explicit Window(GLFWwindow* window) : mWindow(window) {}
  // Opens a window (hidden unless `visible`) whose context shares `share`'s (or none).
  static Result<std::unique_ptr<Window>> openWindow(const std::string& title, int width, int height,
                                                    GLFWwindow* share, bool visible);

  GLFWwindow* mWindow;
  GlInfo mInfo;
};

}  // namespace terralod
