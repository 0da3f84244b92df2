#pragma once
// GLSL of the VIPM chunk passes (vipm_pass.h). One program for every pass, so every pass puts
// a vertex at exactly the same depth (invariant gl_Position) and the material passes can test
// depth for equality against the whole-chunk pass.

#include <string>

#include "terrain_shaders.h"

namespace terralod::shaders {

// Vertices: grid x, grid y (cells from the chunk's south-west corner) and metres above the
// chunk's zBase (geomorphed on the CPU); the vertex's own material index, and its splat
// weights as drawn (one-hot, or fading with its position in a blot root), materials 0-3 and
// 4-7; its chunk's slot in its block (vipm_block.h): the layer of the block's textures. A
// block's blots drawn in one call (uBlock 1) take each chunk's corner, zBase and morph from
// per-slot arrays instead of the one chunk's uniforms.
inline constexpr const char* kVipmVertex = R"(#version 450 core
layout(location = 0) in vec3 aPosition;
layout(location = 1) in uint aMaterial;
layout(location = 2) in vec4 aWeights0;
layout(location = 3) in vec4 aWeights1;
layout(location = 4) in uint aSlot;
uniform mat4 uViewProjection;  // eye at the origin
uniform float uEyeHeight;
uniform vec2 uCornerCells;     // chunk corner, grid cells from the frame's anchor (whole)
uniform float uZBase;          // the chunk's zBase (metres)
uniform float uMorph;
uniform int uBlock;            // 1: a block's chunks in one call, by slot as follows
uniform vec2 uSlotCorner[16];
uniform float uSlotZBase[16];
uniform float uSlotMorph[16];
uniform vec2 uEyeCells;        // the eye, grid cells from the anchor
uniform vec2 uSpacing;         // metres per cell
uniform vec2 uGridSize;        // the normal map's texels a side (unclipped)
uniform float uTexelCells;     // grid cells between its texels (1 up to a root)
uniform vec2 uDetailOrigin;    // detail texture coordinate of the chunk's corner
uniform vec2 uDetailScale;     // detail texture coordinate per cell
uniform int uMaterial;         // the material pass's material, -1 in the whole-chunk pass
uniform vec3 uMaterialColors[8];
invariant gl_Position;
out vec3 vRelative;
out float vHeight;
out vec2 vNormalUv;
out vec2 vDetailUv;
out float vWeight;
out vec3 vMaterialColor;
flat out uint vMaterialId;
flat out int vLayer;
flat out float vMorph;
void main() {
  int slot = int(min(aSlot, 15u));
  vec2 corner = uBlock == 1 ? uSlotCorner[slot] : uCornerCells;
  float zBase = uBlock == 1 ? uSlotZBase[slot] : uZBase;
  // A point two chunks share has the same exact sums in both (fan stitching puts it in each
  // chunk's frame exactly), so both round them alike and draw the same edges; a chunk drawn in
  // its block's call sums the same floats as drawn alone.
  precise vec2 grid = aPosition.xy + corner;
  precise float height = aPosition.z + zBase;
  vLayer = slot;
  vMorph = uBlock == 1 ? uSlotMorph[slot] : uMorph;
  vec3 p = vec3((grid - uEyeCells) * uSpacing, height - uEyeHeight);
  vRelative = p;
  vHeight = p.z + uEyeHeight;
  // Texel i's centre is on grid point i uTexelCells.
  vNormalUv = (aPosition.xy / uTexelCells + 0.5) / uGridSize;
  vDetailUv = uDetailOrigin + aPosition.xy * uDetailScale;
  // The weights sum to 1 (to the bytes' rounding).
  vWeight = uMaterial < 0 ? 0.0 : uMaterial < 4 ? aWeights0[uMaterial] : aWeights1[uMaterial - 4];
  vMaterialColor = uMaterialColors[min(aMaterial, 7u)];
  vMaterialId = min(aMaterial, 7u);
  gl_Position = uViewProjection * vec4(p, 1.0);
}
)";

