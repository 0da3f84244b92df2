#pragma once
// Exact stitching of VIPM chunks by triangle fans (papers/vipm-terrain-story.md, "the perfect"
// way): every chunk border, and every inner seam of a blot root, lies on a grid line x or y =
// a multiple of 64 cells. Each frame the drawn chunks put their active vertices on those lines
// into one StitchTable (absolute positions, as drawn); then every living triangle with an edge
// on a line whose span holds points of the table is replaced by a fan from its opposite corner
// onto those points. Both sides of a line then draw the same polyline, the union of their
// points, so borders match exactly with nothing hanging below the surface.
//
// Points on a line are ordered by (along, z): a vertex geomorphing along its side can stand at
// the same place as its neighbour's vertex at another height, and the union then holds both,
// one above the other, in the same order on both sides. A triangle with edges on two lines (at
// a chunk's corner) is fanned on one, then each piece on the other. Chunks keep the triangles
// that can ever have an edge on a line (at any level), so a frame's work is proportional to the
// borders, not to the chunks.
//
// Positions must be exact for both sides to rasterise the same edges: a point is given in
// absolute grid cells and metres (doubles), and the chunk that inserts it converts it to its
// own frame; geomorphing vertices on the lines are rounded (roundStitchPoint) so that every
// conversion is exact in float.

#include <array>
#include <bit>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "terralod/materials/material.h"
#include "terralod/vipm/progressive_mesh.h"

namespace terralod {

/// Grid cells between the lines chunks can meet on (a VIPM leaf's side).
inline constexpr int64_t kStitchLineCells = 64;

/// The inner seams' spacing of a VIPM node of `chunkCells` cells: a 128-cell root joins its
/// leaves' coarsest levels as they are (T-junctions on their shared sides, which its flanges
/// and fans close), so kStitchLineCells; a leaf has none, and a node above the roots has its
/// cracks closed when it is built: 0.
inline int32_t vipmSeamStep(uint32_t chunkCells) {
  return chunkCells == 2 * kStitchLineCells ? int32_t(kStitchLineCells) : 0;
}

/// A line x = at (axis 0, points ordered by y) or y = at (axis 1, ordered by x); grid cells.
struct StitchLine {
  uint8_t axis = 0;
  int64_t at = 0;
  bool operator==(const StitchLine&) const = default;
};

/// Which of a triangle's edges on lines is split first, lowest first: the finer line (fewer
/// trailing zero bits in its coordinate: a root's inner seam before the side between roots,
/// that before a 256-cell node's side, ...; the map's edge, 0, last), then x = c before y = c.
/// Fans and the joins of the nodes above the roots (which close their children's seams the
/// same way when they are built) cut a corner triangle alike, so children drawn with fans show
/// exactly the surface their parent starts from.
inline uint32_t stitchLineOrder(const StitchLine& line) {
  const uint32_t rank = line.at == 0 ? 64u : uint32_t(std::countr_zero(uint64_t(line.at)));
  return 2 * rank + line.axis;
}

/// A drawn vertex on a line, in absolute coordinates, with what the splatting draws there.
struct StitchPoint {
  double along = 0.0;                            ///< grid cells along the line
  double z = 0.0;                                ///< metres
  std::array<uint8_t, kMaxMaterials> weights{};  ///< splat weights as drawn (bytes)
  uint8_t material = 0;                          ///< the vertex's own material
};

/// The points of every drawn chunk on every line, for one frame.
class StitchTable {
 public:
  void clear();
  void add(const StitchLine& line, const StitchPoint& point);
  /// Orders each line's points by (along, z) and drops exact duplicates (a point two chunks
  /// share). Call once after the last add.
  void finish();
  /// The points of `line` strictly between keys (along0, z0) and (along1, z1), in order from
  /// the first to the second (either way round).
  std::span<const StitchPoint> between(const StitchLine& line, double along0, double z0,
                                       double along1, double z1, bool& reversed) const;
  size_t pointCount() const;
  /// The points of `line` from `along0` to `along1` (grid cells), both included, in order.
  std::span<const StitchPoint> span(const StitchLine& line, double along0, double along1) const;

