#include "terralod/vegetation/far_vegetation_layer.h"

#include <epoxy/gl.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "terralod/render/aerial_perspective.h"
#include "terralod/render/frame_context.h"
#include "terralod/render/full_screen_pass.h"
#include "terralod/render/shader_program.h"

namespace terralod::veg {
namespace {

// Tiles a side of the window of prototile indices around the eye; beyond it tiles are less
// than a pixel wide (4 km for 4.4 m tiles at 1024 pixels across 60 degrees) and a hash picks
// their prototile.
constexpr int kWindowTiles = 2048;

// After the version line, the depth sampler's declaration and the aerial perspective.
constexpr const char* kFragment = R"(
layout(early_fragment_tests) in;
layout(binding = 0) uniform sampler2DArray uTextures;
layout(binding = 1) uniform usampler2D uTiles;
layout(binding = 3) uniform usampler2D uMaterialMask;  // material_mask.h
uniform bool uMaterialRule;
uniform vec2 uMaskCell;                                // metres between its points
uniform mat4 uInverseViewProjection;  // eye-relative
uniform ivec2 uOrigin, uSize;
uniform vec2 uEyeInWindow;     // metres from the window's south-west corner
uniform ivec2 uWindowOrigin;   // the window's first tile
uniform ivec2 uWindowTiles;
uniform float uTileSize;
uniform vec2 uFade;            // distances where the textures start and finish fading in
uniform vec2 uHeightRule;      // draw where below x and above y (metres)
uniform vec2 uSlopeRule;       // draw where below x and above y (degrees)
uniform float uElevations[4];  // degrees, ascending
uniform int uDirections, uElevationCount;
out vec4 fragColor;

int prototileAt(ivec2 t) {
  ivec2 w = t - uWindowOrigin;
  if (all(greaterThanEqual(w, ivec2(0))) && all(lessThan(w, uWindowTiles)))
    return int(texelFetch(uTiles, w, 0).r);
  uint h = uint(t.x) * 0x9e3779b1u ^ uint(t.y) * 0x85ebca77u;
  h ^= h >> 15; h *= 0x2c1b3c6du; h ^= h >> 12;
  return int(h & 7u);
}

vec4 sampleTexture(int prototile, int direction, int elevation, vec2 st, vec2 gx, vec2 gy) {
  float layer = float((prototile * uDirections + direction) * uElevationCount + elevation);
  return textureGrad(uTextures, vec3(st, layer), gx, gy);
}

// The ground point of a pixel, from the eye.
vec3 groundAt(ivec2 pixel, float depth) {
  vec2 ndc = (vec2(pixel) + 0.5 - vec2(uOrigin)) / vec2(uSize) * 2.0 - 1.0;
  vec4 q = uInverseViewProjection * vec4(ndc, depth, 1.0);
  return q.xyz / q.w;
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float d = terrainDepth(pixel);
  if (d <= 0.0) discard;  // sky
  vec3 p = groundAt(pixel, d);  // the ground point, from the eye
  float distance = length(p);
  float weight = smoothstep(uFade.x, uFade.y, distance);
  if (weight <= 0.0) discard;
  // The ground's slope and the texture's footprint from the neighbouring pixels' ground
  // points (not derivatives: pixels around may have left).
  ivec2 across = ivec2(pixel.x + 1 < uOrigin.x + uSize.x ? 1 : -1, 0);
  ivec2 up = ivec2(0, pixel.y + 1 < uOrigin.y + uSize.y ? 1 : -1);
  float dx = terrainDepth(pixel + across), dy = terrainDepth(pixel + up);
  vec3 px = dx > 0.0 ? groundAt(pixel + across, dx) - p : vec3(0.0);
  vec3 py = dy > 0.0 ? groundAt(pixel + up, dy) - p : vec3(0.0);
  px *= float(across.x);
  py *= float(up.y);
  vec3 n = cross(px, py);
  vec2 g = (uEyeInWindow + p.xy) / uTileSize;  // in tiles
  vec2 gx = px.xy / uTileSize, gy = py.xy / uTileSize;
  float height = uEyeHeight + p.z;
  float slope = length(n) > 0.0 ? degrees(acos(clamp(abs(normalize(n).z), 0.0, 1.0))) : 0.0;
  if (!(height < uHeightRule.x && height > uHeightRule.y && slope < uSlopeRule.x &&
        slope > uSlopeRule.y))
    discard;
  ivec2 tile = ivec2(floor(g));
  if (uMaterialRule) {  // the mask's point nearest the tile's centre, as the LDI tiles ask
    vec2 centre = (vec2(tile + uWindowOrigin) + 0.5) * uTileSize;
    ivec2 size = textureSize(uMaterialMask, 0);
    ivec2 point = clamp(ivec2(floor(centre / uMaskCell + 0.5)), ivec2(0), size - 1);
    if (texelFetch(uMaterialMask, point, 0).r == 0u) discard;
  }
  vec2 st = vec2(g.x - float(tile.x), 1.0 - (g.y - float(tile.y)));  // row 0 at the north
  gx.y = -gx.y;
  gy.y = -gy.y;
  int prototile = prototileAt(tile + uWindowOrigin);
  // Between the two nearest directions (azimuth of the line of sight, clockwise from north)
  // and the two nearest elevations.
  float a = atan(p.x, p.y) / (6.28318530718 / float(uDirections));
  float a0 = floor(a);
  float ta = a - a0;
  int d0 = (int(a0) % uDirections + uDirections) % uDirections;
  int d1 = (d0 + 1) % uDirections;
  float e = degrees(atan(-p.z, length(p.xy)));
  int e0 = 0;
  for (int i = 1; i < uElevationCount - 1; ++i)
    if (e > uElevations[i]) e0 = i;
  int e1 = min(e0 + 1, uElevationCount - 1);
  float te = clamp((e - uElevations[e0]) / max(uElevations[e1] - uElevations[e0], 1e-3), 0.0, 1.0);
  vec4 c = mix(mix(sampleTexture(prototile, d0, e0, st, gx, gy),
                   sampleTexture(prototile, d1, e0, st, gx, gy), ta),
               mix(sampleTexture(prototile, d0, e1, st, gx, gy),
                   sampleTexture(prototile, d1, e1, st, gx, gy), ta), te);
  c *= weight;
  if (c.a <= 0.0) discard;
  vec3 linear = pow(c.rgb / c.a, vec3(2.2));
  fragColor = vec4(pow(hazed(linear, height, distance), vec3(1.0 / 2.2)) * c.a, c.a);
}
)";

constexpr const char* kSingleSampled = R"(
layout(binding = 2) uniform sampler2D uDepth;
float terrainDepth(ivec2 p) { return texelFetch(uDepth, p, 0).r; }
)";
constexpr const char* kMultisampled = R"(
layout(binding = 2) uniform sampler2DMS uDepth;
float terrainDepth(ivec2 p) { return texelFetch(uDepth, p, 0).r; }
)";

