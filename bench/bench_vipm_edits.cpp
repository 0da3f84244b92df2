// Rebuilding what a brush stroke reaches in a VIPM chunk set (vipm_chunk_set.h): a raise and
// then a lower of the same stroke (so the set stays near the source), over 1, 4 and 16 leaves
// of Crater Lake (513², 64 leaves under 16 roots), on two threads. Wall time per stroke, from
// the stroke to every reached chunk's new blob and normal map: what an editor waits for
// before it can swap them in.
//
//   build/release/bench/bench_vipm_edits [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <memory>
#include <vector>

#include "terralod/build/vipm_chunk_set.h"
#include "terralod/materials/dem_classification.h"
#include "terralod/raster/dem_reader.h"

namespace {

using namespace terralod;

VipmChunkSet* craterSet() {
  static std::unique_ptr<VipmChunkSet> set = [] {
    auto reader = DemReader::open(TERRALOD_TEST_DATA_DIR "/crater_lake_0513.bt", {}).value();
    const DemInfo info = reader->info();
    Heightfield heights(info.columns, info.rows);
    if (!reader->readWindow(0, 0, info.columns, info.rows, heights.values().data()).ok())
      return std::unique_ptr<VipmChunkSet>();
    BuildOptions options;
    options.kind = TilesetKind::kVipm;
    options.threads = 2;
    NullProgress progress;
    auto built = VipmChunkSet::build(options, info, std::move(heights),
                                     classifyDem(*reader).value(), 0, progress);
    return built ? std::make_unique<VipmChunkSet>(std::move(*built))
                 : std::unique_ptr<VipmChunkSet>();
  }();
  return set.get();
}

// Crater Lake's cells are 20.14 x 27.25 m: centre and radius of a stroke over 1 leaf (inside
// leaf (1, 1)), 4 (around the corner they share at grid point (64, 64)), and 16 (leaves 0..3
// in both directions, around grid point (128, 128)).
TerrainEdit stroke(int64_t leaves, Brush brush) {
  const double sx = 20.142909356725145, sy = 27.251461988304094;
  switch (leaves) {
    case 1:
      return {brush, 96 * sx, 96 * sy, 300.0, 20.0, 0};
    case 4:
      return {brush, 64 * sx, 64 * sy, 300.0, 20.0, 0};
    default:
      return {brush, 128 * sx, 128 * sy, 2000.0, 20.0, 0};
  }
}

void strokeRebuild(benchmark::State& state) {
  VipmChunkSet* set = craterSet();
  if (!set) return state.SkipWithError("crater_lake_0513.bt did not build");
  size_t changed = 0, strokes = 0;
  bool raise = true;
  for (auto _ : state) {
    const TerrainEdit e = stroke(state.range(0), raise ? Brush::kRaise : Brush::kLower);
    auto nodes = set->apply(std::vector<TerrainEdit>{e}, 2);
    if (!nodes) return state.SkipWithError(nodes.error().message.c_str());
    changed += nodes->size();
    ++strokes;
    raise = !raise;
  }
  state.counters["nodes_changed"] = double(changed) / double(strokes);
}

BENCHMARK(strokeRebuild)->Arg(1)->Arg(4)->Arg(16)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
