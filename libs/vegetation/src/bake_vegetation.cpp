#include "terralod/vegetation/vegetation_bake.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <memory>
#include <numeric>

#include "terralod/core/parallel.h"
#include "terralod/vegetation/ldi_baker.h"
#include "terralod/vegetation/wang_tiling.h"

namespace terralod::veg {
namespace {

float tallestPlant(const std::vector<PrototileContent>& tiles, const PlantLibrary& plants) {
  float top = 0;
  for (const PrototileContent& t : tiles)
    for (const PlacedObject& o : t.objects)
      top = std::max(top, plants.mesh(o.species, o.version).height * o.scale);
  return top > 0 ? top : 0.1f;
}

BakeSettings settingsOf(const VegetationScene& scene, const LdiRig& rig) {
  BakeSettings s;
  s.scene = scene.name;
  s.seed = scene.placement.seed;
  s.tileSize = rig.tileSize;
  s.headHeight = rig.headHeight;
  s.tileHeight = rig.tileHeight;
  s.resolutions = rig.resolutions;
  s.ringDistances = rig.ringDistances;
  for (int r = 0; r < kRings; ++r) s.elevations[r] = ringElevation(rig, r);
  s.raysPerPixel = scene.sampling.raysPerPixel;
  return s;
}

}  // namespace

VegetationBake bakeVegetation(const VegetationScene& scene, unsigned threads, Progress& progress) {
  const auto start = std::chrono::steady_clock::now();
  const PlantLibrary plants(scene.placement.seed);
  const Placement placed = placeObjects(
      scene.placement, [&](Species s, int v) { return plants.tightRadius(s, v); }, progress);
  LdiRig rig = scene.rig;
  rig.tileHeight = tallestPlant(placed.tiles, plants);

  std::vector<std::unique_ptr<ContextScene>> contexts;
  for (int k = 0; k < kPrototiles; ++k)
    contexts.push_back(std::make_unique<ContextScene>(
        placed.tiles, contextAround(k, scene.placement.seed), rig.tileSize, plants));

  // The largest LDIs first, so that the last ones to finish are small.
  std::vector<int> order(kLdiCount);
  std::iota(order.begin(), order.end(), 0);
  std::vector<LdiCamera> cameras(kLdiCount);
  uint64_t totalPixels = 0;
  for (int i = 0; i < kLdiCount; ++i) {
    cameras[i] = ldiCamera(rig, (i / kLdiDirections) % kLdiResolutions, i % kLdiDirections);
    totalPixels += uint64_t(cameras[i].width) * cameras[i].height;
  }
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return uint64_t(cameras[a].width) * cameras[a].height >
           uint64_t(cameras[b].width) * cameras[b].height;
  });

  VegetationBake out;
  out.ldis.resize(kLdiCount);
  std::atomic<uint64_t> rays{0};
  progress.begin("baking LDIs", totalPixels);
  parallelFor(kLdiCount, std::max(1u, threads), [&](size_t n, unsigned) {
    const int i = order[n];
    SamplingSettings sampling = scene.sampling;
    sampling.seed = scene.sampling.seed * 0x9e3779b97f4a7c15ull + uint64_t(i);
    uint64_t cast = 0;
    const Ldi ldi = contexts[i / (kLdiResolutions * kLdiDirections)]->bake(cameras[i], sampling,
                                                                           scene.lighting, cast);
    out.ldis[i] = encodeLdiForFile(ldi);
    rays += cast;
    progress.advance(uint64_t(cameras[i].width) * cameras[i].height);
  });
  progress.end();

  VegetationHeader& h = out.header;
  h.settings = settingsOf(scene, rig);
  h.settings.raysCast = rays;
  for (int k = 0; k < kPrototiles; ++k) {
    h.tiles[k] = placed.tiles[k];
    h.trianglesModelled[k] = contexts[k]->trianglesInCentre();
  }
  h.settings.bakeSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace terralod::veg