Result<ShaderProgram> program(bool multisampled) {
  const std::string fragment = std::string("#version 450 core\n") +
                               (multisampled ? kMultisampled : kSingleSampled) +
                               aerialPerspectiveGlsl() + kFragment;
  return ShaderProgram::create(
      multisampled ? "far vegetation (multisampled depth)" : "far vegetation",
      {kFullScreenVertexShader, fragment, {}});
}

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

struct FarVegetationLayer::Gl {
  ShaderProgram single, multi;
  GLuint textures = 0, tiles = 0, materialMask = 0, vertexArray = 0;
  glm::ivec2 windowOrigin{std::numeric_limits<int>::min() / 2};
  Gl(ShaderProgram s, ShaderProgram m) : single(std::move(s)), multi(std::move(m)) {}
  ~Gl() {
    const GLuint names[] = {textures, tiles, materialMask};
    glDeleteTextures(3, names);
    glDeleteVertexArrays(1, &vertexArray);
  }
};

Result<std::unique_ptr<FarVegetationLayer>> FarVegetationLayer::create(
    const DirectionalTextures& t, const FieldLayout& layout, const FieldOptions& options) {
  auto single = program(false);
  if (!single) return single.error();
  auto multi = program(true);
  if (!multi) return multi.error();
  auto gl = std::make_unique<Gl>(std::move(single).value(), std::move(multi).value());
  glCreateVertexArrays(1, &gl->vertexArray);
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &gl->textures);
  const int levels = int(std::log2(double(t.size))) + 1;
  glTextureStorage3D(gl->textures, levels, GL_RGBA8, t.size, t.size, DirectionalTextures::kCount);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage3D(gl->textures, 0, 0, 0, 0, t.size, t.size, DirectionalTextures::kCount,
                      GL_RGBA, GL_UNSIGNED_BYTE, t.rgba.data());
  glGenerateTextureMipmap(gl->textures);
  glTextureParameteri(gl->textures, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(gl->textures, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(gl->textures, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTextureParameteri(gl->textures, GL_TEXTURE_WRAP_T, GL_REPEAT);
  glCreateTextures(GL_TEXTURE_2D, 1, &gl->tiles);
  glTextureStorage2D(gl->tiles, 1, GL_R8UI, kWindowTiles, kWindowTiles);
  glTextureParameteri(gl->tiles, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(gl->tiles, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  if (const MaterialMask* mask = options.where.materialMask.get()) {
    glCreateTextures(GL_TEXTURE_2D, 1, &gl->materialMask);
    glTextureStorage2D(gl->materialMask, 1, GL_R8UI, mask->columns, mask->rows);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(gl->materialMask, 0, 0, 0, mask->columns, mask->rows, GL_RED_INTEGER,
                        GL_UNSIGNED_BYTE, mask->allowed.data());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureParameteri(gl->materialMask, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(gl->materialMask, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  return std::unique_ptr<FarVegetationLayer>(
      new FarVegetationLayer(std::move(gl), layout, options));
}

FarVegetationLayer::FarVegetationLayer(std::unique_ptr<Gl> gl, const FieldLayout& layout,
                                       const FieldOptions& options)
    : mGl(std::move(gl)), mLayout(layout), mOptions(options) {}
FarVegetationLayer::~FarVegetationLayer() = default;

void FarVegetationLayer::recentreWindow(const glm::dvec3& eye) {
  const glm::ivec2 eyeTile(int(std::floor(eye.x / mLayout.tileSize)),
                           int(std::floor(eye.y / mLayout.tileSize)));
  const glm::ivec2 centre = mGl->windowOrigin + kWindowTiles / 2;
  if (std::abs(eyeTile.x - centre.x) < kWindowTiles / 4 &&
      std::abs(eyeTile.y - centre.y) < kWindowTiles / 4)
    return;
  mGl->windowOrigin = eyeTile - kWindowTiles / 2;
  // Prototiles where the tiling covers the terrain; outside it none grows anyway.
  std::vector<uint8_t> window(size_t(kWindowTiles) * kWindowTiles, 0);
  const WangTiling& tiling = mLayout.tiling;
  for (int y = 0; y < kWindowTiles; ++y) {
    const int64_t ty = int64_t(mGl->windowOrigin.y) + y;
    if (ty < 0 || ty >= int64_t(tiling.height())) continue;
    for (int x = 0; x < kWindowTiles; ++x) {
      const int64_t tx = int64_t(mGl->windowOrigin.x) + x;
      if (tx < 0 || tx >= int64_t(tiling.width())) continue;
      window[size_t(y) * kWindowTiles + size_t(x)] = uint8_t(tiling.at(uint32_t(tx), uint32_t(ty)));
    }
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(mGl->tiles, 0, 0, 0, kWindowTiles, kWindowTiles, GL_RED_INTEGER,
                      GL_UNSIGNED_BYTE, window.data());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
}

uint32_t FarVegetationLayer::draw(const FrameContext& frame) {
  mLastMs = 0;
  if (!mEnabled || !frame.depth.readable()) return 0;
  glFinish();  // the terrain's drawing is not this pass's
  const auto start = std::chrono::steady_clock::now();
  recentreWindow(frame.eye);
  const ShaderProgram& p = frame.depth.samples > 0 ? mGl->multi : mGl->single;
  const GLuint id = p.id();
  const double range = ldiRange(mLayout, frame.view, mOptions);
  const glm::mat4 inverse(glm::inverse(frame.projection * frame.viewRotation));
  glProgramUniformMatrix4fv(id, p.uniformLocation("uInverseViewProjection"), 1, GL_FALSE,
                            glm::value_ptr(inverse));
  glProgramUniform2i(id, p.uniformLocation("uOrigin"), frame.viewport.x, frame.viewport.y);
  glProgramUniform2i(id, p.uniformLocation("uSize"), frame.viewport.width, frame.viewport.height);
  // The eye relative to the window's corner, in double first (kilometres from the origin).
  const glm::dvec2 corner = glm::dvec2(mGl->windowOrigin) * double(mLayout.tileSize);
  glProgramUniform2f(id, p.uniformLocation("uEyeInWindow"), float(frame.eye.x - corner.x),
                     float(frame.eye.y - corner.y));
  glProgramUniform2i(id, p.uniformLocation("uWindowOrigin"), mGl->windowOrigin.x,
                     mGl->windowOrigin.y);
  glProgramUniform2i(id, p.uniformLocation("uWindowTiles"), kWindowTiles, kWindowTiles);
  glProgramUniform1f(id, p.uniformLocation("uTileSize"), mLayout.tileSize);
  glProgramUniform2f(id, p.uniformLocation("uFade"), float(range * (1.0 - kRangeFade)),
                     float(range));
  const VegetationWhere& w = mOptions.where;
  constexpr float kNone = std::numeric_limits<float>::max();
  glProgramUniform2f(id, p.uniformLocation("uHeightRule"), float(w.heightBelow.value_or(kNone)),
                     float(w.heightAbove.value_or(-kNone)));
  glProgramUniform2f(id, p.uniformLocation("uSlopeRule"), float(w.slopeBelow.value_or(kNone)),
                     float(w.slopeAbove.value_or(-kNone)));
  // A material rule not resolved allows nothing (vegetation_where.h), drawn or not.
  if (!w.materials.empty() && !mGl->materialMask) return 0;
  glProgramUniform1i(id, p.uniformLocation("uMaterialRule"), mGl->materialMask != 0);
  if (const MaterialMask* mask = w.materialMask.get())
    glProgramUniform2f(id, p.uniformLocation("uMaskCell"), float(mask->cellX), float(mask->cellY));
  glProgramUniform1fv(id, p.uniformLocation("uElevations"), kTextureElevationCount,
                      kTextureElevations.data());
  glProgramUniform1i(id, p.uniformLocation("uDirections"), kLdiDirections);
  glProgramUniform1i(id, p.uniformLocation("uElevationCount"), kTextureElevationCount);
  setAerialPerspective(id, frame);
  p.use();
  glBindTextureUnit(0, mGl->textures);
  glBindTextureUnit(1, mGl->tiles);
  glBindTextureUnit(2, frame.depth.texture);
  glBindTextureUnit(3, mGl->materialMask);
  glBindVertexArray(mGl->vertexArray);
  // The triangle lies where the fade begins (along the view axis, a little nearer for the
  // image's corners, whose rays are longer): the hook's depth test (GEQUAL, reversed-Z)
  // skips every pixel whose terrain is nearer before its shader runs. Premultiplied `over`.
  const double cornerStretch =
      std::sqrt(1.0 + std::pow(frame.view.tanHalfWidth, 2) + std::pow(frame.view.tanHalfHeight, 2));
  const double passDistance = range * (1.0 - kRangeFade) / cornerStretch;
  glProgramUniform1f(id, p.uniformLocation("uPassDepth"), float(kNearPlane / passDistance));
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glDisable(GL_BLEND);
  for (GLuint unit = 0; unit < 4; ++unit) glBindTextureUnit(unit, 0);
  glFinish();
  mLastMs = msSince(start);
  return 1;
}

}  // namespace terralod::veg
