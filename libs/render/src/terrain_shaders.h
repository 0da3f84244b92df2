#pragma once
// GLSL of the terrain and sky passes (one place, so the renderer reads as C++).

#include <iterator>
#include <string>

#include "terralod/format/generated_colour.h"

namespace terralod::shaders {

// The colour of a chunk level (--color-by level, chunk boxes): the version line and this
// function start the fragment shaders that use it (withLevelPalette).
inline constexpr const char* kLevelPalette = R"(#version 450 core
vec3 levelColor(float level) {
  const vec3 palette[8] = vec3[8](vec3(0.90, 0.25, 0.20), vec3(0.95, 0.60, 0.15),
      vec3(0.90, 0.85, 0.20), vec3(0.35, 0.75, 0.25), vec3(0.20, 0.70, 0.75),
      vec3(0.25, 0.40, 0.90), vec3(0.60, 0.35, 0.85), vec3(0.85, 0.40, 0.65));
  return palette[int(level) % 8];
}
)";

inline std::string withLevelPalette(const char* body) {
  return std::string(kLevelPalette) + body;
}

// Aerial perspective from an exponential atmosphere: air density exp(-z / H) relative to sea
// level (z in metres, H the scale height), so the haze a ray gathers is its optical depth, the
// sea-level metres of air it crosses. The terrain and the sky include this after the version
// line (atmosphere.h has the constants).
inline constexpr const char* kAtmosphere = R"(
uniform float uScaleHeight;  // H, metres
uniform float uExtinction;   // per metre of sea-level air (sigma times --haze)
// The integral of exp(-z / H) along the straight segment of length len between heights z0
// and z1: len exp(-lo / H) (1 - exp(-x)) / x with lo the lower end and x = |z1 - z0| / H. The
// quotient is taken by its series where it would lose its digits (near-horizontal segments).
float opticalDepth(float z0, float z1, float len) {
  float lo = min(z0, z1);
  float x = abs(z1 - z0) / uScaleHeight;
  float f = x < 1e-2 ? 1.0 - x * (0.5 - x / 6.0) : (1.0 - exp(-x)) / x;
  return len * exp(-lo / uScaleHeight) * f;
}
// How much of what lies at the far end of the segment comes through the air.
float transmittance(float z0, float z1, float len) {
  return exp(-uExtinction * opticalDepth(z0, z1, len));
}
)";

// Chunk vertices are 16-bit grid offsets and heights; each draw's placement comes from the
// draws[] buffer indexed by gl_DrawIDARB. Positions are relative to the eye (computed in double
// on the CPU per chunk), so float keeps millimetres even hundreds of kilometres from the origin.
inline constexpr const char* kTerrainVertex = R"(#version 450 core
#extension GL_ARB_shader_draw_parameters : require
layout(location = 0) in uvec3 aGrid;   // x, y cells from the chunk's corner; quantised height
layout(location = 1) in int aMorphDelta;
struct Draw {
  vec4 origin;  // chunk corner relative to the eye (z: zBase - eye z), w: morph parameter t
  vec4 scale;   // spacing x, spacing y, zStep, level
  uvec4 counts; // x: surface triangles (skirt triangles follow them), y: colour layer,
                // z: normal layer, w: chunk side in cells
  uvec4 skirt;  // x: first skirt-bottom vertex of the part, y: outward slant (float bits),
                // z: depth below the texture's owner | owner's level << 8, w: column | row << 16
                // of the chunk's square in the owner's (a chunk that inherits its texture)
};
layout(std430, binding = 0) readonly buffer Draws { Draw draws[]; };
uniform mat4 uViewProjection;  // eye at the origin
uniform float uEyeHeight;
uniform int uDrawBase;  // this call's first entry in draws[]
uniform float uEyeNorth;    // the eye's y (metres north of the tileset's first row)
// Shade layers: the snow line at 33 (kSnowLineSamples) evenly spaced rows, first to last, and
// 1 / (spacing y * last row) to take a y to its fraction of them.
uniform float uSnowLine[33];
uniform float uSnowFraction;
out vec3 vRelative;
out float vSnowLine;
out float vHeight;
out vec2 vChunkUv;  // 0..1 across the chunk's square
out vec2 vTextureUv;  // 0..1 across its texture owner's square
flat out float vLevel;
flat out float vTextureLevel;  // the owner's level
flat out float vMorph;
flat out uint vSurfaceTriangles;
flat out uvec2 vLayers;
void main() {
  Draw d = draws[uDrawBase + gl_DrawIDARB];
  float steps = float(aGrid.z) + d.origin.w * float(aMorphDelta);
  vec3 p = d.origin.xyz + vec3(float(aGrid.x) * d.scale.x, float(aGrid.y) * d.scale.y,
                               steps * d.scale.z);
  // Skirt bottoms move a little outwards, under the neighbour: a vertical skirt seen exactly
  // edge-on (the eye above the border, looking along it) covers nothing, a slanted one does.
  if (uint(gl_VertexID - gl_BaseVertexARB) >= d.skirt.x) {
    vec2 outwards = vec2(aGrid.x == 0u ? -1.0 : aGrid.x == d.counts.w ? 1.0 : 0.0,
                         aGrid.y == 0u ? -1.0 : aGrid.y == d.counts.w ? 1.0 : 0.0);
    p.xy += outwards * uintBitsToFloat(d.skirt.y);
  }
  vRelative = p;
  vHeight = p.z + uEyeHeight;
  float u = clamp((p.y + uEyeNorth) * uSnowFraction, 0.0, 1.0) * 32.0;
  int i = min(int(u), 32);
  vSnowLine = mix(uSnowLine[i], uSnowLine[min(i + 1, 32)], u - float(i));
  vChunkUv = vec2(aGrid.xy) / float(d.counts.w);
  vec2 square = vec2(float(d.skirt.w & 0xFFFFu), float(d.skirt.w >> 16));
  vTextureUv = (square + vChunkUv) / float(1u << (d.skirt.z & 0xFFu));
  vLevel = d.scale.w;
  vTextureLevel = float(d.skirt.z >> 8);
  vMorph = d.origin.w;
  vSurfaceTriangles = d.counts.x;
  vLayers = d.counts.yz;
  gl_Position = uViewProjection * vec4(p, 1.0);
}
)";

