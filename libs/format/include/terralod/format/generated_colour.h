#pragma once
// The generated colour: what a textured tileset without a draped image shows, a function of the
// ground's height, slope and latitude and of two things only the full-resolution heights know,
// water and a baked occlusion term (docs/format.md "Version 6").
//
// The colour is a fixed palette in metres (green lowland, tan hills, brown and grey rock), bare
// rock on steep slopes, snow above the latitude's snow line (snowLine) on ground flat enough to
// hold it, darkened hollows, and water (kWaterColor). The build finds water and occlusion
// (build/surface_texels.h) and stores them as a shade layer (shadeValue); the renderer's shader
// makes the colour from it, the drawn height and the normal map (shadedColour is its CPU twin,
// for exports), or, with `build --bake-colour` or under a draped image, the build stores the
// colour itself.

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

namespace terralod {

/// A display-value (gamma 2.2) colour, each channel 0..1.
struct GroundColor {
  float r, g, b;
};

/// Water (sea and lakes, whatever their depth).
constexpr GroundColor kWaterColor{0.302f, 0.471f, 0.620f};
/// Snow, and bare rock (steep ground at any height).
constexpr GroundColor kSnowColor{0.968f, 0.972f, 0.982f};
constexpr GroundColor kBareRockColor{0.695f, 0.667f, 0.644f};

/// The palette by height in metres, linear between stops; below the first and above the last,
/// the end colours.
struct PaletteStop {
  float height;
  GroundColor color;
};
inline constexpr PaletteStop kGroundPalette[] = {
    {0, {0.553f, 0.682f, 0.451f}},     // coastal lowland, green
    {300, {0.600f, 0.710f, 0.482f}},   // lowland
    {800, {0.698f, 0.737f, 0.541f}},   // hills, olive
    {1500, {0.769f, 0.741f, 0.580f}},  // uplands, tan
    {2300, {0.722f, 0.655f, 0.553f}},  // mountains, brown
    {3200, {0.690f, 0.659f, 0.631f}},  // high rock, grey
    {5000, {0.761f, 0.741f, 0.722f}},  // the highest rock, lighter
};
/// Metres from the snow line to full cover.
inline constexpr float kSnowBand = 400.0f;
/// Steep ground turns to bare rock between these slopes (1 - n_z).
inline constexpr float kRockSlopeStart = 0.45f, kRockSlopeEnd = 0.75f;
/// The occlusion term darkens linear light down to this (hollows) from 1 (open ground).
inline constexpr float kMinOcclusion = 0.6f;
/// Shade values: land lies in [kLandShade, 1] (kMinOcclusion .. 1), water is 0.
inline constexpr float kLandShade = 0.75f;

/// Latitude assumed where the raster's place on Earth is unknown (degrees).
constexpr double kUnknownLatitude = 45.0;

/// The climatic snow line in metres at a latitude in degrees (NaN: kUnknownLatitude):
/// 5200 m · cos(latitude)^1.5, a simple fit to the observed line — about 5–5.5 km in the
/// tropics (higher in the dry subtropical Andes, which this ignores), 2.8–3 km in the Alps at
/// 46°, 1–1.5 km in Norway and Alaska at 60–65°, a few hundred metres on Svalbard at 78° —
/// falling to 0 m at the poles, where glaciers reach the sea. Latitude is clamped to ±90°.
double snowLine(double latitudeDeg);

/// Snow cover 0..1 of flat ground at `height` metres: none up to the snow line, whole 400 m
/// above it (smoothstep).
float snowCover(double height, double latitudeDeg);

/// The generated colour of dry ground (not water) at `height` metres, `slope` = 1 - n_z
/// (0 flat, 1 vertical), at `latitudeDeg`, before the occlusion term: the palette by height,
/// snow by snowCover, then bare rock on slopes steeper than about 45°.
GroundColor groundColor(double height, float slope, double latitudeDeg);
/// groundColor for a snow line already worked out.
GroundColor groundColorBelow(float height, float slope, float snowLine);

/// The shade layer's value of a texel: 0 for water, else kLandShade .. 1 for occlusion
/// kMinOcclusion .. 1. Inline: the build calls it for every texel of every leaf.
inline float shadeValue(bool water, float occlusion) {
  if (water) return 0.0f;
  const float t = std::clamp((occlusion - kMinOcclusion) / (1.0f - kMinOcclusion), 0.0f, 1.0f);
  return kLandShade + (1.0f - kLandShade) * t;
}

/// The colour a shade texel (filtered or not) stands for on ground at `height` with `slope`
/// under `snowLine`, in display values: land darkened by its occlusion, mixed with water where
/// the value is below kLandShade (a texel filtered from water and land). The shader's
/// generatedColour is the same function.
GroundColor shadedColour(float height, float slope, float snowLine, float shade);

/// The snow lines a renderer interpolates: kSnowLineSamples values at evenly spaced grid rows,
/// the first at row 0 and the last at the last row, from each row's latitude (south first;
/// empty: kUnknownLatitude everywhere).
inline constexpr size_t kSnowLineSamples = 33;
std::vector<float> snowLineSamples(std::span<const double> rowLatitudes, uint32_t rows);
/// The snow line at fraction t (0 first row, 1 last) of `samples`, linearly interpolated.
float snowLineAt(std::span<const float> samples, double t);

}  // namespace terralod
