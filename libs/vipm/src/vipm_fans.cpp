#include "terralod/vipm/vipm_fans.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <tuple>

#include "collapse_replay.h"

namespace terralod {
namespace {

bool keyLess(const StitchPoint& a, const StitchPoint& b) {
  return std::tie(a.along, a.z) < std::tie(b.along, b.z);
}

// A fan corner in the chunk's frame (doubles, exact): a vertex of the chunk or an inserted
// point (id >= the chunk's vertex count).
struct Corner {
  double x = 0, y = 0, z = 0;
  uint32_t id = 0;
};
using Tri = std::array<Corner, 3>;

}  // namespace

void StitchTable::clear() {
  for (auto& [line, points] : mLines) points.clear();
}

void StitchTable::add(const StitchLine& line, const StitchPoint& point) {
  mLines[line].push_back(point);
}

void StitchTable::finish() {
  for (auto& [line, points] : mLines) {
    std::sort(points.begin(), points.end(), keyLess);
    points.erase(std::unique(points.begin(), points.end(),
                             [](const StitchPoint& a, const StitchPoint& b) {
                               return a.along == b.along && a.z == b.z;
                             }),
                 points.end());
  }
}

size_t StitchTable::pointCount() const {
  size_t n = 0;
  for (const auto& [line, points] : mLines) n += points.size();
  return n;
}

std::span<const StitchPoint> StitchTable::between(const StitchLine& line, double along0, double z0,
                                                  double along1, double z1, bool& reversed) const {
  auto it = mLines.find(line);
  if (it == mLines.end()) return {};
  StitchPoint lo, hi;
  lo.along = along0;
  lo.z = z0;
  hi.along = along1;
  hi.z = z1;
  reversed = keyLess(hi, lo);
  if (reversed) std::swap(lo, hi);
  const auto& points = it->second;
  auto first = std::upper_bound(points.begin(), points.end(), lo, keyLess);
  auto last = std::lower_bound(first, points.end(), hi, keyLess);
  return {first, last};
}

std::span<const StitchPoint> StitchTable::span(const StitchLine& line, double along0,
                                               double along1) const {
  auto it = mLines.find(line);
  if (it == mLines.end()) return {};
  const auto& points = it->second;
  auto first = std::lower_bound(points.begin(), points.end(), along0,
                                [](const StitchPoint& p, double a) { return p.along < a; });
  auto last = std::upper_bound(first, points.end(), along1,
                               [](double a, const StitchPoint& p) { return a < p.along; });
  return {first, last};
}

void StitchFans::clear() {
  replaced.clear();
  triangles.clear();
  positions.clear();
  weights.clear();
  materials.clear();
}

double stitchQuantum(uint32_t largestCells) {
  // Values up to 2^bits are exact in float at 2^(bits-24); one bit to spare.
  const int bits = std::max(7, int(std::bit_width(std::max(largestCells, 1u) - 1)));
  return std::ldexp(1.0, bits - 23);
}

void roundStitchPoint(std::array<float, 3>& p, const StitchChunk& chunk) {
  // Its sides, or an inner seam (a vertex's own coordinates lie within its sides).
  auto onLine = [&](float local, int32_t points) {
    if (local == 0.0f || local == float(points - 1)) return true;
    return chunk.seamStep > 0 && local == std::floor(local) && int64_t(local) % chunk.seamStep == 0;
  };
  const bool onX = onLine(p[0], chunk.width), onY = onLine(p[1], chunk.height);
  if (!onX && !onY) return;
  const double q = stitchQuantum(chunk.largestCells);
  // A point sliding along a line never lands on a place where spans end (a chunk's corner,
  // a multiple of kStitchLineCells): a span holds only the points strictly inside it, so
  // one side would keep it and the other not.
  auto along = [&](float& a) {
    const double rounded = std::round(double(a) / q) * q;
    const bool end = std::fmod(rounded, double(kStitchLineCells)) == 0.0;
    a = float(end && rounded != double(a) ? rounded + (double(a) < rounded ? -q : q) : rounded);
  };
  constexpr double kZ = 1024.0;
  if (onX) along(p[1]);
  if (onY) along(p[0]);
  p[2] = float(std::round(double(p[2]) * kZ) / kZ);
}

VipmStitcher::VipmStitcher(const ProgressiveMesh& mesh, const StitchChunk& chunk)
    : mChunk(chunk), mVertexCount(mesh.vertexCount()) {
  // The chunk's lines: its four sides, then its inner seams.
  auto addLine = [&](uint8_t axis, int32_t local) {
    const int64_t corner = axis == 0 ? chunk.cornerX : chunk.cornerY;
    mLines.push_back({{axis, corner + local}, double(local)});
  };
  addLine(0, 0);
  addLine(0, chunk.width - 1);
  addLine(1, 0);
  addLine(1, chunk.height - 1);
  if (chunk.seamStep > 0) {
    for (int32_t x = chunk.seamStep; x < chunk.width - 1; x += chunk.seamStep) addLine(0, x);
    for (int32_t y = chunk.seamStep; y < chunk.height - 1; y += chunk.seamStep) addLine(1, y);
  }
  // Bounds: on each side of a line, every point of the others strictly inside the chunk's
  // span is inserted once, into one edge (a seam has two sides); each insertion adds a
  // triangle to its edge's fan, and each replaced triangle has an edge there.
  for (size_t l = 0; l < mLines.size(); ++l) {
    const uint32_t cells = uint32_t(mLines[l].line.axis == 0 ? chunk.height - 1 : chunk.width - 1);
    const uint32_t sides = l < 4 ? 1 : 2;
    mMaxInserted += sides * (cells + 2);
    mMaxTriangles += sides * (2 * cells + 2);
  }

  std::vector<uint8_t> maskOf(mVertexCount, 0);
  for (uint32_t v = 0; v < mVertexCount; ++v) {
    const int32_t x = int32_t(mesh.points[v]) % mesh.width;
    const int32_t y = int32_t(mesh.points[v]) / mesh.width;
    uint8_t mask = 0;
    for (size_t l = 0; l < mLines.size(); ++l) {
      const int32_t c = mLines[l].line.axis == 0 ? x : y;
      if (double(c) == mLines[l].local) mask |= uint8_t(1u << l);
    }
    maskOf[v] = mask;
    if (mask) {
      mBorderVertices.push_back(uint16_t(v));
      mLineMask.push_back(mask);
    }
  }
  // Triangles with two corners on one line at some level: at the finest, or after a collapse
  // moves one of their corners.
  const uint32_t triangleCount = uint32_t(mesh.triangles.size());
  std::vector<uint16_t> corners(size_t(triangleCount) * 3);
  std::vector<uint8_t> candidate(triangleCount, 0);
  auto check = [&](uint32_t t) {
    const uint8_t a = maskOf[corners[3 * t]], b = maskOf[corners[3 * t + 1]],
                  c = maskOf[corners[3 * t + 2]];
    if ((a & b) | (b & c) | (c & a)) candidate[t] = 1;
  };
  for (uint32_t t = 0; t < triangleCount; ++t) {
    for (int k = 0; k < 3; ++k) corners[3 * t + k] = mesh.triangles[t][k];
    check(t);
  }
  // The mesh was validated when it was reconstructed; a failure here leaves the candidates
  // of the finest level.
  (void)replayCollapses(
      mesh,
      [&](uint32_t j, uint32_t corner) {
        corners[corner] = mesh.targets[j];
        check(corner / 3);
      },
      [](uint32_t, uint32_t) {});
  for (uint32_t t = 0; t < triangleCount; ++t)
    if (candidate[t]) mCandidates.push_back(t);
}

void VipmStitcher::addPoints(StitchTable& table, uint32_t activeVertices,
                             std::span<const std::array<float, 3>> drawn,
                             std::span<const std::array<uint8_t, kMaxMaterials>> weights,
                             std::span<const uint8_t> materials) const {
  for (size_t i = 0; i < mBorderVertices.size(); ++i) {
    const uint16_t v = mBorderVertices[i];
    if (v >= activeVertices) continue;
    const auto& p = drawn[v];
    StitchPoint point;
    point.z = mChunk.zBase + double(p[2]);
    point.weights = weights[v];
    point.material = materials[v];
    for (size_t l = 0; l < mLines.size(); ++l) {
      if (!(mLineMask[i] & (1u << l))) continue;
      point.along = mLines[l].line.axis == 0 ? double(mChunk.cornerY) + double(p[1])
                                             : double(mChunk.cornerX) + double(p[0]);
      table.add(mLines[l].line, point);
    }
  }
}

uint64_t VipmStitcher::signature(const StitchTable& table, uint32_t applied) const {
  uint64_t h = 1469598103934665603ull ^ applied;
  auto mix = [&h](const void* data, size_t bytes) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < bytes; ++i) h = (h ^ b[i]) * 1099511628211ull;
  };
  for (const Line& l : mLines) {
    const double origin = double(l.line.axis == 0 ? mChunk.cornerY : mChunk.cornerX);
    const double length = double(l.line.axis == 0 ? mChunk.height - 1 : mChunk.width - 1);
    for (const StitchPoint& p : table.span(l.line, origin, origin + length)) {
      mix(&p.along, sizeof(p.along));
      mix(&p.z, sizeof(p.z));
      mix(p.weights.data(), p.weights.size());
      mix(&p.material, 1);
    }
    mix(&l.local, sizeof(l.local));  // a line without points still counts
  }
  return h;
}