// Textured tilesets: colour and normal per pixel from the chunk's tiles (the normal map comes
// from the full-resolution heightfield, so lighting does not change when geometry changes
// level). Tilesets without textures: normals from the drawn (morphed) surface itself, one per
// triangle, continuous through every split and merge because the surface is.
// Tile texel i of n lies at i / (n - 1) of the chunk's side (edge-aligned).
inline constexpr const char* kTerrainFragment = R"(
in vec3 vRelative;
in float vHeight;
in vec2 vChunkUv;
in vec2 vTextureUv;
flat in float vLevel;
flat in float vTextureLevel;
flat in float vMorph;
flat in uint vSurfaceTriangles;
flat in uvec2 vLayers;
uniform int uTextured;
uniform sampler2DArray uColor;   // unit 0
uniform sampler2DArray uNormal;  // unit 1
uniform vec2 uTileSizes;         // colour, normal texels per side
// Where each level's mips keep their texels (texture_placement.h): 16 entries per level and
// layer kind; entry m = log2(pieces) | pieceMip << 4 | pieceSize << 8, bit 31 of entry 0: the
// level's mips are sampled piece by piece.
layout(std430, binding = 1) readonly buffer Placements { uint placements[]; };
uniform int uColorBy;      // 0 shaded relief, 1 level, 2 morph parameter
uniform int uUnlit;        // 1: the colour as it is, no light
uniform int uWire;         // 1: the wireframe overlay pass
uniform vec3 uSun;         // unit vector towards the sun
uniform vec2 uHeightRange; // data min, max z
uniform vec3 uHaze;         // the air's colour, linear
uniform float uEyeHeight;
in float vSnowLine;         // shade layers: the snow line here (metres)
out vec4 fragColor;

vec3 hypsometric(float h) {
  const vec3 lowland = vec3(0.30, 0.45, 0.22), hills = vec3(0.55, 0.55, 0.33);
  const vec3 rock = vec3(0.52, 0.44, 0.38), snow = vec3(0.93, 0.94, 0.96);
  if (h < 0.35) return mix(lowland, hills, h / 0.35);
  if (h < 0.75) return mix(hills, rock, (h - 0.35) / 0.40);
  return mix(rock, snow, smoothstep(0.82, 0.95, h));
}

// The texture coordinate of fraction f of the chunk in a mip made of pieces x pieces tiles of
// pieceSize texels at their mip pieceMip, each placed for its own size.
vec2 placedUv(vec2 f, uint entry) {
  float pieces = float(1u << (entry & 15u));
  uint pieceSize = (entry >> 8) & 0x1FFFu;
  float s = float(max(1u, pieceSize >> ((entry >> 4) & 15u)));
  vec2 scaled = f * pieces;
  vec2 piece = min(floor(scaled), vec2(pieces - 1.0));
  vec2 texel = piece * s + (0.5 + (scaled - piece) * (float(pieceSize) - 1.0)) * s /
               float(pieceSize);
  return texel / (pieces * s);
}

