#include "terralod/vegetation/plant_models.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <numeric>
#include <string>

#include <glm/geometric.hpp>

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

namespace terralod::veg {
namespace {
// Helpers in their own namespace: unity builds put four test files in one unit.
namespace plant_models_test {

constexpr Species kAllSpecies[] = {Species::kSunflower, Species::kGrass, Species::kDandelion,
                                   Species::kYellowFlower};
constexpr uint64_t kSeed = 20010812;

struct Range {
  double lo, hi;
};

/// What each species must be: triangle counts (the paper, §6: ~35,000 per sunflower; a meadow
/// tile of ~62,000 triangles holds 100–200 plants), heights and horizontal reach in metres.
struct Expected {
  Range triangles, height, radius;
};

Expected expected(Species s) {
  switch (s) {
    case Species::kSunflower:
      return {{25000, 40000}, {1.4, 2.2}, {0.15, 0.7}};
    case Species::kGrass:
      return {{200, 800}, {0.15, 0.5}, {0.03, 0.4}};
    case Species::kDandelion:
      return {{500, 2000}, {0.13, 0.4}, {0.05, 0.3}};
    case Species::kYellowFlower:
      return {{200, 800}, {0.09, 0.32}, {0.01, 0.15}};
  }
  return {};
}

struct Hsv {
  float h, s, v;  ///< hue in degrees, saturation and value in [0, 1]
};

Hsv toHsv(const std::array<uint8_t, 3>& c) {
  const float r = c[0] / 255.0f, g = c[1] / 255.0f, b = c[2] / 255.0f;
  const float mx = std::max({r, g, b}), mn = std::min({r, g, b}), d = mx - mn;
  float h = 0;
  if (d > 0) {
    if (mx == r)
      h = 60.0f * std::fmod((g - b) / d + 6.0f, 6.0f);
    else if (mx == g)
      h = 60.0f * ((b - r) / d + 2.0f);
    else
      h = 60.0f * ((r - g) / d + 4.0f);
  }
  return {h, mx > 0 ? d / mx : 0.0f, mx};
}

bool isYellow(const std::array<uint8_t, 3>& c) {
  const Hsv x = toHsv(c);
  return x.h >= 38 && x.h <= 65 && x.s >= 0.6f && x.v >= 0.7f;
}
bool isDarkBrown(const std::array<uint8_t, 3>& c) {  // seeds: dark, red-brown to brown
  const Hsv x = toHsv(c);
  return x.v < 0.4f && x.h <= 40 && x.s >= 0.3f;
}
bool isGreen(const std::array<uint8_t, 3>& c) {
  const Hsv x = toHsv(c);
  return x.h >= 55 && x.h <= 160 && x.s >= 0.2f;
}
bool isWhite(const std::array<uint8_t, 3>& c) {
  const Hsv x = toHsv(c);
  return x.s < 0.15f && x.v > 0.8f;
}

template <class Predicate>
int countTriangles(const PlantMesh& m, Predicate predicate) {
  return int(std::count_if(m.colors.begin(), m.colors.end(), predicate));
}

/// Connected pieces (sharing vertices) among the triangles whose colour passes `predicate`.
template <class Predicate>
int countPieces(const PlantMesh& m, Predicate predicate) {
  std::vector<uint32_t> parent(m.positions.size());
  std::iota(parent.begin(), parent.end(), 0u);
  const auto find = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<bool> used(m.positions.size(), false);
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    if (!predicate(m.colors[i])) continue;
    const auto& t = m.triangles[i];
    for (uint32_t v : t) used[v] = true;
    parent[find(t[1])] = find(t[0]);
    parent[find(t[2])] = find(t[0]);
  }
  int pieces = 0;
  for (uint32_t v = 0; v < parent.size(); ++v) pieces += used[v] && find(v) == v;
  return pieces;
}

bool sameBytes(const PlantMesh& a, const PlantMesh& b) {
  const auto same = [](const auto& x, const auto& y) {
    using T = typename std::decay_t<decltype(x)>::value_type;
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(T)) == 0;
  };
  return same(a.positions, b.positions) && same(a.triangles, b.triangles) &&
         same(a.colors, b.colors) && std::memcmp(&a.tightRadius, &b.tightRadius, 4) == 0 &&
         std::memcmp(&a.height, &b.height, 4) == 0;
}

TEST(PlantModels, TriangleCountsPerSpecies) {
  for (Species s : kAllSpecies) {
    const Range range = expected(s).triangles;
    for (int v = 0; v < versionCount(s); ++v) {
      const PlantMesh m = makePlant(s, v, kSeed);
      EXPECT_GE(m.triangles.size(), range.lo) << speciesName(s) << " version " << v;
      EXPECT_LE(m.triangles.size(), range.hi) << speciesName(s) << " version " << v;
    }
  }
}

TEST(PlantModels, SameInputsSameBytes) {
  for (Species s : kAllSpecies)
    for (int v = 0; v < versionCount(s); ++v)
      EXPECT_TRUE(sameBytes(makePlant(s, v, kSeed), makePlant(s, v, kSeed)))
          << speciesName(s) << " version " << v;
}

TEST(PlantModels, VersionsAndSeedsDiffer) {
  for (Species s : kAllSpecies) {
    std::vector<PlantMesh> versions;
    float lowest = std::numeric_limits<float>::max(), highest = 0;
    for (int v = 0; v < versionCount(s); ++v) {
      versions.push_back(makePlant(s, v, kSeed));
      lowest = std::min(lowest, versions.back().height);
      highest = std::max(highest, versions.back().height);
      for (int w = 0; w < v; ++w)
        EXPECT_FALSE(versions[size_t(w)].positions == versions.back().positions)
            << speciesName(s) << " versions " << w << " and " << v;
    }
    // Visibly different: the versions spread over the species' heights.
    EXPECT_GT(highest - lowest, 0.3f * (expected(s).height.hi - expected(s).height.lo))
        << speciesName(s);
    EXPECT_FALSE(makePlant(s, 0, kSeed).positions == makePlant(s, 0, kSeed + 1).positions)
        << speciesName(s);
  }
}

TEST(PlantModels, ValidTrianglesAndBounds) {
  for (Species s : kAllSpecies)
    for (uint64_t seed : {kSeed, uint64_t(1), uint64_t(0xdeadbeef)})
      for (int v = 0; v < versionCount(s); ++v) {
        const PlantMesh m = makePlant(s, v, seed);
        SCOPED_TRACE(std::string(speciesName(s)) + " version " + std::to_string(v) + " seed " +
                     std::to_string(seed));
        ASSERT_EQ(m.colors.size(), m.triangles.size());
        ASSERT_FALSE(m.triangles.empty());
        int bad = 0;
        for (const auto& t : m.triangles) {
          if (t[0] >= m.positions.size() || t[1] >= m.positions.size() ||
              t[2] >= m.positions.size()) {
            ++bad;
            continue;
          }
          const glm::dvec3 a(m.positions[t[0]]), b(m.positions[t[1]]), c(m.positions[t[2]]);
          bad += !(0.5 * glm::length(glm::cross(b - a, c - a)) > 1e-12);
        }
        EXPECT_EQ(bad, 0) << "out-of-range or degenerate triangles";
        float radius = 0, height = -std::numeric_limits<float>::max(), lowest = 0;
        for (const glm::vec3& p : m.positions) {
          ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
          radius = std::max(radius, std::sqrt(p.x * p.x + p.y * p.y));
          height = std::max(height, p.z);
          lowest = std::min(lowest, p.z);
        }
        EXPECT_NEAR(m.tightRadius, radius, 1e-6f);
        EXPECT_EQ(m.height, height);
        EXPECT_GE(lowest, -0.01f);
        EXPECT_GE(m.height, expected(s).height.lo);
        EXPECT_LE(m.height, expected(s).height.hi);
        EXPECT_GE(m.tightRadius, expected(s).radius.lo);
        EXPECT_LE(m.tightRadius, expected(s).radius.hi);
      }
}

TEST(PlantModels, SunflowerHasYellowPetalsAndADarkSeedHead) {
  std::vector<int> petalCounts;
  for (int v = 0; v < versionCount(Species::kSunflower); ++v) {
    const PlantMesh m = makePlant(Species::kSunflower, v, kSeed);
    SCOPED_TRACE("version " + std::to_string(v));
    const int dark = countTriangles(m, isDarkBrown);
    EXPECT_GT(dark, int(m.triangles.size()) / 2) << "most triangles are the seed head";
    EXPECT_GT(countTriangles(m, isGreen), 1500) << "stem and leaves";
    // Each ray petal is its own yellow piece: 21–34 of them.
    const int petals = countPieces(m, isYellow);
    EXPECT_GE(petals, 21);
    EXPECT_LE(petals, 34);
    petalCounts.push_back(petals);
    // The seed head's size: the spread of the dark seeds' vertices.
    glm::dvec3 mean(0);
    int n = 0;
    for (size_t i = 0; i < m.triangles.size(); ++i)
      if (isDarkBrown(m.colors[i]))
        for (uint32_t k : m.triangles[i]) mean += glm::dvec3(m.positions[k]), ++n;
    mean /= n;
    double reach = 0;
    for (size_t i = 0; i < m.triangles.size(); ++i)
      if (isDarkBrown(m.colors[i]))
        for (uint32_t k : m.triangles[i])
          reach = std::max(reach, glm::length(glm::dvec3(m.positions[k]) - mean));
    EXPECT_GE(2 * reach, 0.16);
    EXPECT_LE(2 * reach, 0.32);
    // The head is at the top, not on the ground.
    EXPECT_GT(mean.z, 0.7 * m.height);
  }
  EXPECT_GT(*std::max_element(petalCounts.begin(), petalCounts.end()),
            *std::min_element(petalCounts.begin(), petalCounts.end()));
}

TEST(PlantModels, GrassIsGreen) {
  for (int v = 0; v < versionCount(Species::kGrass); ++v) {
    const PlantMesh m = makePlant(Species::kGrass, v, kSeed);
    EXPECT_GT(countTriangles(m, isGreen), int(0.75 * double(m.triangles.size()))) << v;
    EXPECT_EQ(countTriangles(m, isYellow), 0) << v;
  }
}

TEST(PlantModels, DandelionsHaveFlowersAndSeedBalls) {
  int withFlower = 0, withSeedBall = 0;
  for (int v = 0; v < versionCount(Species::kDandelion); ++v) {
    const PlantMesh m = makePlant(Species::kDandelion, v, kSeed);
    const int yellow = countTriangles(m, isYellow), white = countTriangles(m, isWhite);
    EXPECT_GT(yellow + white, 150) << v << ": a flower head or a seed ball";
    EXPECT_GT(countTriangles(m, isGreen), 250) << v << ": the rosette";
    withFlower += yellow > 150;
    withSeedBall += white > 150;
  }
  EXPECT_GE(withFlower, 1);
  EXPECT_GE(withSeedBall, 1);
}

TEST(PlantModels, YellowFlowersHaveFivePetals) {
  for (int v = 0; v < versionCount(Species::kYellowFlower); ++v) {
    const PlantMesh m = makePlant(Species::kYellowFlower, v, kSeed);
    const int petals = countPieces(m, isYellow);
    EXPECT_TRUE(petals == 5 || petals == 10) << v << ": " << petals << " petals";
    EXPECT_GT(countTriangles(m, isGreen), 60) << v;
  }
}

TEST(PlantModels, AllSunflowersInWellUnderASecond) {
  const auto start = std::chrono::steady_clock::now();
  size_t triangles = 0;
  for (int v = 0; v < versionCount(Species::kSunflower); ++v)
    triangles += makePlant(Species::kSunflower, v, kSeed).triangles.size();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("11 sunflowers, %zu triangles, in %.3f s\n", triangles, seconds);
#ifdef NDEBUG
  EXPECT_LT(seconds, 1.0);  // about 0.07 s in a release build
#else
  EXPECT_LT(seconds, 3.0);  // about 0.35 s unoptimised
#endif
}

// ---------------------------------------------------------------------------------------------
// Pictures: TERRALOD_PLANT_PICTURES=dir writes, per species, version 0 from two sides, from
// above and close up (<species>.png), and every version from the side and from above
// (<species>_versions.png). A tiny orthographic z-buffer rasteriser, flat-shaded by triangle
// colour with a Lambert term.

struct Canvas {
  int width, height;
  std::vector<uint8_t> rgb;
  std::vector<float> depth;
  Canvas(int w, int h)
      : width(w), height(h), rgb(size_t(w) * size_t(h) * 3), depth(size_t(w) * size_t(h)) {
    for (size_t i = 0; i < depth.size(); ++i) {
      rgb[3 * i] = 222, rgb[3 * i + 1] = 228, rgb[3 * i + 2] = 232;
      depth[i] = std::numeric_limits<float>::max();
    }
  }
};

/// An orthographic view: screen x along `right`, screen up along `up`, looking along
/// `forward`; `centre` lands in the middle of the cell, `pixelsPerMetre` its scale.
struct OrthoView {
  glm::vec3 right, up, forward, centre;
  float pixelsPerMetre;
};

OrthoView sideView(float azimuth, glm::vec3 centre, float pixelsPerMetre) {
  const glm::vec3 forward(std::cos(azimuth), std::sin(azimuth), 0);
  return {glm::vec3(std::sin(azimuth), -std::cos(azimuth), 0), glm::vec3(0, 0, 1), forward, centre,
          pixelsPerMetre};
}

OrthoView topView(glm::vec3 centre, float pixelsPerMetre) {
  return {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, -1), centre, pixelsPerMetre};
}

