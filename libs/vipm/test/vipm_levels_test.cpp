#include "terralod/vipm/vipm_levels.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <set>

#include "terralod/vipm/progressive_mesh.h"
#include "vipm_test_patches.h"

namespace terralod {
namespace {

using Tri = std::array<uint16_t, 3>;

struct Built {
  GridPatch patch;
  ProgressiveMesh mesh;
  std::vector<uint8_t> materials;  // per vertex
};

Built build(double maxError, MaterialRules rules = MaterialRules::kOn,
            GeomorphSpacing spacing = GeomorphSpacing::kOn,
            const std::string& dem = "crater_lake_0513.bt", int32_t x0 = 192, int32_t y0 = 192) {
  Built b;
  b.patch = test::demPatch(dem, x0, y0, 1900, 2050, 65);
  CollapseStart start;
  start.bakedError = float(maxError);
  start.spacing = spacing;
  b.mesh = makeProgressiveMesh(b.patch, buildCollapseOrder(b.patch, rules, start), maxError);
  for (uint16_t p : b.mesh.points) b.materials.push_back(b.patch.materials[p]);
  return b;
}

// The mesh after j collapses, by renaming corners (the oracle for the index edits).
std::vector<Tri> naive(const ProgressiveMesh& m, uint32_t j) {
  std::vector<uint16_t> to = test::unrenamed(m.vertexCount());
  for (uint32_t k = 0; k < j; ++k) to[m.vertexCount() - 1 - k] = m.targets[k];
  return test::renamed(m.triangles, to);
}

// Whether the whole chunk's part draws exactly `expect`, in order.
::testing::AssertionResult wholeIs(const VipmLevels& levels, const std::vector<Tri>& expect) {
  const VipmPart& whole = levels.whole();
  if (levels.drawnTriangles(whole) != expect.size())
    return ::testing::AssertionFailure()
           << levels.drawnTriangles(whole) << " triangles drawn, " << expect.size() << " living";
  for (size_t t = 0; t < expect.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (whole.indices[3 * t + k] != expect[t][k])
        return ::testing::AssertionFailure() << "triangle " << t << " corner " << k;
  return ::testing::AssertionSuccess();
}

TEST(ProgressiveMesh, StartsAtTheMaxErrorWithRemovedVerticesLast) {
  const Built b = build(1.0);
  const ProgressiveMesh& m = b.mesh;
  ASSERT_GT(m.collapseCount(), 100u);
  EXPECT_LE(m.finestError, 1.0f);
  EXPECT_GT(m.errors.front(), 1.0f);
  EXPECT_TRUE(std::is_sorted(m.errors.begin(), m.errors.end()));
  EXPECT_LT(m.vertexCount(), b.patch.pointCount());
  std::set<uint16_t> distinct(m.points.begin(), m.points.end());
  EXPECT_EQ(distinct.size(), m.points.size());
  for (uint32_t j = 0; j < m.collapseCount(); ++j) EXPECT_LT(m.targets[j], m.vertexCount() - 1 - j);
  // After j collapses the living triangles are a prefix and use only vertices [0, N - j).
  auto removal = triangleRemovals(m);
  ASSERT_TRUE(removal.ok()) << removal.error().message;
  for (uint32_t j : {0u, m.collapseCount() / 3, m.collapseCount()}) {
    const auto tris = naive(m, j);
    size_t prefix = 0;
    while (prefix < removal->size() && (*removal)[prefix] >= j) ++prefix;
    EXPECT_EQ(tris.size(), prefix);
    for (const Tri& t : tris)
      for (uint16_t v : t) EXPECT_LT(v, m.vertexCount() - j);
  }
}

TEST(ProgressiveMesh, ALargerMaxErrorStartsCoarser) {
  EXPECT_LT(build(4.0).mesh.vertexCount(), build(0.5).mesh.vertexCount());
}

TEST(VipmLevels, IndexEditsGiveTheSameMeshAsRenamingAtEveryLevel) {
  const Built b = build(1.0);
  auto levels = VipmLevels::reconstruct(b.mesh, b.materials);
  ASSERT_TRUE(levels.ok()) << levels.error().message;
  // Jump around: forwards, backwards, to the ends.
  const uint32_t r = b.mesh.collapseCount();
  for (uint32_t j : {r / 2, r / 5, r, 0u, r - 1, 7u, r / 2}) {
    levels->setApplied(j);
    const auto expect = naive(b.mesh, j);
    ASSERT_TRUE(wholeIs(*levels, expect)) << j;
    // Each material's part: exactly the living triangles with a corner of its material, in
    // the same order.
    for (const VipmPart& part : levels->parts()) {
      if (part.material == kWholeChunk) continue;
      std::vector<Tri> mine;
      for (const Tri& t : expect)
        if (b.materials[t[0]] == part.material || b.materials[t[1]] == part.material ||
            b.materials[t[2]] == part.material)
          mine.push_back(t);
      ASSERT_EQ(levels->drawnTriangles(part), mine.size()) << "material " << part.material;
      for (size_t t = 0; t < mine.size(); ++t)
        for (int k = 0; k < 3; ++k) ASSERT_EQ(part.indices[3 * t + k], mine[t][k]);
    }
  }
  EXPECT_EQ(levels->parts().size(), 4u);  // the whole chunk and three materials
}

// A root of 129² points keeps up to 32,768 triangles: 98,304 corners, more than 16 bits count
// (a rough root of the New Zealand DEM kept 28,000 and drew wrong triangles at some levels).
TEST(VipmLevels, IndexEditsHoldInChunksOfMoreCornersThan16BitsCount) {
  Built b;
  b.patch.width = b.patch.height = 129;
  uint32_t state = 12345;
  for (int32_t i = 0; i < 129 * 129; ++i) {
    state = state * 1664525u + 1013904223u;  // rough: every sample its own height
    b.patch.heights.push_back(float(state >> 8) / float(1u << 24) * 50.0f);
    b.patch.materials.push_back(uint8_t(i % 3));
  }
  CollapseStart start;
  start.bakedError = 0.01f;
  b.mesh =
      makeProgressiveMesh(b.patch, buildCollapseOrder(b.patch, MaterialRules::kOff, start), 0.01);
  for (uint16_t p : b.mesh.points) b.materials.push_back(b.patch.materials[p]);
  ASSERT_GT(b.mesh.triangles.size() * 3, size_t{65536});
  auto levels = VipmLevels::reconstruct(b.mesh, b.materials);
  ASSERT_TRUE(levels.ok()) << levels.error().message;
  const uint32_t r = b.mesh.collapseCount();
  auto drawn = [&](const VipmPart& part) {
    std::multiset<Tri> out;
    for (uint32_t t = 0; t < levels->drawnTriangles(part); ++t)
      out.insert({part.indices[3 * t], part.indices[3 * t + 1], part.indices[3 * t + 2]});
    return out;
  };
  for (uint32_t j : {r / 3, r, r / 2}) {
    levels->setApplied(j);
    const auto expect = naive(b.mesh, j);
    ASSERT_TRUE(wholeIs(*levels, expect)) << j;
    // Each material's part (collapses across materials: it keeps the triangles that ever had
    // a corner of its material): living triangles only, and every one with such a corner now.
    const std::multiset<Tri> living(expect.begin(), expect.end());
    for (const VipmPart& part : levels->parts()) {
      if (part.material == kWholeChunk) continue;
      const std::multiset<Tri> mine = drawn(part);
      std::multiset<Tri> must;
      for (const Tri& t : expect)
        if (b.materials[t[0]] == part.material || b.materials[t[1]] == part.material ||
            b.materials[t[2]] == part.material)
          must.insert(t);
      EXPECT_TRUE(std::includes(living.begin(), living.end(), mine.begin(), mine.end())) << j;
      EXPECT_TRUE(std::includes(mine.begin(), mine.end(), must.begin(), must.end())) << j;
    }
  }
}

TEST(VipmLevels, RefusesAnInconsistentMesh) {
  Built b = build(1.0);
  ProgressiveMesh broken = b.mesh;
  std::swap(broken.triangles.front(), broken.triangles.back());
  EXPECT_FALSE(VipmLevels::reconstruct(broken, b.materials).ok());
  broken = b.mesh;
  broken.targets[3] = uint16_t(broken.vertexCount() - 1);  // onto a removed vertex
  EXPECT_FALSE(VipmLevels::reconstruct(broken, b.materials).ok());
  broken = b.mesh;
  broken.targets[10] = broken.targets[10] == 0 ? 1 : 0;  // not a neighbour (almost surely)
  EXPECT_FALSE(VipmLevels::reconstruct(broken, b.materials).ok());
}

TEST(MorphWindow, SpansTheMorphSpanAndIsASharpCutWithoutMorphing) {
  const std::vector<float> errors{1, 1, 2, 3, 4, 6, 8, 12};
  ASSERT_EQ(kMorphSpan, 1.25);
  auto w = morphWindow(errors, 8.0, Geomorph::kOn);
  EXPECT_EQ(w.applied, 6u);   // errors <= 6.4
  EXPECT_EQ(w.morphing, 7u);  // errors <= 8
  w = morphWindow(errors, 4.0, Geomorph::kOn);
  EXPECT_EQ(w.applied, 4u);   // errors <= 3.2
  EXPECT_EQ(w.morphing, 5u);  // errors <= 4
  w = morphWindow(errors, 4.0, Geomorph::kOff);
  EXPECT_EQ(w.applied, 5u);
  EXPECT_EQ(w.morphing, 5u);
}

TEST(MorphProgress, StartsAndStopsAtRest) {
  const double e = 10.0, s = kMorphSpan;
  EXPECT_EQ(morphProgress(e, e), 0.0f);
  EXPECT_EQ(morphProgress(0.5 * e, e), 0.0f);
  EXPECT_EQ(morphProgress(s * e, e), 1.0f);
  EXPECT_EQ(morphProgress(3.0 * e, e), 1.0f);
  EXPECT_FLOAT_EQ(morphProgress(0.5 * (1.0 + s) * e, e), 0.5f);
  // A step of 0.1 % of the span just after the start, or just before the end, moves a vertex
  // by about 1e-8 of its way (smoothstep: 3e-6; a linear ramp: 1e-3).
  EXPECT_LT(morphProgress((1.0 + 0.001 * (s - 1.0)) * e, e), 1e-5f);
  EXPECT_GT(morphProgress((s - 0.001 * (s - 1.0)) * e, e), 1.0f - 1e-5f);
  float previous = 0.0f;
  for (double theta = e; theta <= s * e; theta += 0.01 * e) {
    EXPECT_GE(morphProgress(theta, e), previous);
    previous = morphProgress(theta, e);
  }
}

// Every vertex's own position (grid x, y, height).
std::vector<std::array<float, 3>> ownPositions(const Built& b) {
  std::vector<std::array<float, 3>> own;
  for (uint16_t p : b.mesh.points)
    own.push_back({float(b.patch.xOf(p)), float(b.patch.yOf(p)), b.patch.heights[p]});
  return own;
}

// Where each vertex is drawn for window `w` geomorphed at `morphTheta`: a vertex removed by an
// applied collapse resolves through the targets to the one drawn in its place.
std::vector<std::array<float, 3>> drawnFor(const ProgressiveMesh& m,
                                           const std::vector<std::array<float, 3>>& own,
                                           const MorphWindow& w, double morphTheta) {
  std::vector<std::array<float, 3>> drawn = own;
  morphPositions(m, w, morphTheta, own, drawn);
  std::vector<std::array<float, 3>> out(m.vertexCount());
  for (uint32_t v = 0; v < m.vertexCount(); ++v) {
    uint32_t x = v;
    while (x >= m.vertexCount() - w.applied) x = m.targets[m.vertexCount() - 1 - x];
    out[v] = drawn[x];
  }
  return out;
}

TEST(MorphPositions, MoveContinuouslyOntoTheTargetsAtTheWindowsEdges) {
  const Built b = build(1.0);
  const ProgressiveMesh& m = b.mesh;
  const auto own = ownPositions(b);
  auto drawnAt = [&](double theta, Geomorph g) {
    return drawnFor(m, own, morphWindow(m.errors, theta, g), theta);
  };
  // Sweeping theta finely (0.02 % steps, 0.1 % of a morph span), every vertex's drawn
  // position changes little between steps with morphing, and jumps somewhere without it.
  double worstOn = 0, worstOff = 0;
  auto prevOn = drawnAt(1.0, Geomorph::kOn), prevOff = drawnAt(1.0, Geomorph::kOff);
  for (double theta = 1.0; theta < 40.0; theta *= 1.0002) {
    const auto on = drawnAt(theta, Geomorph::kOn), off = drawnAt(theta, Geomorph::kOff);
    for (uint32_t v = 0; v < m.vertexCount(); ++v)
      for (int k = 0; k < 3; ++k) {
        worstOn = std::max(worstOn, double(std::abs(on[v][k] - prevOn[v][k])));
        worstOff = std::max(worstOff, double(std::abs(off[v][k] - prevOff[v][k])));
      }
    prevOn = on;
    prevOff = off;
  }
  EXPECT_LT(worstOn, 0.2);
  EXPECT_GT(worstOff, 2.0);
}

TEST(MorphPositions, AnEarlierStateGeomorphedOnDrawsWhatTheNewThetaDraws) {
  // What the bench's pop measure compares: last frame's chunk (the collapses θ chose) carried
  // on to this frame's θ, against this frame's chunk. Geomorphing has no jumps, so they agree
  // exactly; without it the collapses between the two θ show. The window of the earlier θ
  // alone, morphed at the new θ, cuts short the collapses that enter or leave the geomorph
  // within the step (what the measure did before, up to 0.5 px on a fast descent).
  const Built b = build(1.0);
  const ProgressiveMesh& m = b.mesh;
  const auto own = ownPositions(b);
  auto drawnAt = [&](const MorphWindow& w, double morphTheta) {
    return drawnFor(m, own, w, morphTheta);
  };
  auto farthest = [&](const auto& p, const auto& q) {
    double worst = 0.0;
    for (uint32_t v = 0; v < m.vertexCount(); ++v)
      for (int k = 0; k < 3; ++k) worst = std::max(worst, double(std::abs(p[v][k] - q[v][k])));
    return worst;
  };
  double carriedOn = 0.0, unmorphed = 0.0, cutShort = 0.0;
  for (double theta = 1.0; theta < 40.0; theta *= 1.03)
    for (double step : {0.85, 1.15}) {
      const double now = theta * step;
      const auto drawnNow = drawnAt(morphWindow(m.errors, now, Geomorph::kOn), now);
      carriedOn = std::max(
          carriedOn,
          farthest(drawnAt(morphWindow(m.errors, theta, now, Geomorph::kOn), now), drawnNow));
      cutShort = std::max(
          cutShort, farthest(drawnAt(morphWindow(m.errors, theta, Geomorph::kOn), now), drawnNow));
      const MorphWindow off = morphWindow(m.errors, theta, now, Geomorph::kOff);
      EXPECT_EQ(off.applied, off.morphing);
      unmorphed = std::max(
          unmorphed,
          farthest(drawnAt(off, now), drawnAt(morphWindow(m.errors, now, Geomorph::kOff), now)));
    }
  EXPECT_LT(carriedOn, 1e-4);  // float rounding of a finished morph
  EXPECT_GT(cutShort, 0.5);
  EXPECT_GT(unmorphed, 2.0);
}

// Geomorphed surfaces of a patch on a canyon wall (Zion) over a sweep of θ: the number of
// triangles turned over seen from above.
int foldedTriangles(const Built& b) {
  const ProgressiveMesh& m = b.mesh;
  auto levels = VipmLevels::reconstruct(m, b.materials);
  EXPECT_TRUE(levels.ok());
  if (!levels.ok()) return -1;
  std::vector<std::array<float, 3>> own;
  for (uint16_t p : m.points)
    own.push_back({float(b.patch.xOf(p)), float(b.patch.yOf(p)), b.patch.heights[p]});
  int folded = 0;
  for (double theta = 1.0; theta < 4.0 * m.errors.back(); theta *= 1.01) {
    const MorphWindow w = morphWindow(m.errors, theta, Geomorph::kOn);
    std::vector<std::array<float, 3>> drawn = own;
    morphPositions(m, w, theta, own, drawn);
    levels->setApplied(w.applied);
    const VipmPart& whole = levels->whole();
    for (uint32_t t = 0; t < levels->drawnTriangles(whole); ++t) {
      const auto& a = drawn[whole.indices[3 * t]];
      const auto& c1 = drawn[whole.indices[3 * t + 1]];
      const auto& c2 = drawn[whole.indices[3 * t + 2]];
      const double area = (double(c1[0]) - a[0]) * (double(c2[1]) - a[1]) -
                          (double(c1[1]) - a[1]) * (double(c2[0]) - a[0]);
      folded += area < -1e-4;
    }
  }
  return folded;
}

TEST(MorphPositions, CollapsesThatTouchNeverSlideTogetherSoTheSurfaceNeverFolds) {
  // Where a root folded on Zion's canyon walls before the spacing (collapse_order.h).
  for (const MaterialRules rules : {MaterialRules::kOn, MaterialRules::kOff}) {
    const Built spaced =
        build(1.0, rules, GeomorphSpacing::kOn, "zion_srtm3_utm12_30m.tif", 526, 560);
    const Built unspaced =
        build(1.0, rules, GeomorphSpacing::kOff, "zion_srtm3_utm12_30m.tif", 526, 560);
    EXPECT_EQ(foldedTriangles(spaced), 0);
    EXPECT_GT(foldedTriangles(unspaced), 0) << "nothing folds here: the test shows nothing";
  }
}

TEST(MorphMaterialWeights, FollowTargetsThatFadeThemselvesAndEveryPartDrawsThem) {
  // Without the rules (as a blot root is built) collapses join different materials. With the
  // geomorph spacing off a target is often geomorphing itself (with it, never: the weights
  // must still follow chains in any mesh a tileset may hold).
  const Built b = build(1.0, MaterialRules::kOff, GeomorphSpacing::kOff);
  const ProgressiveMesh& m = b.mesh;
  const uint32_t n = m.vertexCount();
  auto levels = VipmLevels::reconstruct(m, b.materials, MaterialFade::kToTarget);
  ASSERT_TRUE(levels.ok()) << levels.error().message;
  auto own = [&](uint32_t v) {
    MaterialWeights w{};
    w[b.materials[v]] = 1.0f;
    return w;
  };
  // The weights drawn at each vertex, resolved through the applied collapses; `chains` false:
  // each vertex fades to its target's own material instead.
  auto drawnAt = [&](double theta, bool chains) {
    const MorphWindow w = morphWindow(m.errors, theta, Geomorph::kOn);
    std::vector<MaterialWeights> weights(n);
    for (uint32_t v = 0; v < n; ++v) weights[v] = own(v);
    if (chains) {
      morphMaterialWeights(m, w, theta, b.materials, weights);
    } else {
      for (uint32_t j = w.applied; j < w.morphing; ++j)
        for (int k = 0; k < kMaxMaterials; ++k) {
          const float t = morphProgress(theta, m.errors[j]);
          weights[n - 1 - j][k] = (1 - t) * own(n - 1 - j)[k] + t * own(m.targets[j])[k];
        }
    }
    std::vector<MaterialWeights> out(n);
    for (uint32_t v = 0; v < n; ++v) {
      uint32_t x = v;
      while (x >= n - w.applied) x = m.targets[n - 1 - x];
      out[v] = weights[x];
    }
    return std::pair{w, out};
  };
  double worstChains = 0, worstOwn = 0, worstSum = 0;
  int missing = 0, fading = 0;
  auto prevChains = drawnAt(1.0, true).second, prevOwn = drawnAt(1.0, false).second;
  for (double theta = 1.0; theta < 60.0; theta *= 1.002) {
    const auto [window, chains] = drawnAt(theta, true);
    const auto own2 = drawnAt(theta, false).second;
    for (uint32_t v = 0; v < n; ++v) {
      float sum = 0;
      for (int k = 0; k < kMaxMaterials; ++k) {
        worstChains = std::max(worstChains, double(std::abs(chains[v][k] - prevChains[v][k])));
        worstOwn = std::max(worstOwn, double(std::abs(own2[v][k] - prevOwn[v][k])));
        sum += chains[v][k];
      }
      worstSum = std::max(worstSum, double(std::abs(sum - 1.0f)));
    }
    // Every living triangle with a corner weighing a material is in that material's part.
    levels->setApplied(window.applied);
    const VipmPart& whole = levels->whole();
    for (const VipmPart& part : levels->parts()) {
      if (part.material == kWholeChunk) continue;
      std::set<Tri> inPart;
      for (uint32_t t = 0; t < levels->drawnTriangles(part); ++t)
        inPart.insert({part.indices[3 * t], part.indices[3 * t + 1], part.indices[3 * t + 2]});
      for (uint32_t t = 0; t < levels->drawnTriangles(whole); ++t) {
        const Tri tri{whole.indices[3 * t], whole.indices[3 * t + 1], whole.indices[3 * t + 2]};
        bool weighs = false;
        for (uint16_t v : tri) weighs |= chains[v][size_t(part.material)] > 0.0f;
        if (!weighs) continue;
        fading += b.materials[tri[0]] != part.material && b.materials[tri[1]] != part.material &&
                  b.materials[tri[2]] != part.material;
        missing += !inPart.count(tri);
      }
    }
    prevChains = chains;
    prevOwn = own2;
  }
  EXPECT_LT(worstSum, 1e-5);
  EXPECT_EQ(missing, 0);
  EXPECT_GT(fading, 0);  // some triangles draw a material none of their corners owns
  EXPECT_LT(worstChains, 0.05);
  EXPECT_GT(worstOwn, 0.3) << "no target fades itself: the test shows nothing";
}

}  // namespace
}  // namespace terralod
