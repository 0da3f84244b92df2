#pragma once
// `terralod build`: a DEM in, a tileset out.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "terralod/build/greedy_mesher.h"
#include "terralod/core/progress.h"
#include "terralod/core/result.h"
#include "terralod/core/terrain_edit.h"
#include "terralod/format/chunk_codec.h"
#include "terralod/raster/dem_reader.h"
#include "terralod/vipm/collapse_order.h"

namespace terralod {

/// Whether chunks store texels their parent's texture already holds (TextureLevel::inherited).
enum class TextureSharing {
  kInherit,     ///< the default: such chunks draw their parent's texture (format version 5)
  kEveryChunk,  ///< --texture-per-chunk: every chunk stores its own (what sharing saves)
};

/// Where the generated colour (no draped image) is made (format/generated_colour.h).
enum class GeneratedColour {
  kShader,  ///< the default: chunks store a shade layer, the shader makes the colour (version 6)
  kBaked,   ///< --bake-colour: chunks store the colour itself (version 5)
};

/// How static chunks store their geometry (`--chunk-codec`, docs/format.md "Version 7").
enum class ChunkCodec {
  kBintree,  ///< the default: RTIN chunks as their bintree's splits and height residuals (7)
  kMeshopt,  ///< every chunk as meshoptimizer vertex and index streams (versions 4 to 6)
};

/// Whether the raster is read whole into memory or streamed in windows.
enum class Streaming {
  kAuto,    ///< stream plain rasters over BuildOptions::streamAboveSamples (16 M) or over the
            ///< memory budget, load the rest (RGB-encoded tiles are always loaded); a streamed
            ///< raster within the budget is kept by pass 1 for pass 2 (decoded once)
  kAlways,  ///< always stream (the path huge rasters take; slower for small ones)
  kNever,   ///< always load whole; fails over the memory budget
};

/// What kind of chunks a build writes (docs/format.md).
enum class TilesetKind : uint8_t {
  kStatic,  ///< the chunked LOD tree of static RTIN meshes (mesh kind 1)
  kVipm,    ///< progressive meshes per 64-cell chunk under blot roots (mesh kind 2)
};

/// VIPM only: where the leaves stop simplifying (with the material rules) and the 128-cell
/// roots take over, at twice it, as blot chunks (simplified further without the rules).
struct BlotError {
  enum class Mode : uint8_t {
    kTimesMaxError,  ///< `value` × the build's --max-error (the default: 4×)
    kMetres,         ///< `value` metres
    kOff,            ///< leaves simplify as far as the rules allow; roots take over at twice
                     ///< the largest error that reaches
  };
  Mode mode = Mode::kTimesMaxError;
  double value = 4.0;