// uPass 0: the whole chunk (depth; black, to which the material passes add), its flanges in
// the material colours lit as level ground (they show only in cracks); 1: a material's
// triangles, weighted by the material's share, added; 2: the wireframe overlay; 3: a blot, the
// whole chunk in one pass coloured by its blot texture (uBlock 1: the block's blots, their
// flanges, from primitive uFlangeFrom on, as in pass 0).
// uMaterialIds 1: a material-ID image instead (VipmImage::kMaterialIds): red holds
// (floor(weight * 31) * 8 + material) / 255, under GL_MAX blending in the material passes, so
// the material with the largest weight wins (ties: the higher index); the whole chunk writes 0
// (as the background), its flanges their provoking vertex's material at weight 1.
inline constexpr const char* kVipmFragment = R"(
in vec3 vRelative;
in float vHeight;
in vec2 vNormalUv;
in vec2 vDetailUv;
in float vWeight;
in vec3 vMaterialColor;
flat in uint vMaterialId;
flat in int vLayer;
flat in float vMorph;
uniform int uPass;
uniform int uBlock;
uniform int uFlangeFrom;
uniform int uMaterialIds;
uniform int uMaterial;
uniform int uFlange;
uniform int uDetailed;        // 0: the material's flat colour instead of its detail texture
uniform sampler2D uDetail;    // unit 0, sRGB
uniform sampler2DArray uNormalMap; // unit 1, the block's: layer vLayer
uniform sampler2DArray uBlot; // unit 2: blots' material colours, one texel a grid point
uniform vec2 uBlotFade;       // materials fade to the blot's colours from x to y metres away
uniform int uColorBy;         // 0 materials, 1 level, 2 morph
uniform int uUnlit;           // 1: the colour as it is, no light
uniform float uLevel;
uniform int uKind;            // uColorBy 3: 0 a leaf, 1 a root, 2 a blot, 3 a block's blot
uniform vec3 uSun;
uniform vec3 uHaze;
uniform float uEyeHeight;
out vec4 fragColor;
// The blot texture's colour here, linear (stored encoded: vipm_blot.h).
vec3 blotColor() { return pow(texture(uBlot, vec3(vNormalUv, vLayer)).rgb, vec3(2.2)); }
// Lit, hazed and encoded for output.
vec3 shade(vec3 base, vec3 n) {
  float diffuse = max(dot(n, uSun), 0.0);
  float sky = 0.30 + 0.20 * n.z;
  vec3 color = uUnlit == 1 ? base : base * (sky + 0.85 * diffuse);
  float through = transmittance(uEyeHeight, vHeight, length(vRelative));
  color = color * through + uHaze * (1.0 - through);
  return pow(color, vec3(1.0 / 2.2));
}
void main() {
  bool flange = uBlock == 1 ? gl_PrimitiveID >= uFlangeFrom : uFlange == 1;
  int pass = uPass == 3 && flange ? 0 : uPass;
  if (pass == 2) {
    fragColor = vec4(0.05, 0.05, 0.05, 1.0);
    return;
  }
  if (uMaterialIds == 1) {
    uint code = uint(floor(clamp(vWeight, 0.0, 1.0) * 31.0)) * 8u + uint(uMaterial);
    if (pass == 0) code = flange ? 248u + vMaterialId : 0u;
    fragColor = vec4(float(code) / 255.0, 0.0, 0.0, 1.0);
    return;
  }
  vec3 n = vec3(0.0, 0.0, 1.0);
  vec3 base;
  float weight = 1.0;
  float toBlot = 0.0;  // a material pass's fade to what the blot draws here
  if (pass == 0) {
    if (!flange) {
      fragColor = vec4(0.0, 0.0, 0.0, 1.0);
      return;
    }
    base = pow(vMaterialColor, vec3(2.2));
  } else {
    vec2 xy = texture(uNormalMap, vec3(vNormalUv, vLayer)).rg * 2.0 - 1.0;
    n = vec3(xy, sqrt(max(0.0, 1.0 - dot(xy, xy))));
    if (pass == 3) {  // a blot: the material colours where the mesh's finest level has them
      base = blotColor();
    } else {
      base = uDetailed == 1 ? texture(uDetail, vDetailUv).rgb : pow(vMaterialColor, vec3(2.2));
      weight = vWeight;
      toBlot = smoothstep(uBlotFade.x, uBlotFade.y, length(vRelative));
    }
  }
  if (uColorBy == 1) base = levelColor(uLevel);
  if (uColorBy == 2) base = mix(vec3(0.15, 0.35, 0.95), vec3(0.95, 0.25, 0.15), vMorph);
  if (uColorBy == 3) base = uKind == 0 ? vec3(0.30, 0.62, 0.25)    // a leaf
                          : uKind == 1 ? vec3(0.22, 0.40, 0.85)    // a root
                          : uKind == 2 ? vec3(0.90, 0.50, 0.12)    // a blot
                                       : vec3(0.70, 0.25, 0.75);  // a block's blot
  vec3 encoded = shade(base, n);
  // Toward the blots every material fades to the blot's colour: the weights sum to one, so the
  // passes add up to mix(splatted, blot, toBlot), which is the blot itself where blots begin.
  if (toBlot > 0.0 && uColorBy == 0) encoded = mix(encoded, shade(blotColor(), n), toBlot);
  fragColor = vec4(weight * encoded, 1.0);
}
)";

inline std::string vipmFragment() {
  return std::string(kLevelPalette) + kAtmosphere + kVipmFragment;
}

}  // namespace terralod::shaders
