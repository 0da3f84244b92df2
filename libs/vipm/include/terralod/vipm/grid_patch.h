#pragma once
// The samples of one VIPM chunk: a rectangle of DEM grid points with their heights and
// material classes. A full chunk is 65 x 65 points (64 x 64 cells, so chunks line up with the
// chunk quadtree's 64-cell leaves); chunks on the data's east and north edges can be narrower.
// Neighbouring chunks share their border points.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace terralod {

/// Cells along each side of a full VIPM chunk.
inline constexpr int32_t kVipmChunkCells = 64;

struct GridPatch {
  int32_t width = 0;   ///< points along x (east), 2 .. kVipmChunkCells + 1
  int32_t height = 0;  ///< points along y (north), 2 .. kVipmChunkCells + 1
  /// Row-major, south row first: point (x, y) is at y * width + x. Metres: the source samples
  /// every error is measured against.
  std::vector<float> heights;
  /// Same layout: the heights the mesh's vertices get (e.g. the stored, quantised ones). Empty:
  /// the samples themselves.
  std::vector<float> vertexHeights;
  /// Same layout: the point's material index (into the tileset's material table).
  std::vector<uint8_t> materials;

  uint16_t id(int32_t x, int32_t y) const { return uint16_t(y * width + x); }
  int32_t xOf(uint32_t id) const { return int32_t(id) % width; }
  int32_t yOf(uint32_t id) const { return int32_t(id) / width; }
  float heightAt(int32_t x, int32_t y) const { return heights[size_t(y) * width + x]; }
  float vertexHeight(uint32_t id) const {
    return vertexHeights.empty() ? heights[id] : vertexHeights[id];
  }
  uint32_t pointCount() const { return uint32_t(width) * uint32_t(height); }
};

}  // namespace terralod