// A tile's texel at fraction f: GL's trilinear filtering, or for tiles whose mips are mosaics of
// unresampled descendants, the same filtering done level by level at each piece's placement.
vec4 sampleTile(sampler2DArray tile, vec2 f, float size, float layer, int kind) {
  vec2 uv = (0.5 + f * (size - 1.0)) / size;
  // A constant of the program variant (the renderer groups draws by it): a software
  // rasteriser would run both sides of a branch on a uniform for every pixel.
  if ((kPiecewise & (1 << kind)) == 0) return texture(tile, vec3(uv, layer));
  int level = int(vTextureLevel + 0.5);
  uint base = uint((level * 2 + kind) * 16);
  int levels = textureQueryLevels(tile);
  float lod = clamp(textureQueryLod(tile, uv).y, 0.0, float(levels - 1));
  int m0 = int(floor(lod));
  int m1 = min(m0 + 1, levels - 1);
  vec4 a = textureLod(tile, vec3(placedUv(f, placements[base + uint(m0)]), layer), float(m0));
  vec4 b = textureLod(tile, vec3(placedUv(f, placements[base + uint(m1)]), layer), float(m1));
  return mix(a, b, lod - float(m0));
}

void main() {
  if (uWire == 1) {
    fragColor = vec4(0.05, 0.05, 0.05, 1.0);
    return;
  }
  vec3 n;
  vec3 base;
  if (uTextured == 1) {
    base = sampleTile(uColor, vTextureUv, uTileSizes.x, float(vLayers.x), 0).rgb;  // sRGB: linear
    vec2 xy = sampleTile(uNormal, vTextureUv, uTileSizes.y, float(vLayers.y), 1).rg * 2.0 - 1.0;
    n = vec3(xy, sqrt(max(0.0, 1.0 - dot(xy, xy))));
    // A shade layer (a constant of the variant): the colour made here from it.
    if (kShaded == 1) base = shadedColourLinear(vHeight, 1.0 - n.z, vSnowLine, base.r);
  } else {
    n = normalize(cross(dFdx(vRelative), dFdy(vRelative)));
    if (n.z < 0.0) n = -n;
    // A skirt shows only where it fills a crack between chunks: light it like level ground
    // so the filled crack does not stand out as a dark seam.
    if (uint(gl_PrimitiveID) >= vSurfaceTriangles) n = vec3(0.0, 0.0, 1.0);
    float range = max(uHeightRange.y - uHeightRange.x, 1e-3);
    base = hypsometric(clamp((vHeight - uHeightRange.x) / range, 0.0, 1.0));
    // Steep slopes show bare rock whatever their height.
    base = mix(base, vec3(0.45, 0.41, 0.38), smoothstep(0.55, 0.85, 1.0 - n.z));
  }
  if (uColorBy == 1) base = levelColor(vLevel);
  if (uColorBy == 2) base = mix(vec3(0.15, 0.35, 0.95), vec3(0.95, 0.25, 0.15), vMorph);
  if (uColorBy == 3) base = vec3(0.62);  // by kind: chunked LOD chunks are grey
  float diffuse = max(dot(n, uSun), 0.0);
  float sky = 0.30 + 0.20 * n.z;
  vec3 color = uUnlit == 1 ? base : base * (sky + 0.85 * diffuse);
  float through = transmittance(uEyeHeight, vHeight, length(vRelative));
  color = color * through + uHaze * (1.0 - through);
  fragColor = vec4(pow(color, vec3(1.0 / 2.2)), 1.0);
}
)";