 private:
  struct Hash {
    size_t operator()(const StitchLine& l) const { return std::hash<int64_t>()(l.at * 2 + l.axis); }
  };
  std::unordered_map<StitchLine, std::vector<StitchPoint>, Hash> mLines;
};

/// Where a chunk lies: its south-west grid point and its zBase (positions are relative to
/// them), its grid points, its inner seams' spacing (blot roots: every kStitchLineCells;
/// 0: none), and the cells of the tileset's largest node (the widest frame a point of this
/// chunk can be fanned into).
struct StitchChunk {
  int64_t cornerX = 0, cornerY = 0;
  double zBase = 0.0;
  int32_t width = 0, height = 0;
  int32_t seamStep = 0;
  uint32_t largestCells = 2 * kStitchLineCells;
};

/// The step a geomorphing point on a line is rounded to along it (cells): the finest that is
/// exact in float in a frame of `largestCells` cells, with a bit to spare (2^-16 for 128-cell
/// roots, 2^-10 for an 8192-cell node).
double stitchQuantum(uint32_t largestCells);

/// Rounds a geomorphing vertex (in its chunk's frame) that lies on one of the chunk's lines,
/// so that moving it into any other chunk's frame is exact in float: along the line to
/// stitchQuantum, z to 2^-10 m (exact while |z| < 16 km above zBase). Vertices off the lines
/// never enter the table and are left as they are: rounding them could put them onto a line
/// or turn a thin triangle over.
void roundStitchPoint(std::array<float, 3>& position, const StitchChunk& chunk);

/// The fans of a chunk at one frame.
struct StitchFans {
  /// Triangles of the whole part (indices into its triangle order) the fans replace,
  /// ascending.
  std::vector<uint32_t> replaced;
  /// The fans' triangles: a corner < vertexCount is the chunk's vertex, else inserted point
  /// corner - vertexCount.
  std::vector<std::array<uint32_t, 3>> triangles;
  /// Points of other chunks (or of the root's other side of a seam) the fans use, in the
  /// chunk's own frame (grid x, y from its corner, metres above its zBase).
  std::vector<std::array<float, 3>> positions;
  std::vector<std::array<uint8_t, kMaxMaterials>> weights;
  std::vector<uint8_t> materials;

  void clear();
  bool operator==(const StitchFans&) const = default;
};

class VipmStitcher {
 public:
  /// Finds the chunk's vertices on its lines and the triangles that can ever have an edge on
  /// one (replaying the collapses once).
  VipmStitcher(const ProgressiveMesh& mesh, const StitchChunk& chunk);
  VipmStitcher() = default;

  /// Adds the active vertices (< activeVertices) on the chunk's lines at their drawn
  /// positions, with their drawn weights and own materials.
  void addPoints(StitchTable& table, uint32_t activeVertices,
                 std::span<const std::array<float, 3>> drawn,
                 std::span<const std::array<uint8_t, kMaxMaterials>> weights,
                 std::span<const uint8_t> materials) const;

  /// The fans for the living triangles `living` (the whole part's indices, a prefix) with
  /// vertices at `drawn`, against `table` (which holds this chunk's own points).
  void fan(const StitchTable& table, std::span<const uint16_t> living,
           std::span<const std::array<float, 3>> drawn, StitchFans& out) const;

  /// A hash of everything fan's result depends on besides the chunk's own triangles at a
  /// level: `applied` (the chunk's collapse count) and the table's points on the chunk's lines
  /// within its span (its own border points among them). Equal signatures: equal fans. Costs
  /// the points on the chunk's lines, not its candidate triangles.
  uint64_t signature(const StitchTable& table, uint32_t applied) const;

  /// Where the chunk lies.
  const StitchChunk& chunk() const { return mChunk; }

  /// The most triangles and inserted points fan can give.
  uint32_t maxFanTriangles() const { return mMaxTriangles; }
  uint32_t maxInsertedPoints() const { return mMaxInserted; }
  /// Vertices on the chunk's lines (the work addPoints does) and candidate triangles.
  size_t borderVertexCount() const { return mBorderVertices.size(); }
  size_t candidateCount() const { return mCandidates.size(); }
  /// Memory it keeps.
  uint64_t bytes() const {
    return mBorderVertices.size() * 3 + mCandidates.size() * 4 + mLines.size() * sizeof(Line);
  }

 private:
  struct Line {
    StitchLine line;
    double local = 0.0;  // the line's coordinate in the chunk's frame
  };
  StitchChunk mChunk;
  uint32_t mVertexCount = 0;
  std::vector<Line> mLines;
  std::vector<uint16_t> mBorderVertices;  // vertices on a line
  std::vector<uint8_t> mLineMask;         // per border vertex (same order): its lines' bits
  std::vector<uint32_t> mCandidates;      // ascending triangle slots
  uint32_t mMaxTriangles = 0, mMaxInserted = 0;
};

}  // namespace terralod
