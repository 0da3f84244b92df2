#pragma once
// A staged build's plan (WORK/plan.json, docs/format.md "Staged build work directory"): the
// build's options, what the source raster is, the height range its error budget is made for,
// and the blocks every job works through. The plan stage writes it; every other stage reads it
// and derives the rest (tree layout, budget, node list) from it the way a local build does, so
// that the bytes match.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "terralod/build/builder.h"
#include "terralod/core/result.h"

namespace terralod {

inline constexpr int kBuildPlanVersion = 6;

/// What the stages need to know of the DEM and the draped image besides their samples, found
/// once by the plan stage: the stages that read no raster (reduce, coarse, assemble, and pass 2
/// of a build whose pass 1 kept the heights) then open neither, and can run in a program
/// without GDAL (`terralod-stage`).
struct SourceFacts {
  DemInfo info;
  std::vector<double> rowLatitudes;  ///< DemReader::gridRowLatitudes (empty: unknown)
  uint32_t imageRefine = 0;          ///< the draped image's texels per cell (0: no image)
};

struct BuildPlan {
  BuildOptions options;  ///< input, output and texture paths absolute
  SourceFacts source;
  int32_t blockCells = 512;
  /// The range the error budget is made for: the data's own (`exactRange`, what a local build
  /// that reads the raster whole uses) or an estimate that the reduce checks (a streamed
  /// build's first attempt; `attempt` 1 is the second, with the range pass 1 found).
  double heightLo = 0, heightHi = 0;
  bool exactRange = false;
  int attempt = 0;
  int jobs = 1;  ///< block jobs of pass 1 and pass 2
  /// Blocks holding data, as (column, row) of the block grid, in the order their chunks are
  /// written (the block-level nodes' order).
  std::vector<std::array<int32_t, 2>> blocks;

  /// The blocks job `job` works on: [first, last).
  std::array<size_t, 2> jobBlocks(int job) const {
    const size_t n = blocks.size();
    return {n * size_t(job) / size_t(jobs), n * size_t(job + 1) / size_t(jobs)};
  }
};

std::string buildPlanJson(const BuildPlan& plan);
/// `subject` names the file in errors.
Result<BuildPlan> parseBuildPlan(const std::string& text, const std::string& subject);

}  // namespace terralod
