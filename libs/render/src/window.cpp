#include "terralod/render/window.h"

#include <GLFW/glfw3.h>

#include <mutex>

#include "current_gl_info.h"

namespace terralod {
namespace {

// GLFW is process-wide: initialised with the first window, terminated with the last.
std::mutex gGlfwMutex;
int gWindows = 0;
std::string gLastGlfwError;

void recordGlfwError(int, const char* description) {
  gLastGlfwError = description;
}

}  // namespace

Result<std::unique_ptr<Window>> Window::open(const std::string& title, int width, int height) {
  auto window = openWindow(title, width, height, nullptr, true);
  if (!window) return window.error();
  glfwMakeContextCurrent((*window)->mWindow);
  (*window)->mInfo = readCurrentGlInfo("GLFW window");
  if (Status ok = requireGl45Core((*window)->mInfo); !ok) return ok.error();
  installDebugOutput();
  return window;
}

Result<std::unique_ptr<GlContext>> Window::createShared() {
  auto shared = openWindow("terralod worker", 1, 1, mWindow, false);
  if (!shared) return shared.error();
  (*shared)->mInfo = mInfo;
  return std::unique_ptr<GlContext>(std::move(shared).value());
}

Result<std::unique_ptr<Window>> Window::openWindow(const std::string& title, int width, int height,
                                                   GLFWwindow* share, bool visible) {
  std::lock_guard lock(gGlfwMutex);
  glfwSetErrorCallback(recordGlfwError);
  if (gWindows == 0 && !glfwInit()) return Error{"no window system available: " + gLastGlfwError};
  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
  GLFWwindow* handle = glfwCreateWindow(width, height, title.c_str(), nullptr, share);
  if (!handle) {
    if (gWindows == 0) glfwTerminate();
    return Error{"cannot open an OpenGL 4.5 core window: " + gLastGlfwError};
  }
  ++gWindows;
  return std::unique_ptr<Window>(new Window(handle));
}

Window::~Window() {
  std::lock_guard lock(gGlfwMutex);
  glfwDestroyWindow(mWindow);
  if (--gWindows == 0) glfwTerminate();
}

Status Window::makeCurrent() {
  glfwMakeContextCurrent(mWindow);
  return {};
}

void Window::releaseCurrent() {
  if (glfwGetCurrentContext() == mWindow) glfwMakeContextCurrent(nullptr);
}

void Window::swapBuffers() {
  glfwSwapBuffers(mWindow);
}

bool Window::shouldClose() const {
  return glfwWindowShouldClose(mWindow) != 0;
}

std::array<int, 2> Window::framebufferSize() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(mWindow, &w, &h);
  return {w, h};
}

}  // namespace terralod
