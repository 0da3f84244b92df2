#pragma once
// Horizon culling (after Lloyd & Egbert 2002): leaves out selected chunks that nearer terrain
// hides from the eye. Pure CPU work after selection, so selection, loads and the error bound
// do not change; a culled chunk is simply not drawn. Conservative: a chunk is culled only when
// no ray from the eye through any point of it can reach it before a drawn triangle.
//
// Occluders. A selected chunk's drawn surface covers its footprint (box x, y) and lies within
// its box's z range over the whole morph range (docs/format.md, minZ/maxZ), so the solid
// {footprint} x (-inf, minZ] lies under it. A chunk's occluder grid (occluder_grid.h: per cell
// of its footprint, a floor under the surface it draws there at any morph, made when its kind
// decoded it) gives finer solids {cell} x (-inf, floor]; a chunk without one falls back to its
// descendants' boxes in the node table (their minZ lowered by both levels' errors). Skirts close
// every step between neighbours of any levels (`verify` checks each side's depth against both
// tops), so a ray that starts above the drawn terrain cannot get under any chunk's surface without
// crossing a drawn triangle first. A chunk outside the frustum is a box no pixel ray enters, which
// keeps that true where the selection drew nothing. Hence: a ray that passes through an occluder's
// solid has crossed a drawn triangle before, no farther (horizontally) than the solid's far side.
//
// The horizon. Around the eye, per azimuth bin, the steepest elevation angle below which every
// ray of the bin passes through some occluder's solid: an occluder counts in a bin only when
// its footprint covers the whole annular sector [ra, rb] of the bin (exact for a rectangle:
// slab distances are monotonic within a bin, as no bin straddles an axis), with the angle of
// max((minZ - eye z) / ra, (minZ - eye z) / rb). Chunks go nearest first; an occluder joins the
// horizon only once the chunks tested are all beyond its farthest corner (with a relative
// margin for depth precision). A chunk is culled when, in every bin its footprint (grown by a
// grid cell: skirt bottoms lean out under the neighbour) touches, the steepest elevation of its
// box's top lies below the horizon by an angular margin of one pixel, and the bins it touches
// are widened by the same margin (so rasterisation's vertex snapping, 1/256 px, cannot matter).
//
// Culling is off for a frame (nothing culled, `active` false) when the eye is not above the
// drawn terrain: outside the data's footprint, below the top of a selected chunk under it (or of
// a frustum-culled node over it), or within a few near-plane distances of any selected chunk's
// box (the crossing triangle could then be clipped by the near plane).

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/occluder_grid.h"
#include "terralod/runtime/selection.h"
#include "terralod/runtime/view.h"

namespace terralod {

/// Whether the chunks hidden behind nearer terrain are left out (`--no-horizon-culling`).
enum class HorizonCulling : uint8_t { kOn, kOff };

struct HorizonCullingStats {
  bool active = false;          ///< the eye was above the drawn terrain: chunks were tested
  uint32_t culled = 0;          ///< selected chunks left out
  uint64_t triangles = 0;       ///< their surface triangles
  uint64_t skirtTriangles = 0;  ///< their skirt triangles
};

/// Holds the scratch memory of the culling (no allocation once it has seen the tree's size).
class HorizonCuller {
 public:
  /// `bins`: azimuth bins around the eye, a multiple of 4 (so that none straddles an axis).
  explicit HorizonCuller(int bins = 1024);

  /// Writes to `visible` the chunks of `selected` (a selection for `view` over `tree`) that
  /// may show a pixel, in their order. `nearPlane`: the renderer's near-plane distance in
  /// metres. `occluders`: per node, its occluder grid (empty ones, or an empty span: none).
  /// Deterministic; a pure function of its arguments.
  HorizonCullingStats cull(const ChunkTree& tree, const View& view,
                           std::span<const SelectedChunk> selected, double nearPlane,
                           std::vector<SelectedChunk>& visible,
                           std::span<const OccluderGrid> occluders = {});

 private:
  bool eyeOverDrawnColumn(const ChunkTree& tree, const View& view, uint32_t node) const;
  void addOccluders(const ChunkTree& tree, uint32_t node, const glm::dvec3& eye,
                    const OccluderGrid* grid);
  void addGrid(const ChunkTree& tree, const ChunkNode& n, const OccluderGrid& grid,
               const glm::dvec3& eye);
  void addSolid(double x0, double y0, double x1, double y1, double top, const glm::dvec3& eye);
  void addPartial(size_t bin, double offset, bool fromStart, double angle);

  struct Candidate {
    double nearest = 0;  ///< horizontal distance from the eye to the grown footprint
    uint32_t index = 0;  ///< into `selected`
  };
  struct Pending {
    double farthest = 0;  ///< horizontal distance from the eye to the footprint's far corner
    uint32_t node = 0;
  };
  int mBins;
  std::vector<double> mCos, mSin;  ///< bin boundaries' directions (exact zeros on the axes)
  std::vector<double> mHorizon;    ///< per bin, an elevation angle in radians
  struct Partial {
    double offset;  ///< azimuth from the bin's start where the covered part ends or begins
    double angle;
  };
  /// Per bin: two parts covered from its start (the highest, the widest), two to its end.
  std::vector<Partial> mPartials;
  std::vector<uint8_t> mSelected;  ///< per node, while a call runs
  std::vector<uint8_t> mHidden;    ///< per entry of `selected`
  std::vector<Candidate> mOrder;
  std::vector<Pending> mPending;  ///< a min-heap on `farthest`
  std::vector<uint32_t> mStack;
};

}  // namespace terralod
