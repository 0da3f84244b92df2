#pragma once
// View-dependent chunk selection (Ulrich 2002, section 4): from the roots down, a chunk is
// drawn when its screen-space error ρ = δ K / D is at most τ, otherwise its children are
// visited. A pure function of (tree, view, options): no GL, no IO, and no allocation once the
// output's capacity covers the tree.
//
// Morph schedule. A drawn chunk of level L gets one morph parameter t in [0, 1]; its vertices
// are drawn at own height + t * morph delta, so t = 1 is the parent's surface and t = 0 its
// own. We use
//
//     t = clamp(τ / ρ - 1, 0, 1)
//
// rather than Ulrich's eq. 4 (t = clamp(2ρ/τ - 1, 0, 1)), for two reasons:
//  - Error. On every triangle the morphed surface is (1 - t) · own + t · target, and the
//    builder guarantees own within δ(L) and target within δ(L - 1) = 2 δ(L) of every source
//    sample (targets are the parent's unquantised planes rounded on a step no coarser than the
//    parent's own). So the morphed error is at most (1 + t) δ(L), which on screen is
//    (1 + t) ρ. Our t makes that exactly τ wherever 0 < t < 1, and less elsewhere: the drawn
//    surface never exceeds τ. Eq. 4 reaches 2τ just before a split.
//  - Continuity. At a split the parent's ρ' is τ; each child's box lies inside the parent's
//    (ChunkTree nests them: a child's own surface may rise above its parent's), so its
//    distance is no smaller and its ρ is at most ρ'/2 = τ/2, which gives t = 1: the
//    children start out as the parent's surface. When a chunk itself splits, ρ = τ and t = 0.
//    Merges are the same moments in reverse. So no frame shows a pop from selection alone
//    (up to the height quantisation of the two levels, a few hundredths of a pixel).
//
// Levels whose errors do not halve (VIPM tilesets: the fallback roots' error is twice the
// leaves' coarsest, far above 2 δ(leaf)) use the same schedule in the allowed error
// θ = τ·D/K = δ_L·τ/ρ: t = clamp((θ − δ_L) / (δ_{L−1} − δ_L), 0, 1), which is the formula above
// when δ_{L−1} = 2 δ_L (bit for bit). So t = 1 still means "at the parent's error": a VIPM
// chunk at t = 1 draws its coarsest level (vipm_theta.h), and a late split eases in from it.

#include <cstdint>
#include <span>
#include <vector>

#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/view.h"

namespace terralod {

struct SelectionOptions {
  double tau = 2.0;   ///< screen-space error bound in pixels, > 0
  bool morph = true;  ///< false: every chunk at t = 0 (shows the pops morphing hides)
  /// Per node, non-zero when its geometry can be drawn now. Empty: every node can. A chunk
  /// splits only when all its children can be drawn; otherwise it is drawn itself, coarser than
  /// wanted (counted), and its children are not visited.
  std::span<const uint8_t> drawable;
};

struct SelectedChunk {
  uint32_t node = 0;
  float morph = 0.0f;  ///< t: 0 own surface, 1 the parent's
};

struct SelectionStats {
  uint32_t visited = 0;            ///< nodes whose box was tested
  uint32_t culled = 0;             ///< nodes outside the frustum (their subtrees skipped)
  uint32_t selected = 0;           ///< chunks to draw
  uint32_t coarserThanWanted = 0;  ///< drawn although they wanted to split (children missing)
  uint32_t undrawableRoots = 0;    ///< visible roots that could not be drawn at all
  uint64_t triangles = 0;          ///< surface triangles of the selected chunks
  uint64_t skirtTriangles = 0;
  int deepestLevel = -1;
};

/// Selects the chunks to draw. `out` is cleared, then filled in depth-first order; reserve
/// tree.nodes().size() once and no call allocates again. Thread-safe (touches only `out`).
SelectionStats selectChunks(const ChunkTree& tree, const View& view,
                            const SelectionOptions& options, std::vector<SelectedChunk>& out);

/// The morph parameter the schedule above gives `node` in `view` (0 with morphing off).
float morphParameter(const ChunkTree& tree, const View& view, const SelectionOptions& options,
                     uint32_t node);

}  // namespace terralod
