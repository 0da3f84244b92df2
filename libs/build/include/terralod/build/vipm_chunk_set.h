#pragma once
// A VIPM tileset's chunks in memory with the heights and materials they are built from
// (docs/architecture.md "Edits"). `build` makes every chunk (or keeps an earlier build's where
// no new stroke reaches, BuildOptions::reuse); `apply` then takes more strokes and builds again
// only the chunks they reach, so an editor can swap those in while it draws; buildVipmTileset
// writes the set as a tileset. The bytes are those of a build of the edited source.

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "terralod/build/builder.h"
#include "terralod/build/tree_layout.h"
#include "terralod/core/progress.h"
#include "terralod/format/node_bytes.h"
#include "terralod/format/tileset_format.h"
#include "terralod/materials/material.h"
#include "terralod/raster/heightfield.h"

namespace terralod {

struct VipmChunkSetState;

/// A node as drawn while a stroke's chunks are made again (VipmChunkSet::apply).
struct VipmInterimNode {
  uint32_t node = 0;
  NodeRecord record;
  NodeBytes bytes;
};
/// Receives a stroke's interim nodes, on the thread that applies it.
using VipmInterimSink = std::function<void(std::vector<VipmInterimNode>)>;
/// Receives a stroke's leaves and 128-cell nodes as made, with the level errors to draw them
/// at (those above the roots as before), on the thread that applies it.
using VipmNearSink =
    std::function<void(std::vector<VipmInterimNode>, const std::vector<double>& levelErrors)>;

/// Levels above the 128-cell roots at most: their top nodes are at most 32768 cells (version 2
/// VIPM blobs).
inline constexpr int32_t kVipmMaxUpperLevels = 8;

/// A VIPM tileset's tree over the DEM's cells: 64-cell leaves under 128-cell nodes (the
/// roots of the flat forest), and `upperLevels` levels of nodes above those (or
/// kVipmUpperLevelsAuto, kVipmUpperLevelsBySize), so that its top nodes are 128 <<
/// upperLevels cells. The leaves are at level depth, the 128-cell nodes at depth - 1.
TreeLayout vipmTreeLayout(const DemInfo& info, int32_t upperLevels = 0);

class VipmChunkSet {
 public:
  /// Builds every chunk of `heights` (void-filled, options.edits applied) and `materials`
  /// (paint applied) with `options` (zStep, rules, blot error, compression; options.reuse:
  /// chunks kept). Fails when the heights' relief needs a step coarser than --max-error.
  /// `filledVoids`: how many source samples were voids (recorded in the header). Fails where
  /// nodes above the roots would hold too many vertices (terrain too rough for their errors),
  /// unless options.vipmUpperLevels is chosen by size: then the levels from that one up are
  /// left out, and `warn` says so.
  static Result<VipmChunkSet> build(
      const BuildOptions& options, const DemInfo& info, Heightfield heights, MaterialMap materials,
      uint64_t filledVoids, Progress& progress,
      const std::function<void(const std::string&)>& warn = [](const std::string&) {});
  VipmChunkSet(VipmChunkSet&&) noexcept;
  VipmChunkSet& operator=(VipmChunkSet&&) noexcept;
  ~VipmChunkSet();

  /// Applies `strokes` to the heights and materials and builds again every chunk they reach
  /// (all of a level when its level error changes, everything when the tileset's height
  /// step does). Returns the nodes whose bytes or record changed, in node order. Fails, with
  /// nothing changed, when a stroke paints a material the set does not have or the relief
  /// outgrows 16-bit heights at --max-error.
  ///
  /// With `interim`, first hands it every leaf and 128-cell node the strokes reach as its
  /// whole grid (buildVipmGridChunk, with its new normal map; record as before but for its
  /// mesh fields), before the slow part: an editor draws those at once, at full resolution,
  /// until the chunks are made (nodes above them keep their old meshes meanwhile). Not when
  /// the height step changes (then every chunk is made again).
  ///
  /// With `near`, on a tileset with nodes above the 128-cell ones, hands it the leaves and
  /// 128-cell nodes that changed as soon as they are made (milliseconds), before the nodes
  /// above them (seconds: their collapses are measured over thousands of cells); returns only
  /// what changed after that.
  Result<std::vector<uint32_t>> apply(std::span<const TerrainEdit> strokes, unsigned threads,
                                      const VipmInterimSink& interim = {},
                                      const VipmNearSink& near = {});

  /// Node records in tileset order (mesh fields and flange depths; no blob offsets).
  const std::vector<NodeRecord>& nodes() const;
  /// How many times `node`'s bytes were made again since the build (0: as built); a node
  /// changed with the same count changed only its record (a flange depth, a level's error).
  uint32_t bytesVersion(uint32_t node) const;
  /// A node's mesh blob followed by its texture blob (the normal map), as a tileset stores
  /// them.
  NodeBytes nodeBytes(uint32_t node) const;
  const std::vector<TerrainEdit>& edits() const;
  double zStep() const;
  /// Per level, top first: its error (the tileset header's levelError).
  const std::vector<double>& levelErrors() const;
  const TreeLayout& layout() const;
  const MaterialMap& materials() const;
  /// The options it was built with, their edits every stroke applied since.
  const BuildOptions& options() const;
  const DemInfo& info() const;
  /// Build figures: collapses, chunks kept, per-leaf CPU seconds (median, max) of those built,
  /// filled voids.
  const BuildSummary& summary() const;

 private:
  explicit VipmChunkSet(std::unique_ptr<VipmChunkSetState> state);
  std::unique_ptr<VipmChunkSetState> mState;
};

}  // namespace terralod