void VipmStitcher::fan(const StitchTable& table, std::span<const uint16_t> living,
                       std::span<const std::array<float, 3>> drawn, StitchFans& out) const {
  out.clear();
  const uint32_t livingTriangles = uint32_t(living.size() / 3);
  std::vector<const StitchPoint*> inserted;  // per inserted point: its table entry
  auto ownCorner = [&](uint16_t v) {
    const auto& p = drawn[v];
    return Corner{double(p[0]), double(p[1]), double(p[2]), v};
  };
  auto insertedCorner = [&](const StitchPoint& s, const Line& l) {
    uint32_t k = 0;
    while (k < inserted.size() && inserted[k] != &s) ++k;
    if (k == inserted.size()) {
      inserted.push_back(&s);
      std::array<float, 3> p{};
      const double along =
          l.line.axis == 0 ? s.along - double(mChunk.cornerY) : s.along - double(mChunk.cornerX);
      p[l.line.axis == 0 ? 0 : 1] = float(l.local);
      p[l.line.axis == 0 ? 1 : 0] = float(along);
      p[2] = float(s.z - mChunk.zBase);
      out.positions.push_back(p);
      out.weights.push_back(s.weights);
      out.materials.push_back(s.material);
    }
    const auto& p = out.positions[k];
    return Corner{double(p[0]), double(p[1]), double(p[2]), mVertexCount + k};
  };
  auto onLine = [](const Corner& c, const Line& l) {
    return (l.line.axis == 0 ? c.x : c.y) == l.local;
  };
  // The table's points strictly inside edge p -> q on one of the chunk's lines, if any.
  struct Inside {
    std::span<const StitchPoint> points;
    bool reversed = false;
    const Line* line = nullptr;
  };
  auto inside = [&](const Corner& p, const Corner& q) {
    Inside r;
    for (const Line& l : mLines) {
      if (!onLine(p, l) || !onLine(q, l)) continue;
      const double origin = double(l.line.axis == 0 ? mChunk.cornerY : mChunk.cornerX);
      const double ap = origin + (l.line.axis == 0 ? p.y : p.x);
      const double aq = origin + (l.line.axis == 0 ? q.y : q.x);
      if (ap == aq) continue;  // across the line, not along it
      r.points = table.between(l.line, ap, mChunk.zBase + p.z, aq, mChunk.zBase + q.z, r.reversed);
      if (!r.points.empty()) {
        r.line = &l;
        return r;
      }
    }
    return r;
  };

  std::vector<Tri> stack;
  for (uint32_t t : mCandidates) {
    if (t >= livingTriangles) break;
    const Tri tri{ownCorner(living[3 * t]), ownCorner(living[3 * t + 1]),
                  ownCorner(living[3 * t + 2])};
    bool replaced = false;
    stack.assign(1, tri);
    // A piece's edge on a line is split into consecutive points of the table, so fanning
    // ends; the guard only bounds a damaged mesh's work.
    for (uint32_t guard = 0; !stack.empty() && guard < 4 * mMaxTriangles + 16; ++guard) {
      const Tri piece = stack.back();
      stack.pop_back();
      // The edge to split first: on the finest line (stitchLineOrder), so that a corner
      // piece is cut as the node above closed it when it was built.
      int chosen = -1;
      Inside in;
      for (int e = 0; e < 3; ++e) {
        const Inside at = inside(piece[size_t(e)], piece[size_t((e + 1) % 3)]);
        if (!at.points.empty() &&
            (chosen < 0 || stitchLineOrder(at.line->line) < stitchLineOrder(in.line->line))) {
          chosen = e;
          in = at;
        }
      }
      const bool split = chosen >= 0;
      if (split) {
        replaced = true;
        const Corner& a = piece[size_t(chosen)];
        const Corner& b = piece[size_t((chosen + 1) % 3)];
        const Corner& apex = piece[size_t((chosen + 2) % 3)];
        // a, p1, ..., pk, b in order from a to b: pieces (a, p1, apex) ... (pk, b, apex).
        Corner previous = a;
        const size_t k = in.points.size();
        for (size_t i = 0; i < k; ++i) {
          const StitchPoint& s = in.points[in.reversed ? k - 1 - i : i];
          const Corner c = insertedCorner(s, *in.line);
          stack.push_back({previous, c, apex});
          previous = c;
        }
        stack.push_back({previous, b, apex});
      }
      if (!split && replaced) out.triangles.push_back({piece[0].id, piece[1].id, piece[2].id});
    }
    if (replaced) out.replaced.push_back(t);
  }
}

}  // namespace terralod