// The generated colour of a shade layer (format/generated_colour.h's shadedColour, whose
// constants it is written from), in linear light.
static_assert(kSnowLineSamples == 33, "kTerrainVertex's uSnowLine[33]");
inline std::string generatedColourGlsl() {
  auto f = [](float v) { return std::to_string(v); };
  auto rgb = [&](GroundColor c) { return "vec3(" + f(c.r) + ", " + f(c.g) + ", " + f(c.b) + ")"; };
  const auto& p = kGroundPalette;
  // The palette without branches (a software rasteriser runs every side of one for every
  // pixel): mixing towards each stop in turn by how far past the previous one h is gives the
  // piecewise-linear palette exactly.
  std::string s = "vec3 paletteColor(float h) {\n  vec3 c = " + rgb(p[0].color) + ";\n";
  for (size_t i = 1; i < std::size(p); ++i)
    s += "  c = mix(c, " + rgb(p[i].color) + ", clamp((h - " + f(p[i - 1].height) + ") / " +
         f(p[i].height - p[i - 1].height) + ", 0.0, 1.0));\n";
  s += "  return c;\n}\n";
  // Display values to linear light: sRGB's curve by a cubic (within 0.0017 of it, linear).
  s += "vec3 displayToLinear(vec3 c) {\n"
       "  return c * (c * (c * 0.305306011 + 0.682171111) + 0.012522878);\n}\n";
  // shadedColour in linear light: the occlusion darkens linear light, water mixes in.
  s += "vec3 shadedColourLinear(float h, float slope, float snowLine, float shade) {\n";
  s += "  vec3 c = mix(paletteColor(h), " + rgb(kSnowColor) + ", smoothstep(snowLine, snowLine + " +
       f(kSnowBand) + ", h));\n";
  s += "  c = mix(c, " + rgb(kBareRockColor) + ", smoothstep(" + f(kRockSlopeStart) + ", " +
       f(kRockSlopeEnd) + ", slope));\n";
  s += "  float v = clamp(shade, 0.0, 1.0), landShade = " + f(kLandShade) +
       ", minOcclusion = " + f(kMinOcclusion) + ";\n";
  s += "  float water = clamp(1.0 - v / landShade, 0.0, 1.0);\n";
  s += "  float land = mix(1.0 + (landShade - 1.0) * (v / landShade), v, step(landShade, v));\n";
  s += "  float occlusion = minOcclusion + (1.0 - minOcclusion) * (land - landShade) / "
       "(1.0 - landShade);\n";
  s += "  return mix(displayToLinear(c) * occlusion, displayToLinear(" + rgb(kWaterColor) +
       "), water);\n}\n";
  return s;
}

// The terrain fragment shader's variant: bits 0 and 1 the piecewise mask (bit 0, colour mips
// sampled piece by piece; bit 1, normal mips: kTerrainFragment's sampleTile), bit 2 a shade
// layer in place of the colour.
inline std::string terrainFragment(int variant) {
  return std::string(kLevelPalette) + kAtmosphere + generatedColourGlsl() +
         "const int kPiecewise = " + std::to_string(variant & 3) + ";\n" +
         "const int kShaded = " + std::to_string((variant >> 2) & 1) + ";\n" + kTerrainFragment;
}

// Chunk bounding boxes: lines between eye-relative corners, coloured by the chunk's level like
// --color-by level.
inline constexpr const char* kBoxVertex = R"(#version 450 core
layout(location = 0) in vec3 aPosition;  // relative to the eye
layout(location = 1) in float aLevel;
uniform mat4 uViewProjection;
flat out float vLevel;
void main() {
  vLevel = aLevel;
  gl_Position = uViewProjection * vec4(aPosition, 1.0);
}
)";

inline constexpr const char* kBoxFragment = R"(
flat in float vLevel;
out vec4 fragColor;
void main() { fragColor = vec4(levelColor(vLevel), 1.0); }
)";

// A full-screen triangle at the far plane: the background colour (what lies beyond the air)
// seen through the air a ray crosses, so haze at the horizon and clearer overhead.
inline constexpr const char* kSkyVertex = R"(#version 450 core
uniform mat4 uInverseViewProjection;
out vec3 vDirection;
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2)) * 2.0 - 1.0;
  vec4 far = uInverseViewProjection * vec4(p, 0.5, 1.0);
  vDirection = far.xyz / far.w;
  gl_Position = vec4(p, 0.0, 1.0);  // reversed depth: 0 is infinitely far
}
)";

// Upwards the ray leaves the air (to infinity); downwards, where no terrain is, it ends at the
// floor (sea level or the data's lowest point, if lower). Either way the optical depth grows
// without bound towards the horizontal, so the horizon is the haze colour.
inline constexpr const char* kSkyFragment = R"(
in vec3 vDirection;
uniform vec3 uBackground;
uniform vec3 uHaze;
uniform float uEyeHeight;
uniform float uFloor;
out vec4 fragColor;
void main() {
  float dz = normalize(vDirection).z;
  const float kLevel = 1e-6;  // steeper than this: the length below stays finite in float
  float through;
  if (dz >= 0.0) {
    through = exp(-uExtinction * uScaleHeight * exp(-uEyeHeight / uScaleHeight) /
                  max(dz, kLevel));
  } else {
    float drop = max(uEyeHeight - uFloor, 0.0);
    through = transmittance(uEyeHeight, uEyeHeight - drop, drop / max(-dz, kLevel));
  }
  fragColor = vec4(uBackground * through + uHaze * (1.0 - through), 1.0);
}
)";

inline std::string skyFragment() {
  return std::string("#version 450 core\n") + kAtmosphere + kSkyFragment;
}

}  // namespace terralod::shaders
