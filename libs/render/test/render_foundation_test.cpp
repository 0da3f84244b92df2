// The render foundation on whatever GL the machine has (Mesa llvmpipe in CI): headless
// contexts, offscreen framebuffers and their readback orientation, shaders and their errors,
// PNG files, a golden image, and multi-draw-indirect with gl_DrawIDARB, which the terrain
// renderer is to use for drawing many chunks per call.

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

#include "image_compare.h"
#include "temp_dir.h"
#include "terralod/render/framebuffer.h"
#include "terralod/render/gl_context.h"
#include "terralod/render/image.h"
#include "terralod/render/shader_program.h"

namespace terralod {
namespace {

using Rgba = std::array<uint8_t, 4>;

// Clear colours are whole multiples of 1/255 so they survive the trip to RGBA8 exactly.
constexpr float kClear[4] = {32 / 255.0f, 48 / 255.0f, 64 / 255.0f, 1.0f};
constexpr Rgba kClearBytes = {32, 48, 64, 255};
constexpr int kSceneSize = 128;

// GL names owned by a test; deleted while the fixture's context is still current.
struct GlBuffer {
  GLuint id = 0;
  GlBuffer() { glCreateBuffers(1, &id); }
  ~GlBuffer() { glDeleteBuffers(1, &id); }
};
struct GlVertexArray {
  GLuint id = 0;
  GlVertexArray() { glCreateVertexArrays(1, &id); }
  ~GlVertexArray() { glDeleteVertexArrays(1, &id); }
};

constexpr const char* kColorVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 color;
out vec3 vColor;
void main() {
  vColor = color;
  gl_Position = vec4(position, 1.0);
}
)";
constexpr const char* kColorFragmentShader = R"(#version 450 core
in vec3 vColor;
layout(location = 0) out vec4 fragColor;
void main() { fragColor = vec4(vColor, 1.0); }
)";

struct ColorVertex {
  float position[3];
  float color[3];
};

// Draws triangles of ColorVertex with the colour shader into whatever framebuffer is bound.
void drawColorTriangles(const std::vector<ColorVertex>& vertices) {
  auto program = ShaderProgram::create("colour", {kColorVertexShader, kColorFragmentShader, {}});
  ASSERT_TRUE(program.ok()) << program.error().message;
  GlBuffer vertexBuffer;
  glNamedBufferStorage(vertexBuffer.id, GLsizeiptr(vertices.size() * sizeof(ColorVertex)),
                       vertices.data(), 0);
  GlVertexArray vertexArray;
  glVertexArrayVertexBuffer(vertexArray.id, 0, vertexBuffer.id, 0, sizeof(ColorVertex));
  glEnableVertexArrayAttrib(vertexArray.id, 0);
  glVertexArrayAttribFormat(vertexArray.id, 0, 3, GL_FLOAT, GL_FALSE,
                            offsetof(ColorVertex, position));
  glVertexArrayAttribBinding(vertexArray.id, 0, 0);
  glEnableVertexArrayAttrib(vertexArray.id, 1);
  glVertexArrayAttribFormat(vertexArray.id, 1, 3, GL_FLOAT, GL_FALSE, offsetof(ColorVertex, color));
  glVertexArrayAttribBinding(vertexArray.id, 1, 0);
  program->use();
  glBindVertexArray(vertexArray.id);
  glDrawArrays(GL_TRIANGLES, 0, GLsizei(vertices.size()));
  glBindVertexArray(0);
  glUseProgram(0);
}

// The foundation scene: a triangle in the upper half of NDC with a red bottom-left, green
// bottom-right and blue apex near the top, on kClear. Spans rows 7..57 of 128 (top first).
Image renderTriangleScene(int samples) {
  auto target = Framebuffer::create(kSceneSize, kSceneSize, samples);
  EXPECT_TRUE(target.ok()) << target.error().message;
  if (!target) return {};
  target->bind();
  glClearNamedFramebufferfv(target->framebufferId(), GL_COLOR, 0, kClear);
  drawColorTriangles({{{-0.5f, 0.1f, 0.0f}, {1, 0, 0}},
                      {{0.5f, 0.1f, 0.0f}, {0, 1, 0}},
                      {{0.0f, 0.9f, 0.0f}, {0, 0, 1}}});
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return target->readPixels();
}

