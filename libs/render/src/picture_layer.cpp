#include "terralod/render/picture_layer.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>

#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include "gl_object.h"
#include "terralod/render/aerial_perspective.h"
#include "terralod/render/frame_context.h"
#include "terralod/render/full_screen_pass.h"
#include "terralod/render/shader_program.h"

namespace terralod {
namespace {

// Reversed-Z like the terrain (frame_context.h): depth = near / distance along the view axis;
// the depth test (GEQUAL, from the layer hook) keeps what is nearer than the terrain.
constexpr const char* kFragment = R"(
layout(binding = 0) uniform sampler2D uColor;
layout(binding = 1) uniform sampler2D uDepth;
uniform float uNear;
uniform ivec2 uOrigin;
uniform ivec2 uSize;
uniform mat4 uInverseViewProjection;  // eye-relative
out vec4 fragColor;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy) - uOrigin;
  p.y = uSize.y - 1 - p.y;  // the picture's row 0 is the top
  vec4 c = texelFetch(uColor, p, 0);
  float d = texelFetch(uDepth, p, 0).r;
  if (c.a <= 0.0 || isinf(d)) discard;
  float depth = uNear / d;
  gl_FragDepth = depth;
  // Through the air like the ground under it (colours are display-encoded, premultiplied).
  vec2 ndc = (vec2(gl_FragCoord.xy) - vec2(uOrigin)) / vec2(uSize) * 2.0 - 1.0;
  vec4 q = uInverseViewProjection * vec4(ndc, depth, 1.0);
  vec3 at = q.xyz / q.w;
  vec3 linear = pow(c.rgb / c.a, vec3(2.2));
  vec3 seen = hazed(linear, uEyeHeight + at.z, length(at));
  fragColor = vec4(pow(seen, vec3(1.0 / 2.2)) * c.a, c.a);
}
)";

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

struct PictureLayer::Gl {
  explicit Gl(ShaderProgram p) : program(std::move(p)) {}
  ShaderProgram program;
  GlVertexArray empty = GlVertexArray::make();
  GlTexture color, depth;
  int width = 0, height = 0;
};

Result<std::unique_ptr<PictureLayer>> PictureLayer::create(Painter painter) {
  auto program = ShaderProgram::create(
      "picture layer", {kFullScreenVertexShader,
                        std::string("#version 450 core\n") + aerialPerspectiveGlsl() + kFragment,
                        {}});
  if (!program) return program.error();
  auto gl = std::make_unique<Gl>(std::move(program).value());
  return std::unique_ptr<PictureLayer>(new PictureLayer(std::move(painter), std::move(gl)));
}

PictureLayer::PictureLayer(Painter painter, std::unique_ptr<Gl> gl)
    : mPainter(std::move(painter)), mGl(std::move(gl)) {}
PictureLayer::~PictureLayer() = default;

uint32_t PictureLayer::draw(const FrameContext& frame) {
  mTimes = {};
  if (!mEnabled) return 0;
  const int width = frame.viewport.width, height = frame.viewport.height;
  const size_t pixels = size_t(width) * size_t(height);
  mRgba.resize(pixels);
  mDepth.resize(pixels);
  auto start = std::chrono::steady_clock::now();
  const PaintedRows painted = mPainter(frame, LayerPicture{width, height, mRgba, mDepth});
  mTimes.paintMs = msSince(start);
  const int top = std::clamp(painted.top, 0, height);
  const int rows = std::clamp(painted.bottom, top, height) - top;
  mTimes.rows = rows;
  if (rows == 0) return 0;

  glFinish();  // the terrain's drawing is not the composite's
  start = std::chrono::steady_clock::now();
  Gl& gl = *mGl;
  if (gl.width != width || gl.height != height) {
    GLuint names[2];
    glCreateTextures(GL_TEXTURE_2D, 2, names);
    gl.color = GlTexture(names[0]);
    gl.depth = GlTexture(names[1]);
    glTextureStorage2D(names[0], 1, GL_RGBA8, width, height);
    glTextureStorage2D(names[1], 1, GL_R32F, width, height);
    gl.width = width;
    gl.height = height;
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  // Texture row r holds picture row r (the shader flips); only the painted rows.
  const size_t first = size_t(top) * size_t(width);
  glTextureSubImage2D(gl.color.id(), 0, 0, top, width, rows, GL_RGBA, GL_UNSIGNED_BYTE,
                      mRgba.data() + first);
  glTextureSubImage2D(gl.depth.id(), 0, 0, top, width, rows, GL_RED, GL_FLOAT,
                      mDepth.data() + first);
  gl.program.use();
  glUniform1f(gl.program.uniformLocation("uNear"), float(kNearPlane));
  glUniform2i(gl.program.uniformLocation("uOrigin"), frame.viewport.x, frame.viewport.y);
  glUniform2i(gl.program.uniformLocation("uSize"), width, height);
  const glm::mat4 inverse(glm::inverse(frame.projection * frame.viewRotation));
  glUniformMatrix4fv(gl.program.uniformLocation("uInverseViewProjection"), 1, GL_FALSE,
                     glm::value_ptr(inverse));
  setAerialPerspective(gl.program.id(), frame);
  glBindTextureUnit(0, gl.color.id());
  glBindTextureUnit(1, gl.depth.id());
  glBindVertexArray(gl.empty.id());
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);  // premultiplied `over`
  if (!mDepthTest) glDisable(GL_DEPTH_TEST);
  glEnable(GL_SCISSOR_TEST);
  glScissor(frame.viewport.x, frame.viewport.y + height - top - rows, width, rows);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_BLEND);
  glEnable(GL_DEPTH_TEST);
  glBindTextureUnit(0, 0);
  glBindTextureUnit(1, 0);
  glFinish();
  mTimes.compositeMs = msSince(start);
  return 1;
}

}  // namespace terralod