void rasterise(Canvas& canvas, int cellX, int cellY, int cellSize, const PlantMesh& m,
               const OrthoView& view) {
  const glm::vec3 light = glm::normalize(-view.forward + glm::vec3(0.3f, 0.2f, 1.0f));
  std::vector<glm::vec3> screen(m.positions.size());
  for (size_t i = 0; i < m.positions.size(); ++i) {
    const glm::vec3 d = m.positions[i] - view.centre;
    screen[i] = {cellX + 0.5f * cellSize + glm::dot(d, view.right) * view.pixelsPerMetre,
                 cellY + 0.5f * cellSize - glm::dot(d, view.up) * view.pixelsPerMetre,
                 glm::dot(d, view.forward)};
  }
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& tri = m.triangles[t];
    const glm::vec3 a = screen[tri[0]], b = screen[tri[1]], c = screen[tri[2]];
    const glm::vec3 n = glm::normalize(glm::cross(m.positions[tri[1]] - m.positions[tri[0]],
                                                  m.positions[tri[2]] - m.positions[tri[0]]));
    const float shade = 0.35f + 0.65f * std::abs(glm::dot(n, light));
    const float area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (std::abs(area) < 1e-12f) continue;
    const int x0 = std::max(cellX, int(std::floor(std::min({a.x, b.x, c.x}))));
    const int x1 = std::min(cellX + cellSize - 1, int(std::ceil(std::max({a.x, b.x, c.x}))));
    const int y0 = std::max(cellY, int(std::floor(std::min({a.y, b.y, c.y}))));
    const int y1 = std::min(cellY + cellSize - 1, int(std::ceil(std::max({a.y, b.y, c.y}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const float px = x + 0.5f, py = y + 0.5f;
        const float w0 = ((b.x - px) * (c.y - py) - (b.y - py) * (c.x - px)) / area;
        const float w1 = ((c.x - px) * (a.y - py) - (c.y - py) * (a.x - px)) / area;
        const float w2 = 1.0f - w0 - w1;
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        const float z = w0 * a.z + w1 * b.z + w2 * c.z;
        const size_t i = size_t(y) * size_t(canvas.width) + size_t(x);
        if (z >= canvas.depth[i]) continue;
        canvas.depth[i] = z;
        for (int k = 0; k < 3; ++k)
          canvas.rgb[3 * i + size_t(k)] = uint8_t(std::min(255.0f, m.colors[t][size_t(k)] * shade));
      }
  }
}

/// The view from the side at `azimuth`, the whole plant in the cell.
OrthoView fitSide(const PlantMesh& m, float azimuth, int cellSize) {
  const float extent = std::max(2.0f * m.tightRadius, m.height) * 1.1f;
  return sideView(azimuth, glm::vec3(0, 0, 0.5f * m.height), cellSize / extent);
}

void writePng(const Canvas& canvas, const std::filesystem::path& path) {
  ASSERT_NE(stbi_write_png(path.string().c_str(), canvas.width, canvas.height, 3, canvas.rgb.data(),
                           canvas.width * 3),
            0)
      << path;
}

TEST(PlantModelPictures, ContactSheets) {
  const char* dir = std::getenv("TERRALOD_PLANT_PICTURES");
  if (!dir || !*dir) GTEST_SKIP() << "set TERRALOD_PLANT_PICTURES=dir to write the pictures";
  std::filesystem::create_directories(dir);
  constexpr int kCell = 480, kSmall = 240;
  for (Species s : kAllSpecies) {
    const PlantMesh m = makePlant(s, 0, kSeed);
    // Version 0: from two sides, from above, and the top fifth of the plant close up.
    Canvas canvas(4 * kCell, kCell);
    rasterise(canvas, 0, 0, kCell, m, fitSide(m, 0.0f, kCell));
    rasterise(canvas, kCell, 0, kCell, m, fitSide(m, 1.5708f, kCell));
    rasterise(canvas, 2 * kCell, 0, kCell, m,
              topView(glm::vec3(0, 0, 0), kCell / (2.2f * m.tightRadius)));
    glm::vec3 top(0);
    int n = 0;
    for (const glm::vec3& p : m.positions)
      if (p.z > 0.8f * m.height) top += p, ++n;
    top /= float(n);
    rasterise(canvas, 3 * kCell, 0, kCell, m, sideView(0.8f, top, kCell / (0.45f * m.height)));
    writePng(canvas, std::filesystem::path(dir) / (std::string(speciesName(s)) + ".png"));

    // Every version, from the side (one scale for all) and from above.
    const int count = versionCount(s);
    Canvas sheet(count * kSmall, 2 * kSmall);
    float extent = 0;
    std::vector<PlantMesh> versions;
    for (int v = 0; v < count; ++v) {
      versions.push_back(makePlant(s, v, kSeed));
      extent = std::max({extent, 2 * versions.back().tightRadius, versions.back().height});
    }
    for (int v = 0; v < count; ++v) {
      const PlantMesh& p = versions[size_t(v)];
      rasterise(sheet, v * kSmall, 0, kSmall, p,
                sideView(0.0f, glm::vec3(0, 0, 0.5f * extent), kSmall / (1.05f * extent)));
      rasterise(sheet, v * kSmall, kSmall, kSmall, p,
                topView(glm::vec3(0), kSmall / (1.05f * extent)));
    }
    writePng(sheet, std::filesystem::path(dir) / (std::string(speciesName(s)) + "_versions.png"));
  }
}

}  // namespace plant_models_test
}  // namespace
}  // namespace terralod::veg
