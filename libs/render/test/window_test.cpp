// The windowed context (GLFW). These run when a display exists: ctest runs them once more
// under xvfb-run (test "render_window_under_xvfb"), and the plain run skips them.

#include "terralod/render/window.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <thread>

#include "terralod/render/gl_worker.h"

namespace terralod {
namespace {

bool haveDisplay() {
  return std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY");
}

TEST(Window, OpensAnOpenGl45CoreWindowAndShowsWhatIsDrawn) {
  if (!haveDisplay()) GTEST_SKIP() << "no display (ctest runs this again under xvfb-run)";
  auto window = Window::open("terralod test", 160, 120);
  ASSERT_TRUE(window.ok()) << window.error().message;
  const GlInfo& info = (*window)->info();
  EXPECT_TRUE(info.coreProfile);
  EXPECT_GE(info.major * 10 + info.minor, 45) << info.version;
  EXPECT_EQ(info.platform, "GLFW window");
  const auto [w, h] = (*window)->framebufferSize();
  EXPECT_EQ(w, 160);
  EXPECT_EQ(h, 120);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, w, h);
  glClearColor(0.2f, 0.4f, 0.6f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  uint8_t pixel[4] = {};
  glReadBuffer(GL_BACK);
  glReadPixels(80, 60, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, pixel);
  EXPECT_NEAR(pixel[0], 51, 1);
  EXPECT_NEAR(pixel[1], 102, 1);
  EXPECT_NEAR(pixel[2], 153, 1);
  (*window)->swapBuffers();
  EXPECT_FALSE((*window)->shouldClose());
}

TEST(Window, TwoWindowsAndBackAgain) {
  if (!haveDisplay()) GTEST_SKIP() << "no display";
  auto a = Window::open("a", 64, 48);
  ASSERT_TRUE(a.ok()) << a.error().message;
  auto b = Window::open("b", 64, 48);
  ASSERT_TRUE(b.ok()) << b.error().message;
  b->reset();
  ASSERT_TRUE((*a)->makeCurrent().ok());
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

TEST(Window, SharedContextOnAnotherThreadMakesWhatTheWindowUses) {
  if (!haveDisplay()) GTEST_SKIP() << "no display";
  auto window = Window::open("shared", 64, 48);
  ASSERT_TRUE(window.ok()) << window.error().message;
  auto shared = (*window)->createShared();
  ASSERT_TRUE(shared.ok()) << shared.error().message;
  auto worker = GlWorker::start(std::move(shared).value());
  ASSERT_TRUE(worker.ok()) << worker.error().message;
  GLuint buffer = 0;
  auto job = (*worker)->post([&] {
    const uint32_t value = 0xBEEFu;
    glCreateBuffers(1, &buffer);
    glNamedBufferStorage(buffer, sizeof value, &value, 0);
  });
  while (!job->done()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  uint32_t read = 0;
  glGetNamedBufferSubData(buffer, 0, sizeof read, &read);
  EXPECT_EQ(read, 0xBEEFu);
  glDeleteBuffers(1, &buffer);
  worker->reset();
}

}  // namespace
}  // namespace terralod
