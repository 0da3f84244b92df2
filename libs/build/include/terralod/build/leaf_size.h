#pragma once
// The leaf chunks' size when the user does not choose one (`--chunk-cells`), from the
// terrain's roughness at the requested error.
//
// A chunk costs a node record, a blob's headers, skirts along its sides and a draw call
// whatever it holds. Smooth terrain at a metre holds a few dozen triangles per 64-cell chunk,
// where those fixed costs are most of the file and of the frame; rough terrain holds hundreds,
// where bigger chunks would draw many more triangles than the view needs. So the leaves are
// made as small as they can be (64 cells) while they still hold kTargetLeafTriangles each on
// average, and larger (128, 256 cells) where they would not. The average comes from pass 1
// itself run on a few blocks spread over the raster (`estimateLeafTriangles`).

#include <cstdint>

#include "terralod/core/result.h"

namespace terralod {

class DemReader;
struct BuildOptions;

/// Average surface triangles per leaf chunk the automatic size aims at, at least. Measured on
/// llvmpipe, a chunk costs about as much frame time as 50 triangles; at 100 the rough 8193²
/// synth (159 per 64-cell leaf) keeps 64-cell leaves, which its low passes draw 1.65× faster
/// than 128-cell ones, and the smooth one (18) gets 256-cell leaves, 12 % faster than 64.
inline constexpr double kTargetLeafTriangles = 100.0;

/// The automatic leaf size for roots of `rootCells` cells whose leaf meshes hold
/// `trianglesPer64` triangles per 64 x 64 cells: 64 · 2^k for the smallest k with
/// trianglesPer64 · 4^k >= kTargetLeafTriangles, at most 256 and at most rootCells / 8 (a tree
/// of at least four levels), never below 64. Pure.
int32_t automaticLeafCells(int32_t rootCells, double trianglesPer64);

struct LeafTriangleEstimate {
  double trianglesPer64 = 0;  ///< estimated leaf triangles per 64 x 64 cells
  int32_t blocks = 0;         ///< sample blocks measured (0: none fitted, no estimate)
};

/// Runs pass 1 on up to 16 blocks of 256 cells spread over the raster (blocks with voids are
/// skipped) and counts the points the leaf level keeps: twice that is about its triangles.
/// The blocks run on `threads` workers (the same estimate for any number).
Result<LeafTriangleEstimate> estimateLeafTriangles(const DemReader& reader, double maxError,
                                                   unsigned threads = 1);

/// options.chunkCells when set; else, for static tilesets whose roots (makeTreeLayout with 0)
/// have room for 128-cell leaves in four levels, automaticLeafCells from
/// estimateLeafTriangles; else 0, which leaves the choice to makeTreeLayout (at most 64 cells;
/// VIPM tilesets have their own fixed leaves).
Result<int32_t> leafCellsFor(const BuildOptions& options, const DemReader& reader);

}  // namespace terralod
