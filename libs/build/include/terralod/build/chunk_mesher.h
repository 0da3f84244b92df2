#pragma once
// Turns the activation grid into one chunk's mesh: the RTIN of the chunk's square at its level's
// threshold (corners always kept), clipped to the data rectangle, with per-vertex morph
// targets (the parent level's surface at the vertex) and skirts along every side that can meet
// another chunk. Exact grid arithmetic; heights in metres.
//
// With MeshMethod::kGreedy, levels from a given one down are instead meshed by greedy
// insertion (greedy_mesher.h) over every sample of the chunk, within the level's bound and,
// while geomorphing, its parent's (the parent's surface is rebuilt or kept from the chunk
// built before). The RTIN levels above give the first greedy level its parent surface; a
// greedy root (first level 0) starts from its rectangle and does not morph, and every other
// greedy chunk starts from its parent's vertices (GreedyStart::kParentVertices).

#include <array>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include "terralod/build/activation_grid.h"
#include "terralod/build/error_budget.h"
#include "terralod/build/greedy_mesher.h"
#include "terralod/build/height_source.h"
#include "terralod/build/surface_interpolation.h"
#include "terralod/build/tree_layout.h"
#include "terralod/core/bintree.h"
#include "terralod/core/touched_index.h"

namespace terralod {

struct MeshVertex {
  int32_t x = 0, y = 0;      ///< grid point (global)
  double z = 0.0;            ///< height at this level
  double morphTarget = 0.0;  ///< the parent level's surface height here (= z at the roots)
};

enum ChunkSide { kSouth = 0, kEast = 1, kNorth = 2, kWest = 3 };

struct ChunkMesh {
  int32_t level = 0, ix = 0, iy = 0;
  int32_t x0 = 0, y0 = 0, side = 0;  ///< the chunk's square in grid cells
  int32_t dataX = 0, dataY = 0;      ///< cells of the square inside the data (at most side)
  std::vector<MeshVertex> vertices;  ///< surface vertices first, then skirt bottoms
  uint32_t surfaceVertexCount = 0;
  std::vector<uint32_t> surfaceIndices;  ///< triangles, counter-clockwise seen from above
  std::vector<uint32_t> skirtIndices;    ///< triangles hanging from the sides
  std::array<double, 4> skirtDepth{};    ///< per ChunkSide; 0 where there is no skirt
  double minZ = 0.0, maxZ = 0.0;         ///< surface over the whole morph range
  /// RTIN chunks: the walk's decision at each splittable triangle (RtinDecision bits), what
  /// payload version 3 stores; empty for greedy chunks.
  std::vector<uint8_t> rtinDecisions;
  MeshMethod method = MeshMethod::kRtin;  ///< how it was made
};

/// A built chunk's surface triangles (grid points and heights), for its children's morphs.
struct ChunkSurface {
  int32_t level = -1, ix = 0, iy = 0;
  std::vector<SurfaceCorner> corners;  ///< three per triangle
  MeshMethod method = MeshMethod::kRtin;
};
/// The surface of a built chunk.
ChunkSurface surfaceOf(const ChunkMesh& mesh);

/// Surfaces built once and read by every mesher: a greedy build's levels at and above the
/// blocks, meshed top-down before the blocks when every height is at hand. Filled between
/// the meshers' uses, never during.
class SurfaceStore {
 public:
  void add(ChunkSurface surface);
  const ChunkSurface* find(int32_t level, int32_t ix, int32_t iy) const;

 private:
  static uint64_t key(int32_t level, int32_t ix, int32_t iy) {
    return (uint64_t(uint32_t(level)) << 48) ^ (uint64_t(uint32_t(iy)) << 24) ^ uint64_t(ix);
  }
  std::unordered_map<uint64_t, ChunkSurface> mByChunk;
};

/// Builds chunk meshes. Keeps scratch buffers between calls: use one per thread.
class ChunkMesher {
 public:
  ChunkMesher(const TreeLayout& layout, const ErrorBudget& budget, const ActivationGrid& grid,
              const HeightSampler& heights);

  ChunkMesh build(int32_t level, int32_t ix, int32_t iy);

