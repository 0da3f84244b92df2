#pragma once
// A chunk's progressive mesh reconstructed for drawing (on a loader thread, O(n)): index
// buffers that serve every level of detail by in-place edits, as in Forsyth's "vanilla" VIPM.
//
// Parts: the whole chunk's triangle list, and one list per material holding the triangles
// with a corner of that material (texture splatting draws each material's list with its
// weights). Every part keeps the progressive mesh's triangle order, so at every level its
// living triangles are a prefix; all parts are driven by the same collapse count, so every
// material agrees on the active vertices (as the paper requires).
//
// Moving to a level applies or undoes collapses one at a time: a collapse rewrites the
// indices of the corners that referred to the removed vertex (in every part) and shortens the
// prefixes by the triangles it removes. The work is proportional to the collapses crossed.
//
// Choosing a level: collapses whose error is at most e are applied (the lower bound, so every
// part sees the same level regardless of the previous state). Geomorphing (morphWindow,
// morphPositions) spreads each collapse over a factor kMorphSpan (1.25) of distance:
// collapse j starts moving its vertex toward its target when the allowed error reaches
// errors[j] and is applied (the vertex sits on its target) when it reaches kMorphSpan
// errors[j], eased in and out. The drawn mesh is then always between two levels whose errors
// are at most the allowed error, and collapses that touch never slide together (the builder
// spaces them, collapse_order.h).

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/materials/material.h"
#include "terralod/vipm/progressive_mesh.h"

namespace terralod {

inline constexpr int kWholeChunk = -1;

struct VipmPart {
  int material = kWholeChunk;       ///< material index, or kWholeChunk
  std::vector<uint16_t> indices;    ///< current state (the applied collapses' edits made)
  std::vector<uint32_t> triangles;  ///< per collapse count 0..R: living triangles (a prefix)
  std::vector<uint32_t> moveStart;  ///< per collapse 0..R: start of its moves
  /// Index positions in `indices` a collapse rewrites (32 bits: a root keeps up to 32,768
  /// triangles, 98,304 positions).
  std::vector<uint32_t> moves;
  /// Per triangle of the part: its index in the whole part (ascending; empty in the whole
  /// part itself, where it is the identity).
  std::vector<uint32_t> wholeTriangles;
  bool dirty = true;  ///< indices changed since the flag was last cleared
};

/// Whether a collapse's vertex fades its material into its target's while it geomorphs.
/// Leaves keep theirs (the rules make a collapse keep the materials where they are; without
/// them the boundaries jump, which is what --no-material-rules shows); blot roots fade.
enum class MaterialFade : uint8_t { kKeep, kToTarget };

class VipmLevels {
 public:
  /// Reconstructs the parts of `mesh`, whose vertices have materials `vertexMaterials` (one
  /// per vertex, < 8), at its finest level. Fails if the mesh is inconsistent. With
  /// kToTarget a material's part also holds the triangles with a corner that can fade into it
  /// (the materials along the corner's chain of collapse targets).
  static Result<VipmLevels> reconstruct(const ProgressiveMesh& mesh,
                                        std::span<const uint8_t> vertexMaterials,
                                        MaterialFade fade = MaterialFade::kKeep);

  uint32_t collapseCount() const { return uint32_t(mTargets.size()); }
  uint32_t vertexCount() const { return mVertexCount; }
  /// Collapses applied now.
  uint32_t applied() const { return mApplied; }
  /// Applies or undoes collapses until `count` are applied.
  void setApplied(uint32_t count);
  /// Vertices active now: [0, activeVertices()).
  uint32_t activeVertices() const { return mVertexCount - mApplied; }

  std::span<VipmPart> parts() { return mParts; }
  std::span<const VipmPart> parts() const { return mParts; }
  const VipmPart& whole() const { return mParts.front(); }
  /// Triangles of `part` drawn now.
  uint32_t drawnTriangles(const VipmPart& part) const { return part.triangles[mApplied]; }

 private:
  uint32_t mVertexCount = 0;
  uint32_t mApplied = 0;
  std::vector<uint16_t> mTargets;
  std::vector<uint16_t> mRemoved;  // per collapse: the vertex it removes
  std::vector<VipmPart> mParts;
};

/// Number of collapses with error <= e (errors non-decreasing).
uint32_t collapsesWithin(std::span<const float> errors, double e);

/// What a chunk draws for an allowed error `theta` (metres): `applied` collapses made, and
/// the collapses [applied, morphing) moving their vertices toward their targets.
struct MorphWindow {
  uint32_t applied = 0;
  uint32_t morphing = 0;
};
/// With morphing off, collapses with error <= theta are applied and none morphs.
enum class Geomorph : uint8_t { kOn, kOff };
MorphWindow morphWindow(std::span<const float> errors, double theta, Geomorph geomorph);
/// The positions `theta` chose geomorphed on to `morphTheta` (the pop measure: an earlier
/// frame's chunk for this frame's camera): with geomorphing on, the window spanning both, so
/// a collapse moving at either keeps moving (drawn at morphTheta, one finished there sits on
/// its target and one not begun on its own position); with it off, what `theta` chose, which
/// cannot move. (Not for materials: a corner takes its target's material when its collapse
/// is applied, a change of state the material pop measure counts.)
MorphWindow morphWindow(std::span<const float> errors, double theta, double morphTheta,
                        Geomorph geomorph);

/// How far collapse j of error `error` has geomorphed at `theta`: 0 until theta reaches the
/// error, 1 from kMorphSpan times the error, eased in and out between (smootherstep of
/// x = (theta / error - 1) / (kMorphSpan - 1): speed and acceleration 0 at both ends, so a
/// frame that crosses an end moves the vertex by about 10 x^3 of its way, not 3 x^2),
/// so a vertex starts and stops sliding gently rather than at once.
inline float morphProgress(double theta, double error) {
  const double x = std::clamp((theta / error - 1.0) / (kMorphSpan - 1.0), 0.0, 1.0);
  return float(x * x * x * (x * (6.0 * x - 15.0) + 10.0));
}

/// Positions of the morphing vertices: for each collapse j in [window.applied,
/// window.morphing), from the last to the first, vertex N - 1 - j is at
/// lerp(own, drawn position of targets[j], morphProgress(theta, errors[j])). Writes `drawn`
/// of the morphing vertices only; `own` holds every vertex's own position.
void morphPositions(const ProgressiveMesh& mesh, const MorphWindow& window, double theta,
                    std::span<const std::array<float, 3>> own,
                    std::span<std::array<float, 3>> drawn);

/// Splat weights per vertex, one per material.
using MaterialWeights = std::array<float, kMaxMaterials>;

/// Materials of the morphing vertices as they fade with their positions: for each collapse j
/// in [window.applied, window.morphing), from the last to the first, vertex N - 1 - j weighs
/// lerp(its own material alone, the drawn weights of targets[j], morphProgress(theta,
/// errors[j])), so a vertex whose target is itself fading follows it and meets exactly what
/// its target shows when it is applied. Writes `weights` of the morphing vertices only; every
/// other vertex must hold its own material alone.
void morphMaterialWeights(const ProgressiveMesh& mesh, const MorphWindow& window, double theta,
                          std::span<const uint8_t> materials, std::span<MaterialWeights> weights);

}  // namespace terralod
