#pragma once
// Camera flights: the JSON file bench, render and the viewer share, its smooth interpolation to
// frames, and a default flight made from a tileset's extent.
//
//   {"fov_deg": 60, "size": [1024, 768], "frames": 300,
//    "keyframes": [{"eye": [x, y, z], "target": [x, y, z]}, ...]}
//
// World metres, z up. Eye and target each follow a centripetal Catmull-Rom spline through the
// keyframes, sampled at equal steps of the eye path's length, so speed is even.

#include <string>
#include <string_view>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/view.h"

namespace terralod {

struct Keyframe {
  glm::dvec3 eye{0.0}, target{0.0};
};

struct Flight {
  double fovDegrees = 60.0;
  int width = 1024, height = 768;
  int frames = 0;  ///< frames to fly; with keyframes.size() == frames they are the frames
  std::vector<Keyframe> keyframes;
  int climbStart = 0;  ///< autoFlight(): the frame where the climb begins (not in the JSON)
};

/// Parses and validates a flight (at least two keyframes, positive size and frame count, a
/// field of view in (0, 180), coordinates finite and within 1e12 m of the origin, eye !=
/// target); `subject` names the file.
Result<Flight> parseFlight(std::string_view json, const std::string& subject);
/// The flight as JSON, keyframes and all (what the viewer records).
std::string flightToJson(const Flight& flight);

/// One camera per frame.
std::vector<Camera> flightCameras(const Flight& flight);

/// Height ranges on a regular grid of cells over the data, row by row from the south-west.
struct ReliefGrid {
  int columns = 0, rows = 0;
  glm::dvec2 origin{0.0};     ///< world x, y of the south-west corner of cell (0, 0)
  glm::dvec2 cellSize{1.0};   ///< metres
  std::vector<double> range;  ///< highest minus lowest height in each cell (0 where no data)
};

/// The tileset's relief without reading a chunk: the height ranges of the chunks' boxes at the
/// finest level that has at most 512 chunks along either side.
ReliefGrid reliefGrid(const ChunkTree& tree);

/// Where the relief is most rugged: the centre of the square window of cells, 1/8 of the
/// extent's shorter side wide, with the largest sum of cell ranges (the mean local relief),
/// among windows whose centre lies at least 15 % of the extent's width and height from its
/// edges. Ties go to the window nearest the extent's centre, so flat data gives about the
/// centre. Deterministic; without any such window, the extent's centre.
glm::dvec2 mostRuggedPoint(const ReliefGrid& grid, const Box& extent);

/// The default flight over a tileset: a low pass towards the most rugged place of the data
/// (mostRuggedPoint(reliefGrid(tree))), from the corner of the data's inner 80 % farthest from
/// it, looking ahead and 15 degrees down (steeper over data small next to the height) at about
/// 1/200 of the extent's diagonal above the ground (higher where the finest level's error would
/// otherwise exceed 1 pixel, so any τ >= 1 can be met), then, from above that place, a climb
/// that turns to look at the whole. Every frame moves the eye at most 0.5 % of its height above
/// the ground (a 60 fps flight), so the flight has as many frames as that takes; `maxFrames`
/// (if > 0) keeps only its first frames. Every frame is a keyframe.
Flight autoFlight(const ChunkTree& tree, int width, int height, double fovDegrees,
                  int maxFrames = 0);

/// Only the climb of autoFlight(): every level's chunks merge on the way up, which is where
/// pops would show. `maxFrames` as above.
Flight autoFlightClimb(const ChunkTree& tree, int width, int height, double fovDegrees,
                       int maxFrames = 0);

/// An upper bound of the terrain's height at (x, y): the top of the finest chunk over it, or
/// the extent's top outside the data.
double groundHeightBound(const ChunkTree& tree, double x, double y);

}  // namespace terralod
