#include "terralod/vipm/vipm_flanges.h"

#include <algorithm>

namespace terralod {
namespace {

// Two flange triangles per edge of `living` on an interior line.
void appendInteriorFlanges(const Flanges& flanges, uint32_t vertexCount,
                           std::span<const uint16_t> living, std::vector<uint16_t>& out) {
  auto onOneLine = [&](uint16_t a, uint16_t b) {
    const Flanges::OnLine &p = flanges.interior[a], &q = flanges.interior[b];
    return (p.lineX >= 0 && p.lineX == q.lineX) || (p.lineY >= 0 && p.lineY == q.lineY);
  };
  for (size_t i = 0; i + 2 < living.size(); i += 3)
    for (size_t k = 0; k < 3; ++k) {
      const uint16_t a = living[i + k], b = living[i + (k + 1) % 3];
      if (!onOneLine(a, b)) continue;
      const uint16_t a2 = uint16_t(vertexCount + uint32_t(flanges.interior[a].flange)),
                     b2 = uint16_t(vertexCount + uint32_t(flanges.interior[b].flange));
      out.insert(out.end(), {a, b2, b, a, a2, b2});
    }
}

}  // namespace

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
    return c > 0 && c < size - 1 && c % interiorStep == 0 ? int16_t(c) : int16_t(-1);
  };
  f.interior.resize(mesh.vertexCount());
  bool any = false;
  for (uint32_t v = 0; v < mesh.vertexCount(); ++v) {
    Flanges::OnLine& on = f.interior[v];
    on.lineX = interiorLine(mesh.points[v] % w, w);
    on.lineY = interiorLine(mesh.points[v] / w, h);
    if (on.lineX >= 0 || on.lineY >= 0) {
      on.flange = flangeVertex(uint16_t(v));
      any = true;
    }
  }
  if (!any) {
    f.interior.clear();
    return f;
  }
  std::vector<uint16_t> finest;
  for (const auto& tri : mesh.triangles) finest.insert(finest.end(), tri.begin(), tri.end());
  std::vector<uint16_t> indices;
  appendInteriorFlanges(f, mesh.vertexCount(), finest, indices);
  f.interiorEdgesMax = uint32_t(indices.size() / 6);
  return f;
}

void flangeIndices(const Flanges& flanges, uint32_t vertexCount, uint32_t activeVertices,
                   std::span<const uint16_t> living, std::vector<uint16_t>& out) {
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
  if (!flanges.interior.empty()) appendInteriorFlanges(flanges, vertexCount, living, out);
}

size_t maxFlangeIndices(const Flanges& f) {
  size_t n = 0;
  for (const auto& side : f.sides) n += side.size() > 1 ? (side.size() - 1) * 6 : 0;
  return n + size_t(f.interiorEdgesMax) * 6;
}

}  // namespace terralod