// Which channel of R, G, B is largest.
int dominantChannel(const Rgba& p) {
  if (p[0] > p[1] && p[0] > p[2]) return 0;
  return p[1] > p[2] ? 1 : 2;
}

class RenderFoundation : public ::testing::Test {
 protected:
  void SetUp() override {
    auto context = GlContext::createHeadless();
    ASSERT_TRUE(context.ok()) << context.error().message;
    mContext = std::move(context.value());
  }
  std::unique_ptr<GlContext> mContext;
};

TEST_F(RenderFoundation, CreatesOpenGl45CoreContext) {
  const GlInfo& info = mContext->info();
  EXPECT_TRUE(info.major > 4 || (info.major == 4 && info.minor >= 5))
      << info.major << "." << info.minor;
  EXPECT_TRUE(info.coreProfile);
  EXPECT_FALSE(info.renderer.empty());
  EXPECT_EQ(mContext->description().rfind(info.platform + ", ", 0), 0u);
  std::printf("context: %s\n", mContext->description().c_str());
  RecordProperty("context", mContext->description());
  // The context is current: GL answers.
  GLint maxTexture = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexture);
  EXPECT_GE(maxTexture, 1024);
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

// Each platform on its own, so a broken fallback cannot hide behind a working first choice.
// A platform the EGL does not offer (NVIDIA has no Mesa surfaceless) is skipped, not failed.
TEST(RenderFoundationPlatforms, EachEglPlatformGivesACoreContext) {
  int offered = 0;
  for (HeadlessPlatform platform : {HeadlessPlatform::kDevice, HeadlessPlatform::kSurfaceless}) {
    auto context = GlContext::createHeadless(platform);
    if (!context && context.error().message.find("not supported by this EGL") != std::string::npos)
      continue;
    ++offered;
    ASSERT_TRUE(context.ok()) << context.error().message;
    std::printf("context: %s\n", (*context)->description().c_str());
    EXPECT_TRUE((*context)->info().coreProfile);
    auto target = Framebuffer::create(4, 4);
    ASSERT_TRUE(target.ok()) << target.error().message;
    glClearNamedFramebufferfv(target->framebufferId(), GL_COLOR, 0, kClear);
    EXPECT_EQ(target->readPixels().pixel(3, 3), kClearBytes);
  }
  EXPECT_GT(offered, 0) << "this EGL offers neither the device nor the surfaceless platform";
}

// Contexts on one EGL display share it; closing one must not terminate it under the other.
TEST_F(RenderFoundation, SecondContextOnSameDisplayCanCloseFirst) {
  {
    auto second = GlContext::createHeadless();
    ASSERT_TRUE(second.ok()) << second.error().message;
  }
  ASSERT_TRUE(mContext->makeCurrent().ok());
  auto target = Framebuffer::create(8, 8);
  ASSERT_TRUE(target.ok()) << target.error().message;
  glClearNamedFramebufferfv(target->framebufferId(), GL_COLOR, 0, kClear);
  EXPECT_EQ(target->readPixels().pixel(0, 0), kClearBytes);
}

// A context moves between threads with releaseCurrent() and makeCurrent().
TEST_F(RenderFoundation, ContextMovesToAnotherThread) {
  mContext->releaseCurrent();
  Rgba seen{};
  std::string failure;
  std::thread renderThread([&] {
    if (Status s = mContext->makeCurrent(); !s) {
      failure = s.error().message;
      return;
    }
    {
      auto target = Framebuffer::create(8, 8);
      if (!target) {
        failure = target.error().message;
      } else {
        glClearNamedFramebufferfv(target->framebufferId(), GL_COLOR, 0, kClear);
        seen = target->readPixels().pixel(7, 0);
      }
    }
    mContext->releaseCurrent();
  });
  renderThread.join();
  EXPECT_EQ(failure, "");
  EXPECT_EQ(seen, kClearBytes);
  EXPECT_TRUE(mContext->makeCurrent().ok());
}

