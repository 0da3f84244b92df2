// The exporter's vertex normals (export_mesh.h): unit, exact on planes, and weighted by the
// angle each triangle makes at the vertex rather than by its area.

#include <gtest/gtest.h>

#include <cmath>

#include "terralod/measure/export_mesh.h"

namespace terralod {
namespace {

using Positions = std::vector<std::array<float, 3>>;

// An n x n grid of unit cells on the plane z = ax + by, two counter-clockwise triangles a cell.
void planeGrid(int n, float a, float b, Positions& positions, std::vector<uint32_t>& indices) {
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) positions.push_back({float(x), float(y), a * x + b * y});
  const auto at = [n](int x, int y) { return uint32_t(y * (n + 1) + x); };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      indices.insert(indices.end(), {at(x, y), at(x + 1, y), at(x + 1, y + 1)});
      indices.insert(indices.end(), {at(x, y), at(x + 1, y + 1), at(x, y + 1)});
    }
}

TEST(AngleWeightedNormals, EveryVertexOfAPlaneGetsItsNormal) {
  Positions positions;
  std::vector<uint32_t> indices;
  planeGrid(4, 0.5f, -0.25f, positions, indices);
  const auto normals = angleWeightedNormals(positions, indices);
  ASSERT_EQ(normals.size(), positions.size());
  const double length = std::sqrt(0.25 + 0.0625 + 1);
  for (const auto& n : normals) {
    EXPECT_NEAR(n[0], -0.5 / length, 1e-6);
    EXPECT_NEAR(n[1], 0.25 / length, 1e-6);
    EXPECT_NEAR(n[2], 1 / length, 1e-6);
  }
}

TEST(AngleWeightedNormals, WeightsByAngleNotByArea) {
  // Vertex 0 at the origin is shared by a huge flat triangle with a 90° corner there and a
  // small steep one, normal (1, 0, 1)/√2, with a corner of acos(1/√3) ≈ 54.7° there: angle
  // weights, where area weights would let the flat one swamp the steep one.
  const Positions positions = {{0, 0, 0}, {1000, 0, 0}, {0, 1000, 0}, {0, -1, 0}, {-1, -1, 1}};
  const std::vector<uint32_t> indices = {0, 1, 2, 0, 4, 3};
  const auto normals = angleWeightedNormals(positions, indices);
  const double steepAngle = std::acos(1 / std::sqrt(3.0)), flatAngle = M_PI / 2;
  const double nx = steepAngle / std::sqrt(2.0), ny = 0,
               nz = flatAngle + steepAngle / std::sqrt(2.0);
  const double nl = std::sqrt(nx * nx + ny * ny + nz * nz);
  EXPECT_NEAR(normals[0][0], nx / nl, 1e-6);
  EXPECT_NEAR(normals[0][1], ny / nl, 1e-6);
  EXPECT_NEAR(normals[0][2], nz / nl, 1e-6);
  // The far corners of the flat triangle see only it.
  EXPECT_NEAR(normals[1][2], 1.0, 1e-6);
  EXPECT_NEAR(normals[2][2], 1.0, 1e-6);
}

TEST(AngleWeightedNormals, UnusedAndDegenerateVerticesPointUp) {
  const Positions positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {5, 5, 5}};
  const auto normals = angleWeightedNormals(positions, {0, 1, 2});
  for (const auto& n : normals) EXPECT_EQ(n, (std::array<float, 3>{0, 0, 1}));
}

}  // namespace
}  // namespace terralod