  /// Switches the height source (e.g. to the window of the next block). Forgets the parent
  /// surfaces kept for greedy chunks.
  void setHeights(const HeightSampler& heights) {
    mHeights = &heights;
    mSurfaces.clear();
  }
  /// Greedy insertion for the levels from `firstLevel` down (kRtin: none). Levels at and
  /// above the blocks only where every height is at hand (their meshes scan every sample).
  /// A chunk at those levels whose parent is RTIN (or a root) takes whichever of its greedy
  /// and RTIN meshes has fewer triangles; a greedy chunk's descendants are all greedy.
  void setMethod(MeshMethod method, int32_t firstLevel) {
    mMethod = method;
    mFirstGreedyLevel = firstLevel;
    mSurfaces.clear();
  }
  /// Parents' surfaces to take from `store` (null: none) before building them.
  void shareSurfaces(const SurfaceStore* store) { mShared = store; }

  /// The surface of `level` at grid point p (p inside the data), by descending the bintree of
  /// the chunk that contains it. Exposed for tests.
  double surfaceHeight(int32_t level, GridPoint p);
  /// The same within the given chunk of that level (p inside or on its square).
  double surfaceHeightIn(int32_t level, int32_t ix, int32_t iy, GridPoint p);

 private:
  using Surface = ChunkSurface;
  bool greedyAt(int32_t level) const {
    return mMethod == MeshMethod::kGreedy && level >= mFirstGreedyLevel &&
           mLayout.chunkCells(level) <= kGreedyMaxChunkCells;
  }
  /// nullopt where insertion gives no mesh (a degenerate start: not expected, since every
  /// chunk below a root starts from its parent's vertices, which asks nothing of its edges).
  /// `parent`: the parent's surface (null at a root), resolved before (it may be built).
  std::optional<ChunkMesh> buildGreedy(ChunkMesh mesh, const Surface* parent);
  /// A greedy root's start (its rectangle) and stand-in parent surface (its heights), for
  /// the w × h cells of mGreedyHeights.
  void greedyRootStart(int32_t w, int32_t h);
  ChunkMesh buildRtin(ChunkMesh mesh);
  const Surface& surfaceOf(int32_t level, int32_t ix, int32_t iy);
  void keepSurface(const ChunkMesh& mesh);

  struct ClipVertex {
    GridPoint p;
    double z;
  };
  /// The plane of a bintree triangle through its corners' heights.
  struct Plane {
    GridPoint origin;
    double z0 = 0, gx = 0, gy = 0;
    double at(GridPoint p) const { return z0 + gx * (p.x - origin.x) + gy * (p.y - origin.y); }
  };
  Plane planeOf(const BinTriangle& t) const;
  /// The vertex at p, added with height z() if new (z is called only then).
  template <typename Height>
  uint32_t vertexIndex(ChunkMesh& mesh, GridPoint p, Height&& z, const Plane& parent);
  void emitTriangle(ChunkMesh& mesh, const BinTriangle& t, const Plane& parent);
  void addSkirts(ChunkMesh& mesh);
  /// Counts the surface's vertices, takes its height range and adds the skirts.
  void finishSurface(ChunkMesh& mesh);
  double planeHeight(const BinTriangle& t, GridPoint p) const;

  const TreeLayout& mLayout;
  const ErrorBudget& mBudget;
  const ActivationGrid& mGrid;
  const HeightSampler* mHeights;
  int32_t mOriginX = 0, mOriginY = 0, mSide = 0;
  TouchedIndex mDenseIndex;  // (side+1)^2 for small chunks
  std::unordered_map<uint64_t, uint32_t> mSparseIndex;
  struct Pending {
    BinTriangle t;
    int depth;         ///< below the chunk's root triangles (sets the Sierpinski visit order)
    bool parentKnown;  ///< the parent level's triangle over t is found (and is `parent`)
    Plane parent;
  };
  std::vector<Pending> mStack;
  BinTriangle mCachedParentTriangle{};
  int32_t mCachedParentLevel = -1;
  MeshMethod mMethod = MeshMethod::kRtin;
  int32_t mFirstGreedyLevel = 0;
  std::vector<Surface> mSurfaces;  ///< the last two levels' built chunks
  const SurfaceStore* mShared = nullptr;
  std::vector<double> mGreedyHeights, mGreedyParent;
  std::vector<SurfaceCorner> mGreedyParentTriangles;
};

}  // namespace terralod
