#include "terralod/build/chunk_mesher.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <set>

#include "terralod/build/activation_pass.h"
#include "terralod/core/sample_raster.h"
#include "test_terrain.h"

namespace terralod {
namespace {

// A built chunk tree in memory (no quantisation), for checking the mesher's promises exactly.
struct Fixture {
  Heightfield heights;
  TreeLayout layout;
  ErrorBudget budget;
  std::unique_ptr<MemoryHeights> memory;
  ActivationGrid grid;

  Fixture(int32_t columns, int32_t rows, int32_t leafCells, double leafError, uint32_t seed)
      : heights(test::makeTestTerrain(columns, rows, seed)),
        layout(makeTreeLayout(columns, rows, leafCells).value()),
        budget(makeErrorBudget(layout, leafError, 400.0).value()),
        memory(std::make_unique<MemoryHeights>(heights)) {
    NullProgress progress;
    ActivationOptions options;
    options.blockCells = 32;
    grid = computeActivations(layout, budget, *memory, *memory, options, progress).value();
  }

  std::vector<ChunkMesh> level(int32_t l) {
    ChunkMesher mesher(layout, budget, grid, *memory);
    std::vector<ChunkMesh> meshes;
    for (int32_t iy = 0; iy < layout.chunksY(l); ++iy)
      for (int32_t ix = 0; ix < layout.chunksX(l); ++ix) meshes.push_back(mesher.build(l, ix, iy));
    return meshes;
  }
};

// Visits the data samples covered by a mesh's surface with the height at morph parameter t.
template <typename Visit>
void rasterize(const ChunkMesh& m, const TreeLayout& layout, double t, Visit&& visit) {
  for (size_t k = 0; k < m.surfaceIndices.size(); k += 3) {
    SampleVertex v[3];
    for (int j = 0; j < 3; ++j) {
      const MeshVertex& mv = m.vertices[m.surfaceIndices[k + j]];
      v[j] = {mv.x, mv.y, mv.z + t * (mv.morphTarget - mv.z)};
    }
    rasterizeTriangle(v[0], v[1], v[2], 0, layout.cellsX, 0, layout.cellsY, visit);
  }
}

class MesherProperties : public ::testing::TestWithParam<std::tuple<int, int, int>> {};

TEST_P(MesherProperties, BoundCoverageMorphSkirtsConformity) {
  const auto [columns, rows, seed] = GetParam();
  Fixture f(columns, rows, 16, 1.0, uint32_t(seed));
  ChunkMesher mesher(f.layout, f.budget, f.grid, *f.memory);
  std::map<std::pair<int32_t, int32_t>, double> previousLevel;  // sample -> surface height
  for (int32_t l = 0; l <= f.layout.depth; ++l) {
    std::map<std::pair<int32_t, int32_t>, double> surface;
    for (const ChunkMesh& m : f.level(l)) {
      // Counter-clockwise, non-degenerate triangles.
      for (size_t k = 0; k < m.surfaceIndices.size(); k += 3) {
        const MeshVertex &a = m.vertices[m.surfaceIndices[k]],
                         &b = m.vertices[m.surfaceIndices[k + 1]],
                         &c = m.vertices[m.surfaceIndices[k + 2]];
        ASSERT_GT(orient2d({a.x, a.y}, {b.x, b.y}, {c.x, c.y}), 0);
      }
      // Bound (before quantisation) and coverage of the chunk's square clipped to the data.
      std::set<std::pair<int32_t, int32_t>> covered;
      rasterize(m, f.layout, 0.0, [&](int64_t x, int64_t y, double z) {
        covered.insert({int32_t(x), int32_t(y)});
        surface[{int32_t(x), int32_t(y)}] = z;
        ASSERT_LE(std::fabs(z - f.heights(int32_t(x), int32_t(y))),
                  f.budget.buildThreshold[l] + 1e-9)
            << "level " << l << " sample " << x << "," << y;
      });
      const int32_t x1 = std::min(m.x0 + m.side, f.layout.cellsX),
                    y1 = std::min(m.y0 + m.side, f.layout.cellsY);
      EXPECT_EQ(covered.size(), size_t(x1 - m.x0 + 1) * size_t(y1 - m.y0 + 1));
      // Fully morphed, the chunk is its parent's surface at every sample.
      if (l > 0) {
        rasterize(m, f.layout, 1.0, [&](int64_t x, int64_t y, double z) {
          ASSERT_NEAR(z, previousLevel.at({int32_t(x), int32_t(y)}), 1e-9)
              << "level " << l << " sample " << x << "," << y;
        });
      }
      // Skirts: deep enough against the surface of any level (morphed or not) across each side.
      for (int side = 0; side < 4; ++side) {
        const bool vertical = side == kEast || side == kWest;
        const int32_t line = side == kSouth   ? m.y0
                             : side == kNorth ? m.y0 + m.side
                             : side == kWest  ? m.x0
                                              : m.x0 + m.side;
        const int32_t limit = vertical ? f.layout.cellsX : f.layout.cellsY;
        if (line <= 0 || line >= limit) {
          EXPECT_EQ(m.skirtDepth[side], 0.0);
          continue;
        }
        ASSERT_GT(m.skirtDepth[side], 0.0);
        const int32_t from = vertical ? m.y0 : m.x0;
        const int32_t to = std::min(from + m.side, vertical ? f.layout.cellsY : f.layout.cellsX);
        const int32_t coarsest = f.layout.coarsestLevelOfBorder(line, l);
        for (int32_t q = from; q <= to; ++q) {
          const GridPoint p = vertical ? GridPoint{line, q} : GridPoint{q, line};
          const double own = mesher.surfaceHeight(l, p);
          const double top = l > 0 ? std::max(own, mesher.surfaceHeight(l - 1, p)) : own;
          double lowest = std::numeric_limits<double>::infinity();
          for (int32_t n = coarsest; n <= f.layout.depth; ++n) {
            lowest = std::min(lowest, mesher.surfaceHeight(n, p));
            if (n > 0) lowest = std::min(lowest, mesher.surfaceHeight(n - 1, p));
          }
          ASSERT_GE(m.skirtDepth[side], top - lowest)
              << "level " << l << " side " << side << " at " << q;
        }
      }
    }
    previousLevel = std::move(surface);
  }
}

TEST_P(MesherProperties, SameLevelChunksShareTheirBorderVertices) {
  const auto [columns, rows, seed] = GetParam();
  Fixture f(columns, rows, 16, 1.0, uint32_t(seed));
  for (int32_t l = 0; l <= f.layout.depth; ++l) {
    // Every border vertex of a chunk must also be a vertex of the chunk across that border.
    std::map<std::pair<int32_t, int32_t>, std::set<std::pair<int32_t, int32_t>>> verticesByChunk;
    const std::vector<ChunkMesh> meshes = f.level(l);
    for (const ChunkMesh& m : meshes)
      for (uint32_t i = 0; i < m.surfaceVertexCount; ++i)
        verticesByChunk[{m.ix, m.iy}].insert({m.vertices[i].x, m.vertices[i].y});
    for (const ChunkMesh& m : meshes) {
      for (uint32_t i = 0; i < m.surfaceVertexCount; ++i) {
        const MeshVertex& v = m.vertices[i];
        if (v.x == m.x0 + m.side && verticesByChunk.count({m.ix + 1, m.iy})) {
          EXPECT_TRUE((verticesByChunk[{m.ix + 1, m.iy}].count({v.x, v.y})));
        }
        if (v.y == m.y0 + m.side && verticesByChunk.count({m.ix, m.iy + 1})) {
          EXPECT_TRUE((verticesByChunk[{m.ix, m.iy + 1}].count({v.x, v.y})));
        }
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Terrains, MesherProperties,
                         ::testing::Values(std::make_tuple(65, 65, 11),
                                           std::make_tuple(100, 37, 12),
                                           std::make_tuple(129, 97, 13)));

TEST_P(MesherProperties, SurfaceFacesUpAndSkirtsFaceOutwards) {
  // Back-face culling must keep every triangle a camera above the terrain or beside a crack
  // can see: surface triangles counter-clockwise from above, skirts from outside the chunk.
  const auto [columns, rows, seed] = GetParam();
  Fixture f(columns, rows, 16, 0.5, uint32_t(seed));
  uint64_t skirts = 0;
  for (int32_t l = 0; l <= f.layout.depth; ++l)
    for (const ChunkMesh& m : f.level(l)) {
      auto corner = [&](uint32_t i) {
        const MeshVertex& v = m.vertices[i];
        return std::array<double, 3>{double(v.x), double(v.y), v.z};
      };
      auto normal = [&](const std::vector<uint32_t>& indices, size_t k) {
        const auto a = corner(indices[k]), b = corner(indices[k + 1]), c = corner(indices[k + 2]);
        const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
        const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
        return std::array<double, 4>{uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx,
                                     (a[0] + b[0] + c[0]) / 3 - (m.x0 + m.side / 2.0)};
      };
      for (size_t k = 0; k < m.surfaceIndices.size(); k += 3)
        ASSERT_GT(normal(m.surfaceIndices, k)[2], 0.0) << "surface triangle faces down";
      for (size_t k = 0; k < m.skirtIndices.size(); k += 3, ++skirts) {
        const auto n = normal(m.skirtIndices, k);
        double cy = 0;
        for (int j = 0; j < 3; ++j) cy += m.vertices[m.skirtIndices[k + j]].y / 3.0;
        // Outwards: the horizontal normal points from the chunk's centre to the skirt.
        const double outX = n[3], outY = cy - (m.y0 + m.side / 2.0);
        ASSERT_GT(n[0] * outX + n[1] * outY, 0.0)
            << "skirt triangle of chunk " << l << "/" << m.ix << "/" << m.iy << " faces inwards";
      }
    }
  EXPECT_GT(skirts, 0u);
}

TEST(Mesher, FlatLandTakesFewTriangles) {
  Heightfield flat(129, 129, 42.0f);
  const TreeLayout layout = makeTreeLayout(129, 129, 16).value();
  const ErrorBudget budget = makeErrorBudget(layout, 0.1, 1.0).value();
  MemoryHeights memory(flat);
  NullProgress progress;
  const ActivationGrid grid =
      computeActivations(layout, budget, memory, memory, {}, progress).value();
  ChunkMesher mesher(layout, budget, grid, memory);
  const ChunkMesh leaf = mesher.build(layout.depth, 1, 1);
  EXPECT_EQ(leaf.surfaceIndices.size(), 6u);  // the two triangles of its square
  EXPECT_EQ(leaf.surfaceVertexCount, 4u);
}

}  // namespace
}  // namespace terralod
