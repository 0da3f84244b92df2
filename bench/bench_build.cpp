// Micro-benchmarks of the build's passes (void filling, activations, meshing, encoding) on an
// in-memory rough terrain.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>

#include "bench_terrain.h"
#include "terralod/build/activation_pass.h"
#include "terralod/build/chunk_encoder.h"
#include "terralod/build/chunk_mesher.h"
#include "terralod/build/chunk_pass.h"
#include "terralod/raster/void_fill.h"

namespace terralod {
namespace {

const Heightfield& terrain() {
  static const Heightfield h = bench::roughTerrain(2049);
  return h;
}

struct Prepared {
  TreeLayout layout = makeTreeLayout(2049, 2049, 64).value();
  ErrorBudget budget = makeErrorBudget(layout, 1.0, 1200.0).value();
  MemoryHeights heights{terrain()};
};

// Arg: per mille of the samples that are voids, as pinholes every so many samples (SRTM's
// speckle) or, for 500, the western half as one sea of nodata.
void fillVoidsPass(benchmark::State& state) {
  Heightfield holey = terrain();
  const int64_t perMille = state.range(0);
  for (int32_t y = 0; y < holey.rows(); ++y) {
    for (int32_t x = 0; x < holey.columns(); ++x) {
      const bool sea = perMille == 500 && x < holey.columns() / 2;
      const bool pinhole =
          perMille != 500 && (int64_t(y) * holey.columns() + x) % (1000 / perMille) == 0;
      if (sea || pinhole) holey.row(y)[x] = std::nanf("");
    }
  }
  Heightfield heights = holey;
  for (auto _ : state) {
    state.PauseTiming();  // a fresh copy of the holes, in memory already touched
    std::copy(holey.values().begin(), holey.values().end(), heights.values().begin());
    state.ResumeTiming();
    benchmark::DoNotOptimize(fillVoids(heights, "bench"));
  }
  state.counters["Msamples/s"] =
      benchmark::Counter(2049.0 * 2049.0, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(fillVoidsPass)->Arg(1)->Arg(10)->Arg(500)->Unit(benchmark::kMillisecond);

void activations(benchmark::State& state) {
  Prepared p;
  NullProgress progress;
  ActivationOptions options;
  options.blockCells = int32_t(state.range(0));
  ActivationStats stats;
  for (auto _ : state) {
    stats = {};
    auto grid =
        computeActivations(p.layout, p.budget, p.heights, p.heights, options, progress, &stats);
    benchmark::DoNotOptimize(grid);
  }
  state.counters["Msamples/s"] =
      benchmark::Counter(2049.0 * 2049.0, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["scanned"] = double(stats.trianglesScanned);
}
BENCHMARK(activations)->Arg(256)->Arg(512)->Unit(benchmark::kMillisecond);

void meshLeafLevel(benchmark::State& state) {
  Prepared p;
  NullProgress progress;
  const ActivationGrid grid =
      computeActivations(p.layout, p.budget, p.heights, p.heights, {}, progress).value();
  ChunkMesher mesher(p.layout, p.budget, grid, p.heights);
  const bool encode = state.range(0) != 0;
  uint64_t triangles = 0;
  for (auto _ : state) {
    triangles = 0;
    for (int32_t iy = 0; iy < p.layout.chunksY(p.layout.depth); ++iy)
      for (int32_t ix = 0; ix < p.layout.chunksX(p.layout.depth); ++ix) {
        ChunkMesh mesh = mesher.build(p.layout.depth, ix, iy);
        triangles += mesh.surfaceIndices.size() / 3;
        if (encode)
          benchmark::DoNotOptimize(encodeChunk(
              quantizeChunk(mesh, p.budget, kStaticChunkPayload).value(), 3, kStaticChunkPayload));
      }
  }
  state.counters["Mtriangles/s"] =
      benchmark::Counter(double(triangles) / 1e6, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(meshLeafLevel)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The stages of encoding one level's chunks, each timed on its own.
void encodeStages(benchmark::State& state) {
  Prepared p;
  NullProgress progress;
  const ActivationGrid grid =
      computeActivations(p.layout, p.budget, p.heights, p.heights, {}, progress).value();
  ChunkMesher mesher(p.layout, p.budget, grid, p.heights);
  std::vector<ChunkGeometry> geometries;
  uint64_t triangles = 0;
  for (int32_t iy = 0; iy < p.layout.chunksY(p.layout.depth); ++iy)
    for (int32_t ix = 0; ix < p.layout.chunksX(p.layout.depth); ++ix) {
      ChunkMesh mesh = mesher.build(p.layout.depth, ix, iy);
      triangles += mesh.surfaceIndices.size() / 3;
      ChunkGeometry g;
      g.zStep = p.budget.zStep[p.layout.depth];
      ChunkPart& part = g.parts.emplace_back();
      for (const MeshVertex& v : mesh.vertices)
        part.vertices.push_back(
            {uint16_t(v.x - mesh.x0), uint16_t(v.y - mesh.y0), uint16_t(v.z * 10), 0});
      part.indices = mesh.surfaceIndices;
      part.surfaceIndexCount = uint32_t(part.indices.size());
      part.indices.insert(part.indices.end(), mesh.skirtIndices.begin(), mesh.skirtIndices.end());
      geometries.push_back(std::move(g));
    }
  const int stage = int(state.range(0));
  for (auto _ : state) {
    for (const ChunkGeometry& g : geometries) {
      ChunkGeometry copy = g;
      if (stage >= 1) optimizeChunkPart(copy.parts[0]);
      if (stage >= 2) benchmark::DoNotOptimize(encodeChunk(copy, stage == 2 ? 1 : 3));
    }
  }
  state.counters["Mtriangles/s"] =
      benchmark::Counter(double(triangles) / 1e6, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(encodeStages)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond);

// Encoded size of the leaf level as the mesher orders it (Arg 0: Sierpinski curve, vertices in
// first-use order) and after meshoptimizer's vertex cache and fetch optimisation (Arg 1).
void encodedSize(benchmark::State& state) {
  Prepared p;
  NullProgress progress;
  const ActivationGrid grid =
      computeActivations(p.layout, p.budget, p.heights, p.heights, {}, progress).value();
  ChunkMesher mesher(p.layout, p.budget, grid, p.heights);
  const bool optimise = state.range(0) != 0;
  uint64_t bytes = 0, triangles = 0, vertices = 0;
  for (auto _ : state) {
    bytes = triangles = vertices = 0;
    for (int32_t iy = 0; iy < p.layout.chunksY(p.layout.depth); ++iy)
      for (int32_t ix = 0; ix < p.layout.chunksX(p.layout.depth); ++ix) {
        const ChunkMesh mesh = mesher.build(p.layout.depth, ix, iy);
        ChunkGeometry g = quantizeChunk(mesh, p.budget, kStaticChunkPayload).value();
        if (optimise)
          for (ChunkPart& part : g.parts) optimizeChunkPart(part);
        bytes += encodeChunk(g, 3, kStaticChunkPayload).size();
        triangles += mesh.surfaceIndices.size() / 3;
        vertices += mesh.surfaceVertexCount;
      }
  }
  state.counters["bytes"] = double(bytes);
  state.counters["bytes/vertex"] = double(bytes) / double(vertices);
  state.counters["bytes/triangle"] = double(bytes) / double(triangles);
}
BENCHMARK(encodedSize)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace terralod

BENCHMARK_MAIN();
