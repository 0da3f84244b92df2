#include "terralod/runtime/flight.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

namespace terralod {
namespace {

using nlohmann::json;

constexpr double kStepOfHeight = 0.005;  // per frame, of the height above ground
constexpr double kLookDownDegrees = 15.0;
// The smallest τ the automatic flight is meant for.
constexpr double kMinimumTauPixels = 1.0;
// Far beyond any terrain, and near enough that the spline's lengths, knots and sums stay finite
// (found by the flight fuzzer: an eye at 1.5e61 m made the arc-length table NaN, and its
// conversion to a segment index undefined).
constexpr double kMaxCoordinate = 1e12;

Result<glm::dvec3> point(const json& j, const std::string& subject, const std::string& what) {
  if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
    return makeError(subject, what + " must be an array of three numbers");
  glm::dvec3 p{j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
    return makeError(subject, what + " must be finite");
  if (std::fabs(p.x) > kMaxCoordinate || std::fabs(p.y) > kMaxCoordinate ||
      std::fabs(p.z) > kMaxCoordinate)
    return makeError(subject, what + " must be within 1e12 m of the origin");
  return p;
}

// Centripetal Catmull-Rom (alpha 1/2) between p1 and p2 at u in [0, 1]: no cusps or loops
// where keyframes bunch up.
glm::dvec3 catmullRom(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2,
                      const glm::dvec3& p3, double u) {
  auto knot = [](const glm::dvec3& a, const glm::dvec3& b) {
    return std::max(std::sqrt(glm::length(b - a)), 1e-6);
  };
  const double t0 = 0, t1 = t0 + knot(p0, p1), t2 = t1 + knot(p1, p2), t3 = t2 + knot(p2, p3);
  const double t = t1 + (t2 - t1) * u;
  const glm::dvec3 a1 = (t1 - t) / (t1 - t0) * p0 + (t - t0) / (t1 - t0) * p1;
  const glm::dvec3 a2 = (t2 - t) / (t2 - t1) * p1 + (t - t1) / (t2 - t1) * p2;
  const glm::dvec3 a3 = (t3 - t) / (t3 - t2) * p2 + (t - t2) / (t3 - t2) * p3;
  const glm::dvec3 b1 = (t2 - t) / (t2 - t0) * a1 + (t - t0) / (t2 - t0) * a2;
  const glm::dvec3 b2 = (t3 - t) / (t3 - t1) * a2 + (t - t1) / (t3 - t1) * a3;
  return (t2 - t) / (t2 - t1) * b1 + (t - t1) / (t2 - t1) * b2;
}

// A spline through `points` at parameter s in [0, points.size() - 1]; the ends are extended
// by reflection.
glm::dvec3 spline(const std::vector<glm::dvec3>& points, double s) {
  const int last = int(points.size()) - 1;
  const int i = std::clamp(int(std::floor(s)), 0, last - 1);
  auto at = [&](int k) {
    if (k < 0) return 2.0 * points[0] - points[1];
    if (k > last) return 2.0 * points[size_t(last)] - points[size_t(last - 1)];
    return points[size_t(k)];
  };
  return catmullRom(at(i - 1), at(i), at(i + 1), at(i + 2), s - i);
}

}  // namespace

Result<Flight> parseFlight(std::string_view text, const std::string& subject) {
  const json j = json::parse(text, nullptr, false);
  if (j.is_discarded()) return makeError(subject, "flight is not valid JSON");
  if (!j.is_object()) return makeError(subject, "flight must be a JSON object");
  Flight f;
  if (j.contains("fov_deg")) {
    if (!j["fov_deg"].is_number()) return makeError(subject, "fov_deg must be a number");
    f.fovDegrees = j["fov_deg"].get<double>();
  }
  if (!(f.fovDegrees > 0 && f.fovDegrees < 180))
    return makeError(subject, "fov_deg must be between 0 and 180");
  if (j.contains("size")) {
    const json& s = j["size"];
    if (!s.is_array() || s.size() != 2 || !s[0].is_number_integer() || !s[1].is_number_integer())
      return makeError(subject, "size must be [width, height] in pixels");
    f.width = s[0].get<int>();
    f.height = s[1].get<int>();
  }
  if (f.width <= 0 || f.height <= 0 || f.width > 16384 || f.height > 16384)
    return makeError(subject, "size must be between 1x1 and 16384x16384 pixels");
  if (!j.contains("keyframes") || !j["keyframes"].is_array() || j["keyframes"].size() < 2)
    return makeError(subject, "flight needs \"keyframes\": an array of at least two");
  for (size_t k = 0; k < j["keyframes"].size(); ++k) {
    const json& key = j["keyframes"][k];
    const std::string what = "keyframe " + std::to_string(k);
    if (!key.is_object() || !key.contains("eye") || !key.contains("target"))
      return makeError(subject, what + " needs \"eye\" and \"target\"");
    auto eye = point(key["eye"], subject, what + " eye");
    if (!eye) return eye.error();
    auto target = point(key["target"], subject, what + " target");
    if (!target) return target.error();
    if (glm::length(*target - *eye) <= 0.0)
      return makeError(subject, what + ": eye and target are the same point");
    f.keyframes.push_back({*eye, *target});
  }
  f.frames = int(f.keyframes.size());
  if (j.contains("frames")) {
    if (!j["frames"].is_number_integer() || j["frames"].get<int64_t>() < 1 ||
        j["frames"].get<int64_t>() > 1000000)
      return makeError(subject, "frames must be a whole number from 1 to 1000000");
    f.frames = j["frames"].get<int>();
  }
  return f;
}

std::string flightToJson(const Flight& f) {
  json j;
  j["fov_deg"] = f.fovDegrees;
  j["size"] = {f.width, f.height};
  j["frames"] = f.frames;
  j["keyframes"] = json::array();
  for (const Keyframe& k : f.keyframes)
    j["keyframes"].push_back(
        {{"eye", {k.eye.x, k.eye.y, k.eye.z}}, {"target", {k.target.x, k.target.y, k.target.z}}});
  return j.dump(1);
}

std::vector<Camera> flightCameras(const Flight& f) {
  std::vector<Camera> cameras;
  if (f.keyframes.empty() || f.frames <= 0) return cameras;
  auto camera = [&](const glm::dvec3& eye, const glm::dvec3& target) {
    Camera c;
    c.eye = eye;
    c.target = target;
    c.hfovDegrees = f.fovDegrees;
    c.width = f.width;
    c.height = f.height;
    return c;
  };
  if (int(f.keyframes.size()) == f.frames || f.keyframes.size() == 1) {
    for (int i = 0; i < f.frames; ++i) {
      const Keyframe& k = f.keyframes[std::min(size_t(i), f.keyframes.size() - 1)];
      cameras.push_back(camera(k.eye, k.target));
    }
    return cameras;
  }
  std::vector<glm::dvec3> eyes, targets;
  for (const Keyframe& k : f.keyframes) {
    eyes.push_back(k.eye);
    targets.push_back(k.target);
  }
  // Arc length of the eye's path, densely tabulated, to sample it at even steps.
  const double segments = double(eyes.size() - 1);
  const int samples = std::max(64, int(segments) * 64);
  std::vector<double> length(size_t(samples) + 1, 0.0);
  glm::dvec3 previous = spline(eyes, 0.0);
  for (int i = 1; i <= samples; ++i) {
    const glm::dvec3 p = spline(eyes, segments * i / samples);
    length[size_t(i)] = length[size_t(i - 1)] + glm::length(p - previous);
    previous = p;
  }
  for (int frame = 0; frame < f.frames; ++frame) {
    const double want = f.frames == 1 ? 0.0 : length.back() * frame / (f.frames - 1);
    const auto it = std::lower_bound(length.begin(), length.end(), want);
    const size_t i = std::clamp<size_t>(size_t(it - length.begin()), 1, size_t(samples));
    const double span = length[i] - length[i - 1];
    const double fraction = span > 0 ? (want - length[i - 1]) / span : 0.0;
    const double s = segments * (double(i - 1) + std::clamp(fraction, 0.0, 1.0)) / samples;
    glm::dvec3 eye = spline(eyes, s), target = spline(targets, s);
    if (glm::length(target - eye) <= 1e-9) target = eye + glm::dvec3(0, 1e-3, -1e-3);
    cameras.push_back(camera(eye, target));
  }
  return cameras;
}

double groundHeightBound(const ChunkTree& tree, double x, double y) {
  auto contains = [&](const ChunkNode& n) {
    return x >= n.box.min[0] && x <= n.box.max[0] && y >= n.box.min[1] && y <= n.box.max[1];
  };
  for (uint32_t r = 0; r < tree.rootCount(); ++r) {
    if (!contains(tree.node(r))) continue;
    uint32_t i = r;
    for (bool descended = true; descended;) {
      descended = false;
      const ChunkNode& n = tree.node(i);
      for (uint32_t c = n.firstChild; c < n.firstChild + n.childCount; ++c)
        if (contains(tree.node(c))) {
          i = c;
          descended = true;
          break;
        }
    }
    return tree.node(i).box.max[2];
  }
  return tree.extent().max[2];
}

ReliefGrid reliefGrid(const ChunkTree& tree) {
  constexpr double kMostCells = 512;
  const Box& e = tree.extent();
  const glm::dvec2 size{std::max(e.max[0] - e.min[0], 0.0), std::max(e.max[1] - e.min[1], 0.0)};
  int level = 0;
  auto cellSize = [&](int l) {
    return glm::dvec2(double(tree.chunkCells(l)) * tree.spacing()[0],
                      double(tree.chunkCells(l)) * tree.spacing()[1]);
  };
  while (level + 1 < tree.levelCount() && tree.chunkCells(level + 1) > 0 &&
         size.x / cellSize(level + 1).x <= kMostCells &&
         size.y / cellSize(level + 1).y <= kMostCells)
    ++level;
  ReliefGrid g;
  g.origin = {e.min[0], e.min[1]};
  g.cellSize = cellSize(level);
  g.columns = std::max(1, int(std::ceil(size.x / g.cellSize.x)));
  g.rows = std::max(1, int(std::ceil(size.y / g.cellSize.y)));
  g.range.assign(size_t(g.columns) * size_t(g.rows), 0.0);
  for (const ChunkNode& n : tree.nodes()) {
    if (n.level != level) continue;
    const int i = int(std::floor((n.box.min[0] - g.origin.x) / g.cellSize.x + 0.5));
    const int j = int(std::floor((n.box.min[1] - g.origin.y) / g.cellSize.y + 0.5));
    if (i < 0 || j < 0 || i >= g.columns || j >= g.rows) continue;
    g.range[size_t(j) * size_t(g.columns) + size_t(i)] = std::max(n.box.max[2] - n.box.min[2], 0.0);
  }
  return g;
}

glm::dvec2 mostRuggedPoint(const ReliefGrid& g, const Box& e) {
  const glm::dvec2 lo{e.min[0], e.min[1]}, hi{e.max[0], e.max[1]};
  const glm::dvec2 centre = 0.5 * (lo + hi), size = hi - lo;
  if (g.columns < 1 || g.rows < 1 || g.range.size() != size_t(g.columns) * size_t(g.rows) ||
      !(g.cellSize.x > 0) || !(g.cellSize.y > 0))
    return centre;
  // Sums of the ranges over every rectangle from cell (0, 0): a window's sum in four look-ups.
  const size_t stride = size_t(g.columns) + 1;
  std::vector<double> sum(stride * (size_t(g.rows) + 1), 0.0);
  for (int j = 0; j < g.rows; ++j)
    for (int i = 0; i < g.columns; ++i)
      sum[size_t(j + 1) * stride + size_t(i + 1)] =
          g.range[size_t(j) * size_t(g.columns) + size_t(i)] +
          sum[size_t(j) * stride + size_t(i + 1)] + sum[size_t(j + 1) * stride + size_t(i)] -
          sum[size_t(j) * stride + size_t(i)];
  const double side = std::min(size.x, size.y) / 8.0;
  const int wx = std::clamp(int(std::lround(side / g.cellSize.x)), 1, g.columns);
  const int wy = std::clamp(int(std::lround(side / g.cellSize.y)), 1, g.rows);
  const glm::dvec2 inLo = lo + 0.15 * size, inHi = hi - 0.15 * size;
  glm::dvec2 best = centre;
  double bestScore = -1.0, bestDistance = 0.0;
  for (int j = 0; j + wy <= g.rows; ++j)
    for (int i = 0; i + wx <= g.columns; ++i) {
      const glm::dvec2 at = g.origin + glm::dvec2(i + 0.5 * wx, j + 0.5 * wy) * g.cellSize;
      if (at.x < inLo.x || at.x > inHi.x || at.y < inLo.y || at.y > inHi.y) continue;
      const double score =
          sum[size_t(j + wy) * stride + size_t(i + wx)] - sum[size_t(j) * stride + size_t(i + wx)] -
          sum[size_t(j + wy) * stride + size_t(i)] + sum[size_t(j) * stride + size_t(i)];
      const double distance = glm::length(at - centre);
      // Sums that differ by rounding only are ties.
      const double tolerance = 1e-9 * std::max(std::fabs(bestScore), 1.0);
      if (score > bestScore + tolerance ||
          (score >= bestScore - tolerance && distance < bestDistance)) {
        best = at;
        bestScore = score;
        bestDistance = distance;
      }
    }
  return best;
}

Flight autoFlight(const ChunkTree& tree, int width, int height, double fovDegrees, int maxFrames) {
  Flight f;
  f.width = width;
  f.height = height;
  f.fovDegrees = fovDegrees;
  const Box& e = tree.extent();
  const glm::dvec2 lo{e.min[0], e.min[1]}, hi{e.max[0], e.max[1]};
  const glm::dvec2 size = hi - lo;
  const double diagonal = std::max(glm::length(size), 1.0);
  // Low, but not so low that the finest level's error would reach a pixel: closer than that
  // the data itself cannot meet the error bound, whatever the selection does.
  const double pixelsPerRadian =
      double(width) / (2.0 * std::tan(fovDegrees * std::numbers::pi / 360.0));
  const double finestError = tree.levelError(tree.levelCount() - 1);
  const double clearance = std::max({diagonal / 200.0, 4.0 * std::max(tree.spacing()[0], 1e-3),
                                     finestError * pixelsPerRadian / kMinimumTauPixels});
  const double ahead = 8.0 * clearance;
  // The eye looks at the ground a little way ahead: 15 degrees down, or steeper when the data
  // is small next to the clearance, so that it stays in view.
  const double lookDistance = std::min(ahead, 0.25 * diagonal);
  const double tanDown =
      std::max(std::tan(kLookDownDegrees * std::numbers::pi / 180.0), clearance / lookDistance);
  // Low over the data towards its most rugged place, from the farthest corner of its inner
  // 80 % (the first of south-west, south-east, north-west, north-east among equals), so that
  // place is ahead all along the pass and the climb starts over it.
  const glm::dvec2 end = mostRuggedPoint(reliefGrid(tree), e);
  glm::dvec2 start = lo + 0.1 * size;
  for (const glm::dvec2 corner : {glm::dvec2(0.9, 0.1), glm::dvec2(0.1, 0.9), glm::dvec2(0.9, 0.9)})
    if (glm::length(lo + corner * size - end) > glm::length(start - end) + 1e-9 * diagonal)
      start = lo + corner * size;
  const glm::dvec2 heading =
      glm::length(end - start) > 0 ? glm::normalize(end - start) : glm::dvec2(0.0, 1.0);
  const double passLength = glm::length(end - start);

  // The highest ground under the next stretch of the path, so the eye rises before a ridge.
  auto groundAhead = [&](glm::dvec2 p) {
    double g = -1e300;
    for (int k = 0; k <= 8; ++k) {
      const glm::dvec2 q = p + heading * (ahead * k / 8.0);
      g = std::max(g, groundHeightBound(tree, q.x, q.y));
    }
    return g;
  };
  auto push = [&](const glm::dvec3& eye, const glm::dvec3& target) {
    f.keyframes.push_back({eye, target});
    return maxFrames > 0 && int(f.keyframes.size()) >= maxFrames;
  };
  auto aboveGround = [&](const glm::dvec3& eye) {
    return std::max(eye.z - groundHeightBound(tree, eye.x, eye.y), clearance * 0.25);
  };

  // The low pass.
  glm::dvec2 p = start;
  double z = groundAhead(p) + clearance;
  double travelled = 0.0;
  glm::dvec3 target;
  for (;;) {
    const glm::dvec3 eye{p.x, p.y, z};
    target = {p.x + heading.x * lookDistance, p.y + heading.y * lookDistance,
              z - lookDistance * tanDown};
    if (push(eye, target) || travelled >= passLength) break;
    const double step = kStepOfHeight * aboveGround(eye);
    const double rise = std::clamp(groundAhead(p) + clearance - z, -0.6 * step, 0.6 * step);
    const double forward = std::sqrt(step * step - rise * rise);
    p += heading * forward;
    z += rise;
    travelled += forward;
  }
  if (maxFrames > 0 && int(f.keyframes.size()) >= maxFrames) {
    f.frames = int(f.keyframes.size());
    return f;
  }
  f.climbStart = int(f.keyframes.size());

  // The climb: up and back until the whole extent is in view, turning towards its centre.
  const glm::dvec3 centre{lo.x + 0.5 * size.x, lo.y + 0.5 * size.y, 0.5 * (e.min[2] + e.max[2])};
  const double finalHeight = e.max[2] + 0.9 * diagonal;
  const glm::dvec2 finalXY = glm::dvec2(centre) - heading * (0.55 * diagonal);
  const glm::dvec3 from{p.x, p.y, z};
  const glm::dvec3 aim = target;
  glm::dvec3 eye = from;
  for (;;) {
    const double step = kStepOfHeight * aboveGround(eye);
    const glm::dvec3 goal{finalXY.x, finalXY.y, finalHeight};
    const glm::dvec3 towards = goal - eye;
    const double remaining = glm::length(towards);
    // How far up the climb is, on a log scale (each frame multiplies the height).
    const double u =
        std::clamp(std::log(std::max(eye.z - from.z + clearance, clearance) / clearance) /
                       std::log((finalHeight - from.z + clearance) / clearance),
                   0.0, 1.0);
    const double blend = u * u * (3.0 - 2.0 * u);
    const glm::dvec3 look = aim + (centre - aim) * blend;
    if (push(eye, look) || remaining <= 1e-6) break;
    // Mostly up at first, so the horizontal motion never outruns 0.5 % of the height.
    glm::dvec3 move = towards / remaining * std::min(step, remaining);
    eye += move;
  }
  f.frames = int(f.keyframes.size());
  return f;
}

Flight autoFlightClimb(const ChunkTree& tree, int width, int height, double fovDegrees,
                       int maxFrames) {
  Flight f = autoFlight(tree, width, height, fovDegrees);
  f.keyframes.erase(f.keyframes.begin(), f.keyframes.begin() + f.climbStart);
  if (maxFrames > 0 && int(f.keyframes.size()) > maxFrames) f.keyframes.resize(size_t(maxFrames));
  f.frames = int(f.keyframes.size());
  f.climbStart = 0;
  return f;
}

}  // namespace terralod
