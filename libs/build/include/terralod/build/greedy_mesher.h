#pragma once
// An irregular chunk mesh by greedy insertion (Garland and Heckbert's "fast polygonal
// approximation of terrains"): repeatedly insert the sample the current triangulation
// approximates worst, flipping edges towards a Delaunay triangulation, until every sample of
// the rectangle is within the error; then collapse each vertex that sits inside one piece of
// the start (all its edges free) onto a neighbour wherever every sample around it stays
// within the error (and the gap), until none goes: about a third fewer triangles. A vertex
// collapsed onto may move up or down (VertexHeights::kFitted) to the middle of the heights that
// keep every sample of its new star within the error, so more collapses go: 15-25 % fewer again;
// then every such vertex moves to the middle of what its triangles allow and the collapses run
// once more (1.5-3 % fewer).
//
// It starts from the parent chunk's triangles and flips their edges only within the gap:
// every other triangle lies inside one of the parent's, so the chunk's vertices moved onto the
// parent's surface (its morph targets) draw the parent's surface to within the gap. It also keeps
// edges along the lines x, y = k * lineSpacing, the borders of its own children, which in turn
// start from its triangles. Or (GreedyStart::kParentVertices, what chunks below a root use) it
// starts from the parent's vertices (and the parent's edges between them) and inserts wherever
// the gap is broken as wherever the error is, keeping no lines. Each side of the rectangle is
// refined first, alone and from the heights (and the parent's surface) along it only, so two
// chunks sharing a side and the parent's vertices on it choose the same vertices there: no
// T-junctions between chunks of a level.
//
// Pure function: exact integer geometry, ties broken by scan order.

#include <cstdint>
#include <span>
#include <vector>

#include "terralod/build/surface_interpolation.h"

namespace terralod {

/// How chunk meshes are made: right-triangulated irregular networks from the activation grid,
/// or greedy insertion below the blocks (fewer triangles; `terralod build --mesher`).
enum class MeshMethod : uint8_t { kRtin, kGreedy };

/// The gap greedy chunks may keep from their parent's surface when fully morphed, as a
/// fraction of the parent level's error: the largest pop where a chunk splits (at τ pixels of
/// the parent's error on screen, at most this times τ).
inline constexpr double kGreedyMorphGap = 0.125;

/// The largest chunk (cells a side) greedy insertion meshes: its scratch is about 24 bytes a
/// sample (100 MB at 2048 cells, per thread); larger chunks (the roots of rasters read whole
/// beyond 2049²) stay RTIN, and their descendants choose.
inline constexpr int32_t kGreedyMaxChunkCells = 2048;

/// What a greedy mesh starts from before insertion.
enum class GreedyStart : uint8_t {
  /// The parent's triangles cut along the rectangle and the lines (which they must cross only
  /// at grid points): every triangle inside one of the parent's, so the morph gap holds by
  /// construction, and the parent must keep the lines its descendants cut along.
  kParentTriangles,
  /// The rectangle's two triangles with every parent vertex in it inserted; insertion then
  /// goes on until the gap holds at every sample too. Asks nothing of the parent's edges, so
  /// no chunk needs lines for its descendants and a coarse chunk is not held to two triangles
  /// per leaf square.
  kParentVertices,
  /// The same, with every parent edge that lies in the rectangle made an edge again (by flips)
  /// and kept as a parent's edge: fewer insertions where the parent is itself a greedy mesh.
  kParentVerticesAndEdges,
};

/// The heights a greedy mesh gives its vertices.
enum class VertexHeights : uint8_t {
  kSamples,  ///< each vertex at its sample's height
  /// Vertices off the rectangle's sides wherever a collapse needs them (within the bound of
  /// every sample around): 15-25 % fewer triangles. Those on the sides stay at their samples'
  /// heights, which the neighbours sharing the side have too.
  kFitted,
};

struct GreedyMeshInput {
  int32_t width = 0, height = 0;  ///< cells; samples are (width+1) x (height+1), row-major
  std::span<const double> heights;
  /// The parent's triangles, three corners each, in sample coordinates: they cover the
  /// rectangle (they may reach beyond it), and cross its sides and the lines below only at grid
  /// points (true of bintree triangles and of greedy meshes made with those lines).
  std::span<const SurfaceCorner> parent;
  int32_t lineSpacing = 0;  ///< > 0: edges kept along x, y = k * lineSpacing inside
  double error = 0.0;
  /// The parent's surface at every sample (its triangles interpolated), and how far the mesh
  /// with its vertices on that surface may be from it: a parent edge may flip, and every
  /// triangle must keep to this gap and, so drawn, within parentError of the heights. Empty
  /// or 0: the parent's edges never flip (and the parent's own bound holds).
  std::span<const double> parentHeights;
  double gap = 0.0;
  double parentError = 0.0;
  /// False at a root, whose "parent" is its own heights: its vertices do not morph, so the
  /// gap only decides which of the start's edges may flip.
  bool verticesMorph = true;
  VertexHeights vertexHeights = VertexHeights::kFitted;
  /// Used where vertices morph (a root always starts from its "parent" triangles).
  GreedyStart start = GreedyStart::kParentTriangles;
};

struct GreedyMesh {
  std::vector<int32_t> x, y;        ///< vertices, in sample coordinates
  std::vector<double> z;            ///< their heights (VertexHeights)
  std::vector<uint32_t> triangles;  ///< counter-clockwise (x east, y north)
};

GreedyMesh greedyMesh(const GreedyMeshInput& input);

/// The largest |surface - height| over every sample minus the error (<= 0: the mesh holds
/// its bound; infinite where a sample is not covered). For tests; rasterises every triangle.
double greedyMeshViolation(const GreedyMeshInput& input, const GreedyMesh& mesh);

}  // namespace terralod
