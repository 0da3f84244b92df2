#pragma once
// bench's run as one call: fly the cameras (bench_flight), then summarise every frame's figures
// into bench's JSON. The caller opens the tileset and the source, makes the scene and the
// cameras, and writes or prints what comes back.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "terralod/core/progress.h"
#include "terralod/core/result.h"
#include "terralod/measure/bench_flight.h"
#include "terralod/render/terrain_scene.h"
#include "terralod/runtime/view.h"

namespace terralod {

/// What bench's JSON says about the run besides the flight's figures.
struct BenchRunInfo {
  std::string tileset;         ///< as given (a path or a URL)
  std::string gl;              ///< the GL context's description
  std::string source;          ///< the source raster as given; shown when the options measure one
  double cacheMB = 0;          ///< the scene's chunk memory budget
  bool horizonCulling = true;  ///< the scene leaves out chunks nearer terrain hides
};

struct BenchRun {
  BenchFlightResult flight;  ///< every frame's figures (and the contact sheet's images)
  nlohmann::json summary;    ///< bench's JSON
};

/// The figures of `flight` (flown over `scene` with `options`), bench's JSON. `scene`'s
/// residency counters are read as they are now, i.e. after the flight.
nlohmann::json summarizeBench(const TerrainScene& scene, const BenchFlightResult& flight,
                              const BenchFlightOptions& options, const BenchRunInfo& info);

/// Flies `cameras` (at least one) over `scene` and summarises the flight: flyBench, then
/// summarizeBench, with the image size of the first camera. Progress is one step per frame.
Result<BenchRun> runBenchFlight(TerrainScene& scene, const std::vector<Camera>& cameras,
                                const BenchFlightOptions& options, const BenchRunInfo& info,
                                Progress& progress);

}  // namespace terralod