TEST_F(RenderFoundation, ClearReadsBackExactly) {
  auto target = Framebuffer::create(64, 48);
  ASSERT_TRUE(target.ok()) << target.error().message;
  target->bind();
  glClearColor(kClear[0], kClear[1], kClear[2], kClear[3]);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  const Image image = target->readPixels();
  ASSERT_EQ(image.width, 64);
  ASSERT_EQ(image.height, 48);
  ASSERT_EQ(image.rgba.size(), size_t(64 * 48 * 4));
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      ASSERT_EQ(image.pixel(x, y), kClearBytes) << x << "," << y;
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

TEST_F(RenderFoundation, RejectsImpossibleFramebuffers) {
  auto empty = Framebuffer::create(0, 48);
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.error().message.find("framebuffer 0x48"), std::string::npos)
      << empty.error().message;
  auto huge = Framebuffer::create(1 << 20, 16);
  EXPECT_FALSE(huge.ok());
  auto tooManySamples = Framebuffer::create(16, 16, 1 << 10);
  ASSERT_FALSE(tooManySamples.ok());
  EXPECT_NE(tooManySamples.error().message.find("samples"), std::string::npos);
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

TEST_F(RenderFoundation, TriangleLandsInUpperRowsTopRowFirst) {
  const Image image = renderTriangleScene(0);
  ASSERT_EQ(image.width, kSceneSize);
  // Inside: every corner's colour dominates near it, and the apex (top of NDC) is near row 0.
  EXPECT_EQ(dominantChannel(image.pixel(64, 9)), 2) << "blue apex near the top rows";
  EXPECT_EQ(dominantChannel(image.pixel(35, 56)), 0) << "red corner at the bottom left";
  EXPECT_EQ(dominantChannel(image.pixel(92, 56)), 1) << "green corner at the bottom right";
  for (const auto& [x, y] : {std::pair{64, 9}, {64, 40}, {35, 56}, {92, 56}}) {
    EXPECT_NE(image.pixel(x, y), kClearBytes) << x << "," << y;
    EXPECT_EQ(image.pixel(x, y)[3], 255);
  }
  // Outside: beside the triangle, above the apex, and the whole lower half.
  for (const auto& [x, y] : {std::pair{10, 30}, {120, 30}, {64, 2}, {20, 56}})
    EXPECT_EQ(image.pixel(x, y), kClearBytes) << x << "," << y;
  for (int y = 60; y < kSceneSize; ++y)
    for (int x = 0; x < kSceneSize; ++x) ASSERT_EQ(image.pixel(x, y), kClearBytes) << x << "," << y;
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

TEST_F(RenderFoundation, TriangleMatchesGoldenImage) {
  const Image image = renderTriangleScene(0);
  const test::ImageComparison comparison = test::compareWithGolden(image, "foundation_triangle");
  EXPECT_TRUE(comparison.matches) << comparison.message;
}

TEST_F(RenderFoundation, MultisampledTriangleResolvesOnReadback) {
  const Image single = renderTriangleScene(0);
  const Image multi = renderTriangleScene(4);
  ASSERT_EQ(multi.width, kSceneSize);
  // Interiors agree; edges get partial coverage, so some pixels differ, but only near edges.
  const test::ImageComparison comparison = test::compareImages(multi, single, {1, 0.05});
  EXPECT_TRUE(comparison.matches) << comparison.message;
  EXPECT_GT(comparison.differingFraction, 0.0) << "no antialiased edge pixels";
  EXPECT_LE(std::abs(int(multi.pixel(64, 40)[0]) - int(single.pixel(64, 40)[0])), 1);
  EXPECT_EQ(multi.pixel(64, 100), kClearBytes);
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

TEST_F(RenderFoundation, DepthAttachmentHidesFartherTriangle) {
  auto target = Framebuffer::create(32, 32);
  ASSERT_TRUE(target.ok()) << target.error().message;
  target->bind();
  glClearNamedFramebufferfv(target->framebufferId(), GL_COLOR, 0, kClear);
  const float farthest = 1.0f;
  glClearNamedFramebufferfv(target->framebufferId(), GL_DEPTH, 0, &farthest);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  // The near red triangle is drawn first; the far green one, covering it, must lose.
  auto coverAll = [](float z, float r, float g) {
    return std::vector<ColorVertex>{
        {{-1, -1, z}, {r, g, 0}}, {{3, -1, z}, {r, g, 0}}, {{-1, 3, z}, {r, g, 0}}};
  };
  drawColorTriangles(coverAll(-0.5f, 1, 0));
  drawColorTriangles(coverAll(0.5f, 0, 1));
  glDisable(GL_DEPTH_TEST);
  EXPECT_EQ(target->readPixels().pixel(16, 16), (Rgba{255, 0, 0, 255}));
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

TEST_F(RenderFoundation, ShaderSyntaxErrorReturnsInfoLog) {
  const std::string broken = "#version 450 core\nout vec4 c;\nvoid main() { c = vec4(1.0) }\n";
  auto program = ShaderProgram::create("broken", {kColorVertexShader, broken, {}});
  ASSERT_FALSE(program.ok());
  const std::string& message = program.error().message;
  std::printf("%s\n", message.c_str());
  EXPECT_EQ(message.rfind("broken: fragment shader does not compile:\n  ", 0), 0u) << message;
  // The driver's own words: a location in the source and "error".
  EXPECT_NE(message.find("error"), std::string::npos) << message;
  EXPECT_NE(message.find("0:3"), std::string::npos) << message;
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

TEST_F(RenderFoundation, ShaderLinkErrorReturnsInfoLog) {
  const std::string wantsMissingInput = R"(#version 450 core
in vec2 neverWritten;
out vec4 c;
void main() { c = vec4(neverWritten, 0.0, 1.0); }
)";
  const std::string writesNothing = "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n";
  auto program = ShaderProgram::create("mismatch", {writesNothing, wantsMissingInput, {}});
  ASSERT_FALSE(program.ok());
  std::printf("%s\n", program.error().message.c_str());
  EXPECT_EQ(program.error().message.rfind("mismatch: program does not link:", 0), 0u)
      << program.error().message;
  EXPECT_NE(program.error().message.find("neverWritten"), std::string::npos)
      << program.error().message;
}

TEST_F(RenderFoundation, GeometryStageLinks) {
  const std::string passThrough = R"(#version 450 core
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
in vec3 vColor[];
out vec3 gColor;
void main() {
  for (int i = 0; i < 3; ++i) {
    gColor = vColor[i];
    gl_Position = gl_in[i].gl_Position;
    EmitVertex();
  }
}
)";
  const std::string fragment = R"(#version 450 core
in vec3 gColor;
out vec4 c;
void main() { c = vec4(gColor, 1.0); }
)";
  auto program = ShaderProgram::create("geometry", {kColorVertexShader, fragment, passThrough});
  ASSERT_TRUE(program.ok()) << program.error().message;
  EXPECT_NE(program->id(), 0u);
}

// Three quads from one glMultiDrawElementsIndirect call; the commands are identical, so only
// gl_DrawIDARB can move each quad to its slot and give it its colour.
TEST_F(RenderFoundation, MultiDrawIndirectSeesDrawId) {
  ASSERT_TRUE(epoxy_has_gl_extension("GL_ARB_shader_draw_parameters"))
      << mContext->description() << " lacks GL_ARB_shader_draw_parameters";
  const std::string vertex = R"(#version 450 core
#extension GL_ARB_shader_draw_parameters : require
layout(location = 0) in vec2 corner;
flat out int drawId;
void main() {
  drawId = gl_DrawIDARB;
  gl_Position = vec4(corner.x + 0.7 * float(gl_DrawIDARB), corner.y, 0.0, 1.0);
}
)";
  const std::string fragment = R"(#version 450 core
flat in int drawId;
out vec4 c;
const vec3 kColors[3] = vec3[3](vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1));
void main() { c = vec4(kColors[drawId], 1.0); }
)";
  auto program = ShaderProgram::create("draw id", {vertex, fragment, {}});
  ASSERT_TRUE(program.ok()) << program.error().message;

  // One quad, x in [-0.9, -0.5], y in [-0.2, 0.2]; draws 1 and 2 shift it right by 0.7 each.
  const float corners[] = {-0.9f, -0.2f, -0.5f, -0.2f, -0.5f, 0.2f, -0.9f, 0.2f};
  const uint16_t indices[] = {0, 1, 2, 0, 2, 3};
  struct DrawElementsIndirectCommand {
    GLuint count, instanceCount, firstIndex;
    GLint baseVertex;
    GLuint baseInstance;
  };
  const DrawElementsIndirectCommand commands[3] = {
      {6, 1, 0, 0, 0}, {6, 1, 0, 0, 0}, {6, 1, 0, 0, 0}};
  GlBuffer vertexBuffer, indexBuffer, commandBuffer;
  glNamedBufferStorage(vertexBuffer.id, sizeof corners, corners, 0);
  glNamedBufferStorage(indexBuffer.id, sizeof indices, indices, 0);
  glNamedBufferStorage(commandBuffer.id, sizeof commands, commands, 0);
  GlVertexArray vertexArray;
  glVertexArrayVertexBuffer(vertexArray.id, 0, vertexBuffer.id, 0, 2 * sizeof(float));
  glVertexArrayElementBuffer(vertexArray.id, indexBuffer.id);
  glEnableVertexArrayAttrib(vertexArray.id, 0);
  glVertexArrayAttribFormat(vertexArray.id, 0, 2, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vertexArray.id, 0, 0);

  auto target = Framebuffer::create(kSceneSize, kSceneSize);
  ASSERT_TRUE(target.ok()) << target.error().message;
  target->bind();
  glClearNamedFramebufferfv(target->framebufferId(), GL_COLOR, 0, kClear);
  program->use();
  glBindVertexArray(vertexArray.id);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, commandBuffer.id);
  glMultiDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_SHORT, nullptr, 3, 0);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
  glBindVertexArray(0);
  glUseProgram(0);
  const Image image = target->readPixels();
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));

  // Quad centres at NDC x = -0.7, 0, 0.7 (columns 19, 64, 108), y = 0 (rows 51..76).
  const Rgba expected[3] = {{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}};
  const int columns[3] = {19, 64, 108};
  for (int quad = 0; quad < 3; ++quad)
    for (int row : {55, 64, 72})
      EXPECT_EQ(image.pixel(columns[quad], row), expected[quad])
          << "quad " << quad << " row " << row;
  // Between the quads, above and below them: nothing.
  for (const auto& [x, y] : {std::pair{41, 64}, {86, 64}, {64, 40}, {64, 90}, {125, 64}})
    EXPECT_EQ(image.pixel(x, y), kClearBytes) << x << "," << y;
}

