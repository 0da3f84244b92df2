#include "terralod/vegetation/plant_models.h"

// The plants of the vegetation scenes (papers/tiling-layered-depth-images.md §3, §6), built
// from a few kinds of parts over a tiny mesh builder:
//   tube    a stem or stalk: rings of vertices around a centreline;
//   ribbon  a blade, petal, bract or narrow leaf: cross-sections along a centreline, flat, V-
//           shaped or cupped, closing to a point where the half-width reaches zero;
//   grid    anything else (a heart-shaped leaf, a seed disc, a head's back): rows of vertices
//           joined by quads.
// A row whose vertices coincide (a leaf's centre, a petal's tip, a dome's pole) is how fans
// and points are made: the builder drops the zero-area triangles and the unused vertices.
// Everything random comes from a splitmix64 generator seeded by (seed, species, version), never
// from <random>'s distributions, whose output differs between standard libraries.

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <vector>

#include "random_stream.h"

#include <glm/geometric.hpp>

namespace terralod::veg {
namespace {
// File-local helpers in their own namespace: unity builds put four files in one unit.
namespace plantgen {

constexpr float kPi = std::numbers::pi_v<float>;
constexpr float kTwoPi = 2.0f * kPi;
constexpr double kGoldenAngle = 2.399963229728653;  // π (3 − √5): the sunflower's phyllotaxis
const glm::vec3 kUp(0.0f, 0.0f, 1.0f);

// ---------------------------------------------------------------------------------------------
// Small maths

float sq(float x) {
  return x * x;
}

float smoothstep(float edge0, float edge1, float x) {
  const float t = std::clamp((x - edge0) / (edge1 - edge0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

/// The unit vector `tilt` radians from +z towards the horizontal direction `azimuth`.
glm::vec3 spherical(float tilt, float azimuth) {
  return {std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth), std::cos(tilt)};
}

/// Horizontal unit vector at `azimuth` (radians from +x).
glm::vec3 horizontal(float azimuth) {
  return {std::cos(azimuth), std::sin(azimuth), 0.0f};
}

/// An orthonormal frame; at(a, b, c) is origin + a·x + b·y + c·z.
struct Frame {
  glm::vec3 origin, x, y, z;
  glm::vec3 at(float a, float b, float c) const { return origin + a * x + b * y + c * z; }
  /// The unit vector at `angle` in the frame's xy plane.
  glm::vec3 radial(float angle) const { return std::cos(angle) * x + std::sin(angle) * y; }
};

/// A frame whose z axis is `normal` and whose x axis is horizontal (when normal is not +z).
Frame frameFacing(glm::vec3 origin, glm::vec3 normal) {
  glm::vec3 x = glm::cross(kUp, normal);
  x = glm::dot(x, x) < 1e-8f ? glm::vec3(1, 0, 0) : glm::normalize(x);
  return {origin, x, glm::cross(normal, x), normal};
}

// ---------------------------------------------------------------------------------------------
// Randomness: splitmix64 (Steele, Lea, Flood 2014), whose output is fixed by its definition.

uint64_t mixSeed(uint64_t a, uint64_t b) {
  uint64_t state = a ^ (b * 0xd1342543de82ef95ULL);
  return splitmix64(state);
}

class Rng {
 public:
  explicit Rng(uint64_t seed) : mState(seed) {}
  uint64_t next() { return splitmix64(mState); }
  /// Uniform in [0, 1), 24 bits.
  float uniform() { return float(next() >> 40) * 0x1p-24f; }
  float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
  float symmetric(float amplitude) { return uniform(-amplitude, amplitude); }
  /// Uniform in [lo, hi], both included.
  int integer(int lo, int hi) { return lo + int(next() % uint64_t(hi - lo + 1)); }
  bool chance(float p) { return uniform() < p; }

 private:
  uint64_t mState;
};

// ---------------------------------------------------------------------------------------------
// Colours: sRGB components in [0, 1] until the builder stores them as bytes.

using Colour = glm::vec3;

Colour hsv(float hueDegrees, float saturation, float value) {
  const float h = std::fmod(hueDegrees + 360.0f, 360.0f) / 60.0f;
  const float c = value * saturation, x = c * (1.0f - std::abs(std::fmod(h, 2.0f) - 1.0f));
  const float m = value - c;
  switch (int(h)) {  // the sextant of the colour wheel
    case 0:
      return Colour(c, x, 0) + m;
    case 1:
      return Colour(x, c, 0) + m;
    case 2:
      return Colour(0, c, x) + m;
    case 3:
      return Colour(0, x, c) + m;
    case 4:
      return Colour(x, 0, c) + m;
    default:
      return Colour(c, 0, x) + m;
  }
}

/// `colour` a little lighter or darker (by up to ±amount) and a little off in each channel.
Colour vary(Colour colour, Rng& rng, float amount) {
  const float brightness = 1.0f + rng.symmetric(amount);
  Colour out;
  for (int i = 0; i < 3; ++i) out[i] = colour[i] * brightness * (1.0f + rng.symmetric(amount / 3));
  return glm::clamp(out, 0.0f, 1.0f);
}

std::array<uint8_t, 3> toBytes(Colour c) {
  std::array<uint8_t, 3> out;
  for (int i = 0; i < 3; ++i) out[i] = uint8_t(std::lround(std::clamp(c[i], 0.0f, 1.0f) * 255));
  return out;
}

// ---------------------------------------------------------------------------------------------
// The mesh builder

/// Triangles at most this large (m²) are dropped: collapsed rows make them on purpose.
constexpr double kMinTriangleArea = 1e-11;

class MeshBuilder {
 public:
  void reserve(size_t vertices, size_t triangles) {
    mMesh.positions.reserve(vertices);
    mMesh.triangles.reserve(triangles);
    mMesh.colors.reserve(triangles);
  }

  uint32_t vertex(glm::vec3 p) {
    mMesh.positions.push_back(p);
    return uint32_t(mMesh.positions.size() - 1);
  }

  void triangle(uint32_t a, uint32_t b, uint32_t c, Colour colour) {
    const glm::dvec3 pa(mMesh.positions[a]), pb(mMesh.positions[b]), pc(mMesh.positions[c]);
    if (0.5 * glm::length(glm::cross(pb - pa, pc - pa)) <= kMinTriangleArea) return;
    mMesh.triangles.push_back({a, b, c});
    mMesh.colors.push_back(toBytes(colour));
  }

  /// The quad a-b-c-d (in order round it) as two triangles.
  void quad(uint32_t a, uint32_t b, uint32_t c, uint32_t d, Colour colour) {
    triangle(a, b, c, colour);
    triangle(a, c, d, colour);
  }

  /// `rows` × `columns` vertices position(row, column), neighbouring rows joined by quads
  /// coloured colour(row, column) (the quad from that vertex on); `wrap` joins the last column
  /// to the first (a tube).
  template <class Position, class ColourOf>
  void grid(int rows, int columns, bool wrap, Position position, ColourOf colour) {
    const uint32_t first = uint32_t(mMesh.positions.size());
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < columns; ++j) vertex(position(i, j));
    const auto at = [&](int i, int j) { return first + uint32_t(i * columns + j % columns); };
    for (int i = 0; i + 1 < rows; ++i)
      for (int j = 0; j < (wrap ? columns : columns - 1); ++j)
        quad(at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j), colour(i, j));
  }

  /// The finished mesh: unused vertices dropped, bounds measured.
  PlantMesh finish() && {
    PlantMesh out;
    std::vector<uint32_t> remap(mMesh.positions.size(), UINT32_MAX);
    out.triangles = std::move(mMesh.triangles);
    out.colors = std::move(mMesh.colors);
    out.positions.reserve(mMesh.positions.size());
    for (auto& tri : out.triangles)
      for (uint32_t& index : tri) {
        if (remap[index] == UINT32_MAX) {
          remap[index] = uint32_t(out.positions.size());
          out.positions.push_back(mMesh.positions[index]);
        }
        index = remap[index];
      }
    for (const glm::vec3& p : out.positions) {
      out.tightRadius = std::max(out.tightRadius, std::sqrt(p.x * p.x + p.y * p.y));
      out.height = std::max(out.height, p.z);
    }
    return out;
  }

 private:
  PlantMesh mMesh;
};

// ---------------------------------------------------------------------------------------------
// Centrelines, tubes and ribbons

/// A curve from `start`, `length` long, sampled at the arc-length fractions `ts` (0 first, 1
/// last): `direction(t)` (unit) is integrated by the midpoint rule between samples.
template <class Direction>
std::vector<glm::vec3> centrelineAt(glm::vec3 start, float length, const std::vector<float>& ts,
                                    Direction direction) {
  std::vector<glm::vec3> points{start};
  for (size_t k = 1; k < ts.size(); ++k)
    points.push_back(points.back() +
                     (length * (ts[k] - ts[k - 1])) * direction(0.5f * (ts[k] + ts[k - 1])));
  return points;
}

std::vector<float> evenSteps(int segments) {
  std::vector<float> ts(size_t(segments) + 1);
  for (int k = 0; k <= segments; ++k) ts[size_t(k)] = float(k) / float(segments);
  return ts;
}

template <class Direction>
std::vector<glm::vec3> centreline(glm::vec3 start, float length, int segments,
                                  Direction direction) {
  return centrelineAt(start, length, evenSteps(segments), direction);
}

/// Unit tangents of a polyline (central differences, one-sided at the ends).
std::vector<glm::vec3> tangentsOf(const std::vector<glm::vec3>& p) {
  std::vector<glm::vec3> t(p.size());
  for (size_t i = 0; i < p.size(); ++i)
    t[i] = glm::normalize(p[std::min(i + 1, p.size() - 1)] - p[i == 0 ? 0 : i - 1]);
  return t;
}

/// The point at fraction t of a polyline's samples.
glm::vec3 pointAt(const std::vector<glm::vec3>& p, float t) {
  const float u = std::clamp(t, 0.0f, 1.0f) * float(p.size() - 1);
  const size_t k = std::min(size_t(u), p.size() - 2);
  return glm::mix(p[k], p[k + 1], u - float(k));
}

/// A tube of `sides` round a centreline, radius(t) at fraction t along it, coloured
/// colour(ring, side). Its rings are carried along by parallel transport, so it never twists.
template <class Radius, class ColourOf>
void tube(MeshBuilder& mb, const std::vector<glm::vec3>& centre, int sides, Radius radius,
          ColourOf colour) {
  const std::vector<glm::vec3> t = tangentsOf(centre);
  std::vector<glm::vec3> u(centre.size()), v(centre.size());
  for (size_t i = 0; i < centre.size(); ++i) {
    const glm::vec3 previous = i == 0 ? frameFacing({}, t[0]).x : u[i - 1];
    u[i] = glm::normalize(previous - t[i] * glm::dot(previous, t[i]));
    v[i] = glm::cross(t[i], u[i]);
  }
  const int rings = int(centre.size());
  mb.grid(
      rings, sides, true,
      [&](int i, int j) {
        const float a = kTwoPi * float(j) / float(sides);
        const float r = radius(float(i) / float(rings - 1));
        return centre[size_t(i)] + r * (std::cos(a) * u[size_t(i)] + std::sin(a) * v[size_t(i)]);
      },
      colour);
}

/// A ribbon's cross-section: its centre, unit across and normal directions, half-width.
struct Section {
  glm::vec3 centre, across, normal;
  float halfWidth;
};

/// Sections along a centreline: across is side(t) made perpendicular to the curve (a side that
/// turns along it twists the ribbon), half-width halfWidth(t), t the fraction along.
template <class Side, class HalfWidth>
std::vector<Section> sectionsAlong(const std::vector<glm::vec3>& centre, Side side,
                                   HalfWidth halfWidth) {
  const std::vector<glm::vec3> tangent = tangentsOf(centre);
  std::vector<Section> out(centre.size());
  for (size_t i = 0; i < centre.size(); ++i) {
    const float t = float(i) / float(centre.size() - 1);
    const glm::vec3 s = side(t);
    const glm::vec3 across = glm::normalize(s - tangent[i] * glm::dot(s, tangent[i]));
    out[i] = {centre[i], across, glm::cross(tangent[i], across), std::max(0.0f, halfWidth(t))};
  }
  return out;
}

/// A ribbon through `sections` with `columns` vertices across: the vertex at x ∈ [−1, 1] lies
/// at centre + x·h·across + cup·x²·h·normal (h the half-width), so 2 columns make a flat strap,
/// 3 a V (a keeled blade, a channelled petal) and more a rounded cup. colour(row, column).
template <class ColourOf>
void ribbon(MeshBuilder& mb, const std::vector<Section>& sections, int columns, float cup,
            ColourOf colour) {
  mb.grid(
      int(sections.size()), columns, false,
      [&](int i, int j) {
        const Section& s = sections[size_t(i)];
        const float x = -1.0f + 2.0f * float(j) / float(columns - 1);
        return s.centre + (x * s.halfWidth) * s.across + (cup * x * x * s.halfWidth) * s.normal;
      },
      colour);
}

/// A closed ellipsoidal bud: `radius` wide, `length` long along the frame's z from its origin.
void bud(MeshBuilder& mb, Rng& rng, const Frame& f, float radius, float length, Colour colour,
         Colour tip) {
  constexpr int kRows = 5, kSides = 8;
  mb.grid(
      kRows, kSides, true,
      [&](int i, int j) {
        const float polar = kPi * float(i) / float(kRows - 1);  // 0 at the foot, π at the tip
        const glm::vec3 around = f.radial(kTwoPi * float(j) / kSides);
        return f.origin + radius * std::sin(polar) * around +
               0.5f * length * (1.0f - std::cos(polar)) * f.z;
      },
      [&](int i, int) { return vary(i + 2 >= kRows ? tip : colour, rng, 0.06f); });
}

/// `count` small pointed bracts round a head's foot (the frame's origin, z the way the head
/// faces), each leaving it at `angle` radians from z and turning `curl` radians further away
/// from z by its tip (bending back towards the stem).
void bracts(MeshBuilder& mb, Rng& rng, const Frame& f, int count, float footRadius, float length,
            float halfWidth, float angle, float curl, Colour colour) {
  for (int k = 0; k < count; ++k) {
    const float a = kTwoPi * (float(k) + rng.symmetric(0.2f)) / float(count);
    const glm::vec3 radial = f.radial(a), tangential = f.radial(a + 0.5f * kPi);
    const float lean = angle + rng.symmetric(0.15f), bend = curl * rng.uniform(0.7f, 1.3f);
    const auto centre = centreline(f.origin + footRadius * radial, length, 2, [&](float t) {
      const float b = lean + bend * t;
      return std::sin(b) * radial + std::cos(b) * f.z;
    });
    const Colour c = vary(colour, rng, 0.08f);
    ribbon(mb,
           sectionsAlong(
               centre, [&](float) { return tangential; },
               [&](float t) { return halfWidth * (1.0f - t); }),
           3, -0.3f, [&](int, int) { return c; });
  }
}

// ---------------------------------------------------------------------------------------------
// Sunflower: a thick hairy stem bending over at the neck into a heavy head that faces sideways
// and up; heart-shaped leaves on long petioles, alternate, up the stem; the head a dark disc
// of seeds in a golden-angle spiral (most of the triangles), a ring of yellow ray petals, green
// bracts behind them and a green back.

struct SunflowerHead {
  float radius = 0;  ///< of the seed disc
  float depth = 0;   ///< from the disc back to where the neck joins
  float dome = 0;    ///< how far the disc's centre stands proud of its rim
  int seeds = 0;
  int petals = 0;
  float petalLength = 0, petalWidth = 0;
  Colour petal, seed, centre, florets, back, bract;
};

float discHeight(const SunflowerHead& h, float rho) {
  return h.dome * (1.0f - sq(rho / h.radius));
}

/// The disc under the seeds, dark, so no light shows between them.
void seedDisc(MeshBuilder& mb, Rng& rng, const Frame& f, const SunflowerHead& h) {
  constexpr int kRings = 4, kSides = 40;
  mb.grid(
      kRings + 1, kSides, true,
      [&](int i, int j) {
        const float rho = h.radius * float(i) / kRings;
        const glm::vec3 p = f.origin + rho * f.radial(kTwoPi * float(j) / kSides);
        return p + (discHeight(h, rho) - 0.001f) * f.z;
      },
      [&](int, int) { return vary(h.seed * 0.8f, rng, 0.1f); });
}

/// A seed's colour by where it is (q: distance from the middle over the disc radius): young
/// closed florets in the middle are olive, ripening seeds dark brown, the open florets of the
/// outer rings orange-brown with pollen.
Colour seedColour(const SunflowerHead& h, float q, Rng& rng) {
  Colour c = glm::mix(h.centre, h.seed, smoothstep(0.06f, 0.2f, q));
  c = glm::mix(c, h.florets, smoothstep(0.8f, 0.93f, q));
  return vary(c, rng, 0.18f);
}

/// The seeds: Vogel's model of the sunflower, seed i at radius ∝ √i and angle i × the golden
/// angle, so each has the same area and they pack without gaps. Each seed is a bump: a hexagon
/// on the disc, a smaller hexagon raised above it and a point (13 vertices, 18 triangles).
void seeds(MeshBuilder& mb, Rng& rng, const Frame& f, const SunflowerHead& h) {
  const float outer = 0.97f * h.radius;
  const float spacing = outer / std::sqrt(float(h.seeds));  // πs² is the area of one seed
  const float base = 1.08f * spacing;                       // hexagons just touch
  for (int i = 0; i < h.seeds; ++i) {
    const float rho = outer * std::sqrt((float(i) + 0.5f) / float(h.seeds));
    const float angle = float(std::fmod(double(i) * kGoldenAngle, 2.0 * std::numbers::pi));
    const glm::vec3 radial = f.radial(angle), tangential = f.radial(angle + 0.5f * kPi);
    const glm::vec3 foot = f.origin + rho * radial + discHeight(h, rho) * f.z;
    const Colour side = seedColour(h, rho / h.radius, rng), top = side * 0.7f;
    uint32_t low[6], high[6];
    for (int k = 0; k < 6; ++k) {
      const float a = float(k) * kPi / 3.0f;
      const glm::vec3 d = std::cos(a) * radial + std::sin(a) * tangential;
      low[k] = mb.vertex(foot + base * d - 0.0005f * f.z);
      high[k] = mb.vertex(foot + 0.6f * base * d + 0.45f * base * f.z);
    }
    const uint32_t apex = mb.vertex(foot + 0.75f * base * f.z);
    for (int k = 0; k < 6; ++k) {
      const int n = (k + 1) % 6;
      mb.quad(low[k], low[n], high[n], high[k], side);
      mb.triangle(high[k], high[n], apex, top);
    }
  }
}

/// The back of the head: a shallow green dish from the disc's rim to the neck.
void headBack(MeshBuilder& mb, Rng& rng, const Frame& f, const SunflowerHead& h, float neckRadius) {
  constexpr int kRings = 5, kSides = 40;
  mb.grid(
      kRings + 1, kSides, true,
      [&](int i, int j) {
        const float s = 0.5f * kPi * float(i) / kRings;  // quarter ellipse, rim to neck
        const float rho = neckRadius + (h.radius - neckRadius) * std::cos(s);
        return f.origin + rho * f.radial(kTwoPi * float(j) / kSides) - h.depth * std::sin(s) * f.z;
      },
      [&](int, int) { return vary(h.back, rng, 0.07f); });
}

/// Ray petals round the disc, every other one a little behind: each a strip along a centreline
/// that leaves the rim tilted forward by `rise` and curls back by `curl` towards its tip,
/// twisting a little, channelled along its middle, pointed.
void rayPetals(MeshBuilder& mb, Rng& rng, const Frame& f, const SunflowerHead& h) {
  for (int k = 0; k < h.petals; ++k) {
    const float a = kTwoPi * (float(k) + rng.symmetric(0.15f)) / float(h.petals);
    const glm::vec3 radial = f.radial(a), tangential = f.radial(a + 0.5f * kPi);
    const bool behind = k % 2 == 1;
    const float length = h.petalLength * rng.uniform(0.85f, 1.15f);
    const float halfWidth = 0.5f * h.petalWidth * rng.uniform(0.85f, 1.1f);
    const float rise = rng.uniform(-0.05f, 0.3f) - (behind ? 0.1f : 0.0f);
    const float curl = rng.uniform(-0.7f, 0.1f), twist = rng.symmetric(0.5f);
    const glm::vec3 start =
        f.origin + 0.93f * h.radius * radial + (behind ? -0.004f : 0.002f) * f.z;
    const auto centre = centreline(start, length, 6, [&](float t) {
      const float b = rise + curl * t * t;
      return std::cos(b) * radial + std::sin(b) * f.z;
    });
    const auto sections = sectionsAlong(
        centre,
        [&](float t) { return std::cos(twist * t) * tangential + std::sin(twist * t) * f.z; },
        [&](float t) {  // narrow foot, widest at 40 %, pointed tip
          return halfWidth * std::pow(std::max(0.0f, std::sin(kPi * (0.15f + 0.85f * t))), 0.7f);
        });
    const Colour colour = vary(h.petal, rng, 0.05f);
    const Colour foot = colour * Colour(0.9f, 0.75f, 0.6f);  // deeper yellow where it joins
    ribbon(mb, sections, 3, -0.25f,
           [&](int i, int) { return glm::mix(foot, colour, smoothstep(0.0f, 2.5f, float(i))); });
  }
}

void sunflowerHead(MeshBuilder& mb, Rng& rng, const Frame& f, const SunflowerHead& h,
                   float neckRadius) {
  seedDisc(mb, rng, f, h);
  seeds(mb, rng, f, h);
  headBack(mb, rng, f, h, neckRadius);
  // Two rows of bracts (phyllaries) behind the petals, bent back towards the stem.
  Frame rim = f;
  rim.origin = f.origin - 0.15f * h.depth * f.z;
  bracts(mb, rng, rim, h.petals / 2 + 6, 0.95f * h.radius, 0.38f * h.radius, 0.09f * h.radius,
         0.5f * kPi + 0.3f, 0.5f, h.bract);
  rim.origin = f.origin - 0.3f * h.depth * f.z;
  bracts(mb, rng, rim, h.petals / 2 + 6, 0.9f * h.radius, 0.34f * h.radius, 0.09f * h.radius,
         0.5f * kPi + 0.7f, 0.6f, h.bract * 0.9f);
  rayPetals(mb, rng, f, h);
}

/// A sunflower leaf blade: ovate with a pointed tip and a heart-shaped base whose two round
/// lobes reach back past the petiole. Each half is a grid: rows along the midrib (x, from the
/// lobes' back at −0.15 L to the tip at L), columns across from the inner edge (the midrib, or
/// the notch between the lobes behind the petiole) to the margin. The midrib leaves the petiole
/// at `elevation` and droops `droop` radians by the tip; the halves cup up (cup > 0) or hang
/// down (cup < 0); the margin waves a little.
void heartLeaf(MeshBuilder& mb, Rng& rng, glm::vec3 base, glm::vec3 outward, float length,
               float elevation, float droop, float cup, Colour colour) {
  constexpr int kRows = 11, kColumns = 4;
  const float back = -0.15f * length, lobe = 0.16f * length;  // the lobes' rear points
  const float halfWidth = length * rng.uniform(0.34f, 0.42f);
  const glm::vec3 side = glm::normalize(glm::cross(kUp, outward));
  const auto midribAngle = [&](float x) {
    return elevation - droop * std::pow(std::max(x, 0.0f) / length, 1.5f);
  };
  const auto midrib = [&](float x) {  // behind the petiole (x < 0) it runs straight back
    glm::vec3 p = base;
    if (x <= 0) return p + x * (std::cos(elevation) * outward + std::sin(elevation) * kUp);
    constexpr int kSteps = 6;
    for (int k = 0; k < kSteps; ++k) {
      const float b = midribAngle((float(k) + 0.5f) * x / kSteps);
      p += (x / kSteps) * (std::cos(b) * outward + std::sin(b) * kUp);
    }
    return p;
  };
  const float wave = rng.uniform(0.01f, 0.03f) * length, wavePhase = rng.uniform(0.0f, kTwoPi);
  for (const float sign : {-1.0f, 1.0f}) {
    mb.grid(
        kRows, kColumns, false,
        [&](int i, int j) {
          const float u = float(i) / (kRows - 1), x = back + u * (length - back);
          // Margin: round at the lobes (u = 0), widest at 40 %, pointed at the tip.
          const float outer =
              halfWidth *
                  std::pow(std::max(0.0f, std::sin(kPi * std::pow(u, 0.7f))), 1.0f + 0.6f * u) +
              lobe * std::pow(1.0f - u, 4.0f);
          const float inner = x < 0 ? lobe * x / back : 0.0f;  // the notch, closing at x = 0
          const float across = float(j) / (kColumns - 1);
          const float y = sign * (inner + (std::max(outer, inner) - inner) * across);
          const float b = midribAngle(x);
          const glm::vec3 normal = -std::sin(b) * outward + std::cos(b) * kUp;
          const float lift = cup * y * y / length + wave * across * across * std::sin(kPi * u) *
                                                        std::sin(12.0f * u + sign + wavePhase);
          return midrib(x) + y * side + lift * normal;
        },
        [&](int, int) { return vary(colour, rng, 0.05f); });
  }
}

PlantMesh sunflower(Rng& rng, float slot) {
  MeshBuilder mb;
  const float height = 1.5f + 0.6f * slot;

  SunflowerHead head;
  head.radius = rng.uniform(0.09f, 0.15f);
  head.depth = head.radius * rng.uniform(0.3f, 0.42f);
  head.dome = head.radius * rng.uniform(0.03f, 0.1f);
  head.seeds = int(1250.0f + 500.0f * (head.radius - 0.09f) / 0.06f) + rng.integer(-40, 40);
  head.petals = rng.integer(21, 34);
  mb.reserve(13 * size_t(head.seeds) + 8000, 18 * size_t(head.seeds) + 9000);  // seeds + the rest
  head.petalLength = head.radius * rng.uniform(0.55f, 0.85f);
  head.petalWidth = std::clamp(kTwoPi * head.radius / float(head.petals) * rng.uniform(1.0f, 1.3f),
                               0.016f, 0.03f);
  head.petal = hsv(rng.uniform(40, 50), rng.uniform(0.85f, 1.0f), rng.uniform(0.9f, 1.0f));
  head.seed = hsv(rng.uniform(18, 30), rng.uniform(0.55f, 0.8f), rng.uniform(0.16f, 0.26f));
  head.centre = hsv(rng.uniform(45, 60), rng.uniform(0.5f, 0.7f), rng.uniform(0.28f, 0.36f));
  head.florets = hsv(rng.uniform(26, 34), rng.uniform(0.7f, 0.85f), rng.uniform(0.38f, 0.48f));
  head.back = hsv(rng.uniform(70, 85), rng.uniform(0.45f, 0.6f), rng.uniform(0.38f, 0.48f));
  head.bract = hsv(rng.uniform(85, 100), rng.uniform(0.55f, 0.7f), rng.uniform(0.28f, 0.36f));
  const Colour stemGreen =
      hsv(rng.uniform(75, 92), rng.uniform(0.45f, 0.6f), rng.uniform(0.4f, 0.5f));
  const Colour leafGreen =
      hsv(rng.uniform(82, 105), rng.uniform(0.55f, 0.75f), rng.uniform(0.3f, 0.42f));

  // The stem: straight at the foot, leaning up to `lean` at the neck, then bending over the
  // neck to the head's facing direction, `tilt` from vertical (sideways and up).
  const float tilt = rng.uniform(0.7f, 1.4f), faceAzimuth = rng.uniform(0.0f, kTwoPi);
  const float lean = rng.uniform(0.0f, 0.14f), leanAzimuth = faceAzimuth + rng.symmetric(1.0f);
  const float neck = rng.uniform(0.1f, 0.16f);  // fraction of the stem in the bend
  const glm::vec3 facing = spherical(tilt, faceAzimuth);
  const auto direction = [&](float t) {
    const float straight = 1.0f - neck;
    const glm::vec3 lower =
        spherical(lean * std::pow(std::min(t / straight, 1.0f), 1.5f), leanAzimuth);
    return glm::normalize(glm::mix(lower, facing, smoothstep(straight, 1.0f, t)));
  };
  // The stem's length puts the top of the head (rim and petals) at `height`.
  constexpr int kStemSegments = 48;
  const auto unitStem = centreline(glm::vec3(0), 1.0f, kStemSegments, direction);
  const float tipZ = height - head.depth * std::cos(tilt) -
                     (head.radius + 0.8f * head.petalLength) * std::sin(tilt);
  const float stemLength = tipZ / unitStem.back().z;
  const auto stem = centreline(glm::vec3(0), stemLength, kStemSegments, direction);
  const float stemRadius = rng.uniform(0.014f, 0.022f);
  const auto radiusAt = [&](float t) {  // tapering, then swelling under the head
    return stemRadius * (1.0f - 0.5f * t) * (1.0f + 0.5f * smoothstep(0.9f, 1.0f, t));
  };
  tube(mb, stem, 12, radiusAt, [&](int i, int) {
    const float t = float(i) / kStemSegments;  // the foot a little browner
    return vary(glm::mix(stemGreen * Colour(1.1f, 0.9f, 0.7f), stemGreen, smoothstep(0, 0.3f, t)),
                rng, 0.05f);
  });

  // Leaves, alternate up the stem at the golden angle, largest a third of the way up.
  const int leaves = rng.integer(12, 18);
  const float leafLength = rng.uniform(0.22f, 0.3f), firstAzimuth = rng.uniform(0.0f, kTwoPi);
  for (int i = 0; i < leaves; ++i) {
    const float f = 0.1f + 0.68f * (float(i) + rng.uniform(0.2f, 0.8f)) / float(leaves);
    const float azimuth = firstAzimuth + float(i) * float(kGoldenAngle) + rng.symmetric(0.3f);
    const glm::vec3 outward = horizontal(azimuth);
    const float length =
        leafLength * (0.5f + 0.5f * std::exp(-sq((f - 0.35f) / 0.3f))) * rng.uniform(0.9f, 1.1f);
    // The petiole leaves the stem steeply and levels out.
    const float e0 = rng.uniform(0.6f, 1.0f), e1 = rng.uniform(0.0f, 0.35f);
    const auto petiole = centreline(pointAt(stem, f) + 0.7f * radiusAt(f) * outward,
                                    length * rng.uniform(0.3f, 0.45f), 5, [&](float t) {
                                      const float e = e0 + (e1 - e0) * t;
                                      return std::cos(e) * outward + std::sin(e) * kUp;
                                    });
    tube(
        mb, petiole, 5, [&](float t) { return 0.004f * (1.0f - 0.3f * t); },
        [&](int, int) { return vary(stemGreen, rng, 0.05f); });
    Colour colour = vary(leafGreen, rng, 0.1f);
    if (f < 0.25f && rng.chance(0.5f))  // the lowest leaves yellowing
      colour = glm::mix(colour, hsv(45, 0.6f, 0.45f), rng.uniform(0.3f, 0.7f));
    heartLeaf(mb, rng, petiole.back(), outward, length, e1, rng.uniform(0.3f, 0.9f),
              rng.uniform(-0.5f, 0.15f), colour);
  }

  const Frame headFrame = frameFacing(stem.back() + head.depth * facing, facing);
  sunflowerHead(mb, rng, headFrame, head, radiusAt(1.0f));
  return std::move(mb).finish();
}

// ---------------------------------------------------------------------------------------------
// Grass clump: curved tapering keeled blades from a small foot, leaning out and drooping, each
// its own green, darker at the foot; now and then one with a dry tip.

PlantMesh grassClump(Rng& rng, float slot) {
  MeshBuilder mb;
  const int blades = rng.integer(12, 40);
  // Fewer segments per blade in bigger clumps keeps every clump at about 400–600 triangles.
  const int segments = std::clamp(int(std::lround((520.0f / float(blades) + 2.0f) / 4.0f)), 4, 9);
  const float height = 0.17f + 0.3f * slot;
  const float footRadius = rng.uniform(0.01f, 0.035f), splay = rng.uniform(0.08f, 0.3f);
  const float arch = rng.uniform(0.3f, 0.9f);  // how far the outer blades arch over
  const float hue = rng.uniform(78, 105), saturation = rng.uniform(0.5f, 0.75f);
  const float value = rng.uniform(0.48f, 0.65f);

  struct Blade {
    std::vector<glm::vec3> centre;
    float azimuth, halfWidth, twist;
    Colour foot, tip;
  };
  std::vector<Blade> list;
  float top = 0;
  for (int b = 0; b < blades; ++b) {
    Blade blade;
    const float r = footRadius * std::sqrt(rng.uniform()), a = rng.uniform(0.0f, kTwoPi);
    blade.azimuth = a + rng.symmetric(0.8f);  // mostly leaning outwards
    // A fountain: the middle blades upright, the outer ones leaning out and arching over.
    const float out = r / footRadius;
    const float tilt = rng.uniform(0.02f, 0.15f) + splay * out;
    const float bend = arch * rng.uniform(0.3f, 1.0f) * (0.4f + out);
    const float length = rng.uniform(0.6f, 1.0f);
    blade.centre =
        centreline(glm::vec3(r * std::cos(a), r * std::sin(a), 0), length, segments,
                   [&](float t) { return spherical(tilt + bend * t * t, blade.azimuth); });
    for (const glm::vec3& p : blade.centre) top = std::max(top, p.z);
    blade.halfWidth = rng.uniform(0.0025f, 0.005f);
    blade.twist = rng.symmetric(0.8f);
    blade.foot = hsv(hue + rng.symmetric(10), saturation * rng.uniform(0.85f, 1.1f),
                     value * rng.uniform(0.7f, 0.85f));
    blade.tip = hsv(hue - rng.uniform(0, 15), saturation * rng.uniform(0.7f, 1.0f),
                    value * rng.uniform(1.0f, 1.3f));
    if (rng.chance(0.08f)) blade.tip = hsv(45, 0.45f, 0.7f);  // dry, straw-coloured tip
    list.push_back(std::move(blade));
  }

  // Scale the clump to its height (only the centrelines: blades keep their real widths); tips
  // that droop to the ground rest on it.
  const float scale = height / top;
  for (Blade& blade : list) {
    for (size_t k = 0; k < blade.centre.size(); ++k) {
      glm::vec3& p = blade.centre[k];
      p.x *= scale, p.y *= scale;
      p.z = std::max(p.z * scale, 0.004f * float(k) / float(segments));
    }
    const glm::vec3 side = horizontal(blade.azimuth + 0.5f * kPi);
    const auto sections = sectionsAlong(
        blade.centre,
        [&](float t) { return std::cos(blade.twist * t) * side + std::sin(blade.twist * t) * kUp; },
        [&](float t) { return blade.halfWidth * std::pow(1.0f - t * t * t, 0.6f); });
    ribbon(mb, sections, 3, 0.35f, [&](int i, int) {
      const float t = float(i) / float(segments);
      return vary(glm::mix(blade.foot, blade.tip, t * (2.0f - t)), rng, 0.04f);
    });
  }
  return std::move(mb).finish();
}

// ---------------------------------------------------------------------------------------------
// Dandelion: a flat rosette of toothed leaves and one to three hollow stems, each with a
// yellow flower head, a white seed ball (the "clock") or a closed bud.

enum class DandelionHead { kFlower, kSeedBall, kBud };

/// A rosette leaf lying out from the foot: rising at first, then flat on the ground; its
/// margin cut into teeth that point back towards the foot (runcinate), the tip whole.
void rosetteLeaf(MeshBuilder& mb, Rng& rng, float azimuth, float length, Colour colour) {
  constexpr int kSegments = 15;
  const glm::vec3 outward = horizontal(azimuth), side = horizontal(azimuth + 0.5f * kPi);
  const float rise = rng.uniform(0.25f, 0.7f), widest = length * rng.uniform(0.1f, 0.16f);
  const float lobes = float(rng.integer(3, 5)), phase = rng.uniform();
  auto centre = centreline(0.004f * outward + 0.003f * kUp, length, kSegments, [&](float t) {
    const float e = rise * (1.0f - 1.6f * t);
    return std::cos(e) * outward + std::sin(e) * kUp;
  });
  for (glm::vec3& p : centre) p.z = std::max(p.z, 0.002f);
  // The outline: an envelope widest 60 % out and pointed at the tip, times a sawtooth that
  // jumps out and slants back in along the leaf (so each lobe's point faces the foot), the
  // last fifth whole.
  const auto halfWidth = [&](float t) {
    const float envelope = std::pow(std::max(0.0f, std::sin(kPi * std::pow(t, 1.4f))), 0.6f);
    const float tooth = 1.0f - (t * lobes + phase - std::floor(t * lobes + phase));
    return widest * envelope * glm::mix(0.35f + 0.65f * tooth, 1.0f, smoothstep(0.65f, 0.8f, t));
  };
  const auto sections = sectionsAlong(
      centre, [&](float) { return side; }, halfWidth);
  ribbon(mb, sections, 3, 0.25f, [&](int, int) { return vary(colour, rng, 0.05f); });
}

/// An open flower head: rings of strap-shaped florets, the outer long and spreading, the inner
/// short and upright, over a cup of green bracts with an outer row bent back down the stem.
void dandelionFlower(MeshBuilder& mb, Rng& rng, const Frame& f, float radius, Colour yellow) {
  const Colour green = hsv(95, 0.6f, 0.4f);
  bracts(mb, rng, f, 10, 0.003f, 0.4f * radius, 0.0015f, 0.3f, 0.2f, green);
  bracts(mb, rng, f, 8, 0.003f, 0.45f * radius, 0.0012f, 2.2f, 0.5f, green);
  constexpr int kRings = 4;
  constexpr int kCount[kRings] = {20, 15, 10, 6};
  constexpr float kLength[kRings] = {1.0f, 0.8f, 0.6f, 0.42f};
  constexpr float kElevation[kRings] = {0.2f, 0.55f, 0.9f, 1.25f};
  const Colour orange = yellow * Colour(1.0f, 0.88f, 0.6f);  // the inner florets
  for (int r = 0; r < kRings; ++r) {
    const float length = kLength[r] * radius, foot = 0.12f * radius * (1.0f - 0.25f * r);
    // Straps widening to their square tips, nearly closing the ring at 60 % out.
    const float halfWidth = 0.8f * kPi * (foot + 0.6f * length) / float(kCount[r]);
    for (int k = 0; k < kCount[r]; ++k) {
      const float a = kTwoPi * (float(k) + 0.5f * float(r) + rng.symmetric(0.2f)) / kCount[r];
      const glm::vec3 radial = f.radial(a), tangential = f.radial(a + 0.5f * kPi);
      const float e = kElevation[r] + rng.symmetric(0.15f);
      const auto centre = centreline(f.at(0, 0, 0.06f * radius * float(r + 1)) + foot * radial,
                                     length * rng.uniform(0.85f, 1.1f), 2, [&](float t) {
                                       const float b = e - 0.3f * t;  // tips curve down
                                       return std::cos(b) * radial + std::sin(b) * f.z;
                                     });
      const Colour colour = vary(glm::mix(yellow, orange, float(r) / (kRings - 1)), rng, 0.05f);
      ribbon(mb,
             sectionsAlong(
                 centre, [&](float) { return tangential; },
                 [&](float t) { return halfWidth * (0.6f + 0.5f * t); }),
             2, 0.0f, [&](int, int) { return colour; });
    }
  }
}

/// The seed ball: parachutes all round the receptacle but where the stem comes in, each a
/// beak (a sliver) from the receptacle out to a cone of white pappus hairs.
void seedBall(MeshBuilder& mb, Rng& rng, const Frame& f, float radius) {
  constexpr int kParachutes = 40, kHairs = 5;
  constexpr float kLowest = -0.6f;  // z of the lowest parachute direction
  const glm::vec3 centre = f.origin + 0.004f * f.z;
  Frame receptacle = f;  // a small brown knob, where the seeds sit
  receptacle.origin = centre - 0.0035f * f.z;
  bud(mb, rng, receptacle, 0.0035f, 0.007f, hsv(30, 0.4f, 0.5f), hsv(30, 0.4f, 0.5f));
  bracts(mb, rng, f, 8, 0.002f, 0.5f * radius, 0.0012f, 2.4f, 0.4f, hsv(90, 0.5f, 0.4f));
  const float rim = 1.25f * radius * std::sqrt(4.0f / kParachutes);  // cones just overlap
  for (int i = 0; i < kParachutes; ++i) {
    const float z = 1.0f - (1.0f - kLowest) * (float(i) + 0.5f) / kParachutes;
    const float angle = float(std::fmod(double(i) * kGoldenAngle, 2.0 * std::numbers::pi));
    const glm::vec3 d = std::sqrt(1.0f - z * z) * f.radial(angle) + z * f.z;
    const Frame hairs = frameFacing(centre + radius * d, d);
    const uint32_t apex = mb.vertex(centre + 0.8f * radius * d);
    uint32_t ring[kHairs];
    const float spin = rng.uniform(0.0f, kTwoPi);
    for (int k = 0; k < kHairs; ++k)
      ring[k] = mb.vertex(hairs.origin + rim * hairs.radial(spin + kTwoPi * float(k) / kHairs));
    const Colour white = vary(hsv(45, 0.06f, 0.95f), rng, 0.04f);
    for (int k = 0; k < kHairs; ++k) mb.triangle(apex, ring[k], ring[(k + 1) % kHairs], white);
    const uint32_t beakA = mb.vertex(centre + 0.15f * radius * d + 0.0004f * hairs.x);
    const uint32_t beakB = mb.vertex(centre + 0.15f * radius * d - 0.0004f * hairs.x);
    mb.triangle(beakA, beakB, apex, hsv(40, 0.2f, 0.8f));
  }
}

PlantMesh dandelion(Rng& rng, float slot, bool seedBallFirst) {
  MeshBuilder mb;
  const Colour leafGreen =
      hsv(rng.uniform(85, 105), rng.uniform(0.5f, 0.7f), rng.uniform(0.35f, 0.5f));
  const int leaves = rng.integer(6, 10);
  const float leafLength = rng.uniform(0.08f, 0.18f), firstAzimuth = rng.uniform(0.0f, kTwoPi);
  for (int i = 0; i < leaves; ++i)
    rosetteLeaf(mb, rng, firstAzimuth + kTwoPi * float(i) / float(leaves) + rng.symmetric(0.3f),
                leafLength * rng.uniform(0.7f, 1.15f), vary(leafGreen, rng, 0.08f));

  const Colour yellow = hsv(rng.uniform(44, 52), 1.0f, rng.uniform(0.92f, 1.0f));
  const Colour stemGreen =
      hsv(rng.uniform(75, 90), rng.uniform(0.35f, 0.5f), rng.uniform(0.55f, 0.65f));
  const int stems = rng.integer(1, 3);
  for (int s = 0; s < stems; ++s) {
    DandelionHead kind = DandelionHead::kFlower;
    if (s == 0)
      kind = seedBallFirst ? DandelionHead::kSeedBall : DandelionHead::kFlower;
    else if (rng.chance(0.35f))
      kind = DandelionHead::kBud;
    else if (rng.chance(0.3f))
      kind = DandelionHead::kSeedBall;
    // Seed balls stand tallest (the stem grows on after flowering), buds lowest.
    const float u = s == 0 ? slot : rng.uniform();
    const float length = kind == DandelionHead::kSeedBall ? 0.22f + 0.12f * u
                         : kind == DandelionHead::kFlower ? 0.15f + 0.13f * u
                                                          : 0.06f + 0.08f * u;
    const float azimuth = rng.uniform(0.0f, kTwoPi), tilt = rng.uniform(0.1f, 0.45f);
    const float nod = rng.symmetric(0.25f);  // the head's tilt off the stem's last direction
    const auto stem = centreline(0.004f * horizontal(azimuth), length, 10, [&](float t) {
      return spherical(tilt * (1.0f - 0.7f * t), azimuth);  // arching out, then up
    });
    tube(
        mb, stem, 6, [](float t) { return 0.0022f * (1.0f - 0.2f * t); },
        [&](int i, int) {
          const float t = float(i) / 10.0f;  // reddish at the foot
          return vary(glm::mix(hsv(10, 0.45f, 0.45f), stemGreen, smoothstep(0.0f, 0.35f, t)), rng,
                      0.05f);
        });
    const Frame head = frameFacing(stem.back(), spherical(tilt * 0.3f + nod, azimuth));
    switch (kind) {
      case DandelionHead::kFlower:
        dandelionFlower(mb, rng, head, rng.uniform(0.015f, 0.022f), yellow);
        break;
      case DandelionHead::kSeedBall:
        seedBall(mb, rng, head, rng.uniform(0.016f, 0.022f));
        break;
      case DandelionHead::kBud:
        bud(mb, rng, head, 0.005f, 0.016f, hsv(95, 0.55f, 0.4f), hsv(80, 0.6f, 0.5f));
        bracts(mb, rng, head, 6, 0.003f, 0.007f, 0.0012f, 2.2f, 0.4f, hsv(95, 0.55f, 0.4f));
        break;
    }
  }
  return std::move(mb).finish();
}

// ---------------------------------------------------------------------------------------------
// Small yellow flower (a buttercup or cinquefoil): a thin stem with a few small leaves, five
// rounded cupped yellow petals round a centre, sometimes a side stem with a second flower or
// a bud.

/// A small lanceolate leaf: a keeled strip rising at `elevation`, drooping by `droop`.
void smallLeaf(MeshBuilder& mb, Rng& rng, glm::vec3 base, glm::vec3 outward, float length,
               float elevation, float droop, Colour colour) {
  const auto centre = centreline(base, length, 4, [&](float t) {
    const float e = elevation - droop * t;
    return std::cos(e) * outward + std::sin(e) * kUp;
  });
  const float width = length * rng.uniform(0.18f, 0.3f);
  const auto sections = sectionsAlong(
      centre, [&](float) { return glm::cross(kUp, outward); },
      [&](float t) {
        return width * std::pow(std::max(0.0f, std::sin(kPi * std::pow(t, 0.8f))), 0.8f);
      });
  ribbon(mb, sections, 3, 0.3f, [&](int, int) { return vary(colour, rng, 0.05f); });
}

/// Five obovate petals, narrow at the foot and round at the tip, cupped, round a domed centre,
/// with five green sepals under them.
void fivePetalFlower(MeshBuilder& mb, Rng& rng, const Frame& f, float petalLength, Colour petal,
                     Colour centre) {
  static const std::vector<float> kRows = {0, 0.2f, 0.4f, 0.58f, 0.74f, 0.86f, 0.95f, 1};
  const float spin = rng.uniform(0.0f, kTwoPi);
  for (int k = 0; k < 5; ++k) {
    const float a = spin + kTwoPi * float(k) / 5 + rng.symmetric(0.08f);
    const glm::vec3 radial = f.radial(a), tangential = f.radial(a + 0.5f * kPi);
    const float length = petalLength * rng.uniform(0.9f, 1.1f);
    const float width = 0.45f * length * rng.uniform(0.9f, 1.1f);
    const float rise = rng.uniform(0.2f, 0.5f), curve = rng.uniform(0.1f, 0.5f);
    const auto line = centrelineAt(f.origin + 0.0012f * radial, length, kRows, [&](float t) {
      const float e = rise + curve * t;
      return std::cos(e) * radial + std::sin(e) * f.z;
    });
    std::vector<Section> sections = sectionsAlong(
        line, [&](float) { return tangential; }, [](float) { return 0.0f; });
    for (size_t i = 0; i < sections.size(); ++i) {  // the rows are uneven: widths by kRows
      const float t = kRows[i];
      sections[i].halfWidth =
          t < 0.55f ? width * (0.35f + 0.65f * t / 0.55f)
                    : width * std::sqrt(std::max(0.0f, 1.0f - sq((t - 0.55f) / 0.45f)));
    }
    const Colour colour = vary(petal, rng, 0.04f), foot = colour * Colour(0.95f, 0.8f, 0.5f);
    ribbon(mb, sections, 4, 0.35f, [&](int i, int) { return i == 0 ? foot : colour; });
  }
  // The centre: a little dome of stamens.
  const float r = 0.3f * petalLength;
  mb.grid(
      3, 8, true,
      [&](int i, int j) {
        const float polar = 0.25f * kPi * float(i);  // rim, shoulder, top
        return f.origin + r * std::cos(polar) * f.radial(kTwoPi * float(j) / 8) +
               0.8f * r * std::sin(polar) * f.z;
      },
      [&](int, int) { return vary(centre, rng, 0.08f); });
  bracts(mb, rng, f, 5, 0.001f, 0.5f * petalLength, 0.2f * petalLength, 1.7f, 0.3f,
         hsv(95, 0.6f, 0.38f));
}

PlantMesh yellowFlower(Rng& rng, float slot) {
  MeshBuilder mb;
  const Colour green =
      hsv(rng.uniform(88, 110), rng.uniform(0.5f, 0.7f), rng.uniform(0.35f, 0.48f));
  const Colour petal = hsv(rng.uniform(48, 57), rng.uniform(0.88f, 1.0f), rng.uniform(0.95f, 1.0f));
  const Colour centre = rng.chance(0.5f) ? hsv(rng.uniform(68, 80), 0.65f, rng.uniform(0.5f, 0.6f))
                                         : hsv(rng.uniform(26, 33), 0.9f, rng.uniform(0.7f, 0.8f));
  const float petalLength = rng.uniform(0.008f, 0.012f);

  // The stem, its head nodding a little at the top.
  const float stemLength = 0.1f + 0.18f * slot;
  const float tilt0 = rng.uniform(0.0f, 0.25f), tilt1 = rng.uniform(0.0f, 0.45f);
  const float azimuth = rng.uniform(0.0f, kTwoPi);
  const auto direction = [&](float t) {
    return spherical(tilt0 + (tilt1 - tilt0) * t * t, azimuth);
  };
  constexpr int kSegments = 8;
  const auto stem = centreline(glm::vec3(0), stemLength, kSegments, direction);
  const auto thin = [](float t) { return 0.0014f * (1.0f - 0.3f * t); };
  tube(mb, stem, 5, thin, [&](int, int) { return vary(green * 1.1f, rng, 0.05f); });

  // Two or three leaves spread round the foot, one or two up the stem.
  const int basal = rng.integer(2, 3), upper = rng.integer(1, 2);
  const float firstAzimuth = rng.uniform(0.0f, kTwoPi);
  for (int i = 0; i < basal + upper; ++i) {
    const bool low = i < basal;
    const float a = firstAzimuth + kTwoPi * float(i) / float(basal) + rng.symmetric(0.5f);
    const glm::vec3 base = low ? 0.002f * horizontal(a) : pointAt(stem, rng.uniform(0.25f, 0.6f));
    smallLeaf(mb, rng, base, horizontal(a),
              low ? rng.uniform(0.025f, 0.045f) : rng.uniform(0.012f, 0.025f),
              low ? rng.uniform(0.3f, 0.7f) : rng.uniform(0.4f, 0.9f), rng.uniform(0.2f, 0.8f),
              vary(green, rng, 0.08f));
  }

  fivePetalFlower(mb, rng, frameFacing(stem.back(), direction(1.0f)), petalLength, petal, centre);

  // Sometimes a side stem from the middle, with a smaller flower or a bud.
  if (rng.chance(0.45f)) {
    const float from = rng.uniform(0.45f, 0.7f), sideAzimuth = azimuth + rng.uniform(2.0f, 4.3f);
    const float sideTilt = rng.uniform(0.5f, 0.9f);
    const auto branch =
        centreline(pointAt(stem, from), stemLength * rng.uniform(0.3f, 0.5f), 5,
                   [&](float t) { return spherical(sideTilt * (1.0f - 0.6f * t), sideAzimuth); });
    tube(
        mb, branch, 5, [](float) { return 0.001f; },
        [&](int, int) { return vary(green * 1.1f, rng, 0.05f); });
    const Frame tip = frameFacing(branch.back(), spherical(sideTilt * 0.4f, sideAzimuth));
    if (rng.chance(0.5f))
      fivePetalFlower(mb, rng, tip, petalLength * 0.85f, petal, centre);
    else
      bud(mb, rng, tip, 0.003f, 0.007f, green, green * 1.2f);
  }
  return std::move(mb).finish();
}

// ---------------------------------------------------------------------------------------------

/// Where a version sits in its species' range (tallest to shortest, say): a seeded permutation
/// of the versions spreads them over [0, 1) one slot each, jittered within the slot.
float versionSlot(uint64_t seed, Species species, int version, Rng& rng) {
  const int count = versionCount(species);
  Rng order(mixSeed(seed, 0x51075ULL + uint64_t(species)));
  std::vector<int> permutation(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) permutation[size_t(i)] = i;
  for (int i = count - 1; i > 0; --i)
    std::swap(permutation[size_t(i)], permutation[size_t(order.integer(0, i))]);
  return (float(permutation[size_t(version)]) + rng.uniform(0.1f, 0.9f)) / float(count);
}

}  // namespace plantgen
}  // namespace

PlantMesh makePlant(Species species, int version, uint64_t seed) {
  namespace pg = plantgen;  // qualified: another file's helpers may share a unity unit
  assert(version >= 0 && version < versionCount(species));
  version = std::clamp(version, 0, versionCount(species) - 1);
  pg::Rng rng(pg::mixSeed(pg::mixSeed(seed, uint64_t(species) + 1), uint64_t(version) + 1));
  const float slot = pg::versionSlot(seed, species, version, rng);
  switch (species) {
    case Species::kSunflower:
      return pg::sunflower(rng, slot);
    case Species::kGrass:
      return pg::grassClump(rng, slot);
    case Species::kDandelion:
      // A third of the versions carry a seed ball on their first stem, the rest a flower; each
      // kind spread over its own range of heights.
      if (slot < 1.0f / 3.0f) return pg::dandelion(rng, 3.0f * slot, true);
      return pg::dandelion(rng, 1.5f * (slot - 1.0f / 3.0f), false);
    case Species::kYellowFlower:
      return pg::yellowFlower(rng, slot);
  }
  return {};
}

}  // namespace terralod::veg