  static BlotError metres(double m) { return {Mode::kMetres, m}; }
  static BlotError off() { return {Mode::kOff, 0.0}; }
  /// The leaves' last error in metres for a build at `maxError`; infinity when off.
  double leafError(double maxError) const;
};

/// BuildOptions::vipmUpperLevels: as many levels as make one top node.
inline constexpr int32_t kVipmUpperLevelsAuto = -1;
/// BuildOptions::vipmUpperLevels, the default: kVipmUpperLevelsAuto for maps of more than
/// kVipmFlatRootsMax 128-cell roots, none for smaller ones (whose roots all stay resident in
/// little memory: 256 roots of the 8193² synth are 83 MB, a sixth of the default budget).
inline constexpr int32_t kVipmUpperLevelsBySize = -2;
inline constexpr int64_t kVipmFlatRootsMax = 256;

struct BuildOptions {
  std::string input;
  std::string output;
  DemOpenOptions dem;
  double maxError = 1.0;     ///< leaf level geometric error in metres
  int32_t chunkCells = 0;    ///< leaf chunk side in cells; 0 = automatic
  unsigned threads = 0;      ///< 0 = all hardware threads
  uint64_t memoryMB = 2048;  ///< above this the input is read in windows, never whole
  int compressionLevel = kDefaultChunkCompressionLevel;  ///< zstd level for chunk blobs
  Streaming streaming = Streaming::kAuto;
  uint64_t streamAboveSamples = uint64_t{1} << 24;  ///< kAuto's threshold (tests lower it)
  int32_t blockCells = 512;                         ///< side of the blocks both passes work in
  /// Chunk meshes below the blocks: RTIN or greedy insertion (`--mesher`).
  MeshMethod mesher = MeshMethod::kRtin;
  bool textures = true;      ///< colour and normal-map tiles per chunk (format version 2)
  std::string textureImage;  ///< draped image; empty: the generated colour
  double textureTau = 2.0;   ///< --min-tau: the τ the texture resolution is sized for
  TextureSharing textureSharing = TextureSharing::kInherit;
  GeneratedColour generatedColour = GeneratedColour::kShader;
  ChunkCodec chunkCodec = ChunkCodec::kBintree;
  TilesetKind kind = TilesetKind::kStatic;
  // VIPM only (kind kVipm):
  std::string materialsPath;  ///< categorical raster; empty: classify the DEM
  std::string palettePath;    ///< JSON palette naming the raster's classes (optional)
  MaterialRules materialRules = MaterialRules::kOn;
  BlotError blotError;
  /// Levels of nodes above the 128-cell roots (256, 512, ... cells; --upper-levels): N,
  /// kVipmUpperLevelsAuto (as many as make one top node, at most kVipmMaxUpperLevels) or
  /// kVipmUpperLevelsBySize (the default: auto for maps of more than kVipmFlatRootsMax roots,
  /// none below).
  int32_t vipmUpperLevels = kVipmUpperLevelsBySize;
  /// Brush strokes applied to the heights and materials before anything is built, and
  /// recorded in the metadata ("edits"; `terralod edit`).
  std::vector<TerrainEdit> edits;
  /// VIPM: an earlier build of the same source with the same options and a prefix of `edits`
  /// (the tileset an edit replaces). Its chunks that the other strokes do not reach are kept as
  /// they are; the result is the same bytes as a build without it. Empty: build every chunk.
  std::string reuse;
};

struct BuildSummary {
  int32_t levels = 0;
  uint64_t chunks = 0;
  uint64_t vertices = 0;   ///< surface vertices over all chunks
  uint64_t triangles = 0;  ///< surface triangles over all chunks
  uint64_t skirtTriangles = 0;
  uint64_t fileBytes = 0;
  uint64_t filledVoids = 0;
  uint64_t sourceSamples = 0;
  bool streamed = false;     ///< the raster was read in windows, never whole
  bool readOnce = false;     ///< streamed, and pass 1 kept the samples for pass 2 (within budget)
  uint64_t keptSamples = 0;  ///< read once, RTIN: the samples pass 1 kept (KeptHeights)
  int errorPasses = 0;       ///< 2 when the streamed height range estimate was too small
  double loadSeconds = 0, errorSeconds = 0, meshSeconds = 0, totalSeconds = 0;
  uint64_t trianglesScanned = 0, trianglesBounded = 0;
  uint64_t textureBytes = 0;   ///< texture blobs over all chunks
  uint32_t textureRefine = 0;  ///< draped image texels per DEM cell (0: generated colour)
  // VIPM builds:
  uint64_t collapses = 0;         ///< runtime collapses over all leaves
  uint32_t materials = 0;         ///< materials in the tileset
  double chunkSecondsMedian = 0;  ///< per leaf chunk: collapse order to encoded blob
  double chunkSecondsMax = 0;
  uint64_t reusedChunks = 0;  ///< chunks kept from BuildOptions::reuse
};

/// Builds `options.output` from `options.input` (a VIPM tileset when options.kind says so:
/// buildVipmTileset). Warnings (e.g. assumed spacing) go to `warn`.
Result<BuildSummary> buildTileset(const BuildOptions& options, Progress& progress,
                                  const std::function<void(const std::string&)>& warn);

}  // namespace terralod
