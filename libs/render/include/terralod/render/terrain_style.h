#pragma once
// How the terrain is drawn: colours, overlays and light. A value every pass of a frame reads
// (frame_context.h).

#include <array>
#include <cstdint>

namespace terralod {

/// kKind: by chunk kind (VIPM leaves, VIPM roots, VIPM blots, VIPM blots drawn in their
/// super-chunk's call; static chunks grey).
enum class ColorBy { kRelief, kLevel, kMorph, kKind };

/// How VIPM chunks close their borders (the static kind always hangs skirts): flanges hanging
/// below every border, or fans that replace the border triangles so both sides draw the same
/// edges (vipm_fans.h). `skirts` false leaves out both (shows the cracks).
enum class VipmStitch : uint8_t { kFlanges, kFans };

/// Far VIPM chunks as blots (vipm_blot.h): on; kFadeOnly fades the materials as kOn does but
/// draws no chunk as a blot (what a blot replaces: bench measures the switch against it);
/// off, every chunk one pass per material at every distance.
enum class VipmBlots : uint8_t { kOn, kFadeOnly, kOff };

/// Lit: the surface colour lit by the sun and the sky. Unlit: the colour as it is, no light
/// (for colour that already carries its light, such as aerial or satellite imagery: how 3D
/// Tiles clients draw KHR_materials_unlit content; the haze still applies).
enum class Shading : uint8_t { kLit, kUnlit };

/// VIPM blots of one super-chunk (4 × 4 chunks of a level sharing GPU storage, vipm_block.h)
/// drawn in one call (kOn), or each chunk in its own (kOff).
enum class VipmSuperChunks : uint8_t { kOn, kOff };

struct TerrainStyle {
  ColorBy colorBy = ColorBy::kRelief;
  Shading shading = Shading::kLit;
  bool wireframe = false;  ///< draw triangle edges over the surface
  bool skirts = true;
  VipmStitch stitch = VipmStitch::kFlanges;
  /// VIPM chunks far enough that a grid cell covers less than blotCellPixels pixels are drawn
  /// as blots, in one pass with their materials' average colours; from half that distance on,
  /// the materials fade to those colours.
  VipmBlots blots = VipmBlots::kOn;
  double blotCellPixels = 1.0;
  VipmSuperChunks superChunks = VipmSuperChunks::kOn;
  bool textures = true;     ///< false: ignore chunk textures, light from the drawn geometry
  bool sky = true;          ///< false: empty pixels keep exactly the background colour
  bool chunkBoxes = false;  ///< outline each drawn chunk's bounding box, coloured by level
  std::array<uint8_t, 3> background{0x9C, 0xC3, 0xE6};  ///< sRGB; the sky overhead
  double sunAzimuthDegrees = 315.0;                     ///< clockwise from north
  double sunElevationDegrees = 40.0;
  /// Aerial perspective: scales how much the air hazes what lies behind it (0: no haze).
  /// The haze follows the air a ray crosses in an exponential atmosphere (atmosphere.h).
  double haze = 1.0;
};

}  // namespace terralod
