#pragma once
// The error a drawn VIPM chunk may show, θ (metres), from the selection's distance and morph
// parameter.
//
// A chunk at distance D (the selection's eye-to-box distance) may show θ = τ·D/K, so its
// screen-space error is at most τ. The selection's morph parameter t of a chunk of level L
// runs from 0 at δ(L) to 1 at δ(L−1) (selection.h: t = (τD/K − δ_L) / (δ_{L−1} − δ_L),
// clamped), so its own schedule is exactly θ clamped to [δ_L, δ_{L−1}]. A late split eases
// t in from 1 (the frame driver): the chunk then shows lerp(δ_L, δ_{L−1}, t), which at t = 1
// is δ_{L−1}, the fallback parent's error: a VIPM tileset's levelError[0] is twice every
// leaf's coarsest error, so the leaf draws its coarsest level, which is what the parent drew.

#include <algorithm>

namespace terralod {

/// θ for a chunk whose unconstrained allowance is `tauDistanceOverK` (τ·D/K), drawn with
/// morph parameter `morph`, of level error `ownError` under a parent of `parentError` (for a
/// root, its own).
inline double vipmTheta(double tauDistanceOverK, float morph, double ownError, double parentError) {
  const double t = std::clamp(double(morph), 0.0, 1.0);
  return std::max(tauDistanceOverK, ownError + t * (parentError - ownError));
}

}  // namespace terralod
