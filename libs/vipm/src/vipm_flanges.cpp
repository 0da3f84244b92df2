#include "terralod/vipm/vipm_flanges.h"

#include <algorithm>

namespace terralod {

Flanges makeFlanges(const ProgressiveMesh& mesh, uint8_t sideMask, int32_t interiorStep) {
  const int32_t w = mesh.width, h = mesh.height;
  Flanges f;
  std::vector<int32_t> flangeOf(mesh.vertexCount(), -1);
  auto flangeVertex = [&](uint16_t v) {
    if (flangeOf[v] < 0) {
      flangeOf[v] = int32_t(f.tops.size());
      f.tops.push_back(v);
    }
    return uint16_t(flangeOf[v]);
  };
  // Side: which points lie on it, and their position along it.
  struct Side {
    uint8_t bit;
    bool (*on)(int32_t x, int32_t y, int32_t w, int32_t h);
    bool alongX;
  };
  const Side sides[] = {
      {kFlangeWest, [](int32_t x, int32_t, int32_t, int32_t) { return x == 0; }, false},
      {kFlangeEast, [](int32_t x, int32_t, int32_t cw, int32_t) { return x == cw - 1; }, false},
      {kFlangeSouth, [](int32_t, int32_t y, int32_t, int32_t) { return y == 0; }, true},
      {kFlangeNorth, [](int32_t, int32_t y, int32_t, int32_t ch) { return y == ch - 1; }, true},
  };
  for (const Side& s : sides) {
    if (!(sideMask & s.bit)) continue;
    std::vector<std::pair<int32_t, uint16_t>> along;  // position along the side, vertex
    for (uint32_t v = 0; v < mesh.vertexCount(); ++v) {
      const int32_t x = mesh.points[v] % w, y = mesh.points[v] / w;
      if (s.on(x, y, w, h)) along.push_back({s.alongX ? x : y, uint16_t(v)});
    }
    std::sort(along.begin(), along.end());
    std::vector<uint16_t> side;
    for (const auto& [position, v] : along) side.push_back(flangeVertex(v));
    f.sides.push_back(std::move(side));
  }
  if (interiorStep <= 0) return f;
  auto interiorLine = [&](int32_t c, int32_t size) {
    return c > 0 && c < size - 1 && c % interiorStep == 0;
  };
  for (const auto& tri : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const uint16_t a = tri[size_t(k)], b = tri[size_t((k + 1) % 3)];
      const int32_t ax = mesh.points[a] % w, ay = mesh.points[a] / w;
      const int32_t bx = mesh.points[b] % w, by = mesh.points[b] / w;
      if ((ax == bx && interiorLine(ax, w)) || (ay == by && interiorLine(ay, h)))
        f.interior.push_back({flangeVertex(a), flangeVertex(b)});
    }
  return f;
}

void flangeIndices(const Flanges& flanges, uint32_t vertexCount, uint32_t activeVertices,
                   std::vector<uint16_t>& out) {
  out.clear();
  for (const std::vector<uint16_t>& side : flanges.sides) {
    int32_t previous = -1;  // the last active vertex along the side, as a flange index
    for (uint16_t k : side) {
      if (flanges.tops[k] >= activeVertices) continue;
      if (previous >= 0) {
        const uint16_t a = flanges.tops[size_t(previous)], b = flanges.tops[k];
        const uint16_t a2 = uint16_t(vertexCount + uint32_t(previous)),
                       b2 = uint16_t(vertexCount + k);
        out.insert(out.end(), {a, b2, b, a, a2, b2});
      }
      previous = k;
    }
  }
  for (const auto& [ka, kb] : flanges.interior) {
    const uint16_t a = flanges.tops[ka], b = flanges.tops[kb];
    if (a >= activeVertices || b >= activeVertices) continue;
    const uint16_t a2 = uint16_t(vertexCount + ka), b2 = uint16_t(vertexCount + kb);
    out.insert(out.end(), {a, b2, b, a, a2, b2});
  }
}

}  // namespace terralod