TEST(RenderImage, PngRoundTripKeepsEveryByte) {
  test::TempDir dir;
  Image image{5, 3, {}};
  for (int i = 0; i < 5 * 3 * 4; ++i) image.rgba.push_back(uint8_t(i * 17 + (i % 4 == 3 ? 3 : 0)));
  const std::string path = dir.file("round_trip.png");
  ASSERT_TRUE(writePng(image, path).ok());
  auto back = readPng(path);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->width, 5);
  EXPECT_EQ(back->height, 3);
  EXPECT_EQ(back->rgba, image.rgba);
  EXPECT_EQ(back->pixel(4, 2), image.pixel(4, 2));
  // Nothing but the image itself: the temporary file was renamed, not left behind.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 1);
}

TEST(RenderImage, UnwritablePathFailsNamingItAndLeavesNothing) {
  test::TempDir dir;
  const std::string blocker = dir.file("not_a_directory");
  std::ofstream(blocker) << "x";
  const Image image{2, 2, std::vector<uint8_t>(16, 200)};
  for (const std::string& path :
       {blocker + "/out.png", dir.file("missing/out.png"), dir.path().string()}) {
    const Status status = writePng(image, path);
    ASSERT_FALSE(status.ok()) << path;
    EXPECT_NE(status.error().message.find(path), std::string::npos) << status.error().message;
  }
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 1);
}

TEST(RenderImage, ReadPngRejectsMissingAndForeignFiles) {
  test::TempDir dir;
  const std::string missing = dir.file("missing.png");
  auto none = readPng(missing);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().message.find(missing), std::string::npos) << none.error().message;
  const std::string text = dir.file("text.png");
  std::ofstream(text) << "definitely not a PNG";
  auto foreign = readPng(text);
  ASSERT_FALSE(foreign.ok());
  EXPECT_NE(foreign.error().message.find(text), std::string::npos) << foreign.error().message;
  // A PNG cut short: right signature, missing data.
  const std::string truncated = dir.file("truncated.png");
  ASSERT_TRUE(writePng(Image{4, 4, std::vector<uint8_t>(64, 9)}, truncated).ok());
  std::filesystem::resize_file(truncated, 30);
  auto cut = readPng(truncated);
  ASSERT_FALSE(cut.ok());
  EXPECT_NE(cut.error().message.find(truncated), std::string::npos) << cut.error().message;
}

}  // namespace
}  // namespace terralod
