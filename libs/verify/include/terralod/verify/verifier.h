#pragma once
// `terralod verify`: checks a tileset against its source, independently of the builder's
// bookkeeping. Every chunk is decoded from the file as a renderer would; its triangles are
// rasterised over the source samples to measure the true error; the fully morphed surface is
// compared with the parent's; every pair of chunks that can meet across a border (at any
// levels) is checked for a crack their skirts would not cover; checksums are checked on read.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "terralod/core/progress.h"
#include "terralod/core/result.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/raster/dem_reader.h"
#include "terralod/raster/heightfield.h"

namespace terralod {

struct VerifyOptions {
  unsigned threads = 0;  ///< 0 = all hardware threads
  size_t maxListedFailures = 20;
  /// VIPM tilesets built with --materials: the categorical raster (and palette) they came
  /// from, to check vertex materials against; empty: checked against the stored ones only.
  std::string materialsPath, palettePath;
};

/// LODs verify rasterises at most of a VIPM node above the roots (its finest, its coarsest and
/// evenly spaced ones between): such a node spans up to 32768² samples, too many to check at
/// each of its thousands of LODs.
inline constexpr uint32_t kVipmUpperLevelsVerified = 6;

/// What verify checked in a VIPM tileset (docs/format.md "VIPM tilesets") beyond the levels.
struct VipmVerifyStats {
  uint64_t lods = 0;                 ///< chunk levels of detail checked, over all chunks
  double worstErrorMargin = 0;       ///< smallest (recorded - true error) over every LOD
  uint64_t collapsesChecked = 0;     ///< collapses checked against the material rules
  uint64_t ruleViolations = 0;       ///< collapses breaking one (a failure when promised)
  bool rulesPromised = true;         ///< the tileset was built with the rules
  bool materialsFromSource = false;  ///< vertex materials compared with the source's
  uint64_t materialMismatches = 0;
  uint64_t partLevelsChecked = 0;   ///< LODs at which every material's part was compared
  uint64_t fallbackSamples = 0;     ///< root samples compared with the children's coarsest LOD
  double fallbackMismatch = 0;      ///< largest difference there
  uint64_t flangePairs = 0;         ///< chunk pairs checked across a side
  double worstFlangeMargin = 0;     ///< smallest (flange depth - largest gap), metres
  uint64_t normalMapsChecked = 0;   ///< nodes whose normal map was compared with the source
  uint64_t normalTexels = 0;        ///< texels compared there
  double worstNormalDeviation = 0;  ///< largest |stored - source| normal component (BC5 loss)
  uint64_t upperNodes = 0;          ///< nodes above the roots (at kVipmUpperLevelsVerified LODs)
  uint64_t upperJoins = 0;          ///< of those, whose finest points are their children's coarsest
};

struct LevelCheck {
  double bound = 0;             ///< the level's promised error
  double maxError = 0;          ///< largest |source - surface| found at a sample
  uint64_t samples = 0;         ///< source samples compared (each once per level)
  uint64_t uncovered = 0;       ///< samples no triangle of the level covers
  double maxMorphMismatch = 0;  ///< largest |fully morphed surface - parent surface|
  double heightStep = 0;        ///< the level's height quantisation step (zStep)
  /// What maxMorphMismatch may reach (levels below the roots): half the level's height step
  /// plus half its parent level's, plus kVerifySlack. A chunk's morph targets are its parent's
  /// exact surface at its vertices, rounded to the chunk's step (off by <= step/2); the parent
  /// draws its own vertices rounded to its step (off by <= parent step/2); the chunk refines
  /// its parent, so between vertices both are linear over the same triangles. Where the
  /// metadata has a "morph_gap" (`build --mesher greedy`), plus that times the parent level's
  /// error.
  double morphTolerance = 0;
};

/// Metres of floating-point slack in every comparison verify makes.
inline constexpr double kVerifySlack = 1e-6;

struct VerifyReport {
  std::vector<LevelCheck> levels;
  double morphGap = 0;  ///< the metadata's "morph_gap" (0: chunks refine their parents)
  uint64_t chunks = 0;
  uint64_t skirtPairs = 0;              ///< chunk pairs checked across borders
  uint64_t skirtSamples = 0;            ///< border samples checked
  double worstSkirtMargin = 0;          ///< smallest (skirt depth - largest possible step), metres
  std::optional<VipmVerifyStats> vipm;  ///< VIPM tilesets
  std::vector<std::string> failures;
  uint64_t failureCount = 0;
  bool ok() const { return failureCount == 0; }
};

/// How to open the tileset's source the way it was built (encoding, band, vertical scale).
DemOpenOptions tilesetDemOptions(const TilesetReader& tileset);

/// The source raster read the way the tileset's metadata says it was built (same encoding and
/// vertical scale), with its voids filled as the builder fills them and the tileset's recorded
/// edits ("edits", `terralod edit`) applied. Fails naming the source when it cannot be read or
/// is not the size the tileset was built from.
Result<Heightfield> loadTilesetSource(const TilesetReader& tileset, const std::string& sourcePath);

/// Verifies `tilesetPath` against `sourcePath` (read the way the tileset's metadata says it
/// was built: same encoding and vertical scale).
Result<VerifyReport> verifyTileset(const std::string& tilesetPath, const std::string& sourcePath,
                                   const VerifyOptions& options, Progress& progress);

}  // namespace terralod
