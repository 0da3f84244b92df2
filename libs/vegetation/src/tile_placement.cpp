#include "terralod/vegetation/tile_placement.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <numbers>
#include <optional>

#include "random_stream.h"
#include "terralod/vegetation/wang_tiling.h"

namespace terralod::veg {
namespace {

constexpr float kCornerBoxScale = 1.0f;
enum Side { kNorth = 0, kEast = 1, kSouth = 2, kWest = 3 };

// Where a dart may land: anywhere in its tile, across its south or west edge line (within the
// dart's tight radius of it, either side), or in a corner box (within mCornerBox of two edges).
enum class DartArea { kAnywhere, kAcrossSouth, kAcrossWest, kCorner };
constexpr Side opposite(Side s) {
  return Side((s + 2) % 4);
}

uint8_t colourOf(const TileEdges& e, Side s) {
  switch (s) {
    case kNorth:
      return e.north;
    case kEast:
      return e.east;
    case kSouth:
      return e.south;
    case kWest:
      return e.west;
  }
  return 0;
}

// Where a point of a tile lies in the frame of its neighbour across side s.
struct Shift {
  float dx, dy;
};
Shift intoNeighbourAcross(Side s, float size) {
  switch (s) {
    case kNorth:
      return {0, -size};
    case kEast:
      return {-size, 0};
    case kSouth:
      return {0, size};
    case kWest:
      return {size, 0};
  }
  return {0, 0};
}

// How far a point is from the line of side s (negative outside the tile).
float distanceToSide(float x, float y, Side s, float size) {
  switch (s) {
    case kNorth:
      return size - y;
    case kEast:
      return size - x;
    case kSouth:
      return y;
    case kWest:
      return x;
  }
  return 0;
}

// One place a dart would be stored: prototile `tile`, at (x, y) in its frame.
struct Copy {
  int tile;
  float x, y;
};

class Placer {
 public:
  Placer(const PlacementSettings& s, uint32_t edgeTarget)
      : mS(s), mTiles(kWangPrototiles), mEdgeTarget(edgeTarget) {
    for (int k = 0; k < kWangPrototiles; ++k) mTiles[k].edges = prototileEdges(k);
  }

  // Every copy of a dart thrown in `home` at (o.x, o.y); empty when its tight disk crosses
  // two edge lines.
  std::vector<Copy> copiesOf(int home, const PlacedObject& o) const {
    int crossed = -1, crossings = 0;
    for (int s = 0; s < 4; ++s)
      if (distanceToSide(o.x, o.y, Side(s), mS.tileSize) < o.tightRadius) {
        crossed = s;
        ++crossings;
      }
    if (crossings == 0) return {{home, o.x, o.y}};
    if (crossings > 1) return {};
    const Side side = Side(crossed);
    const uint8_t colour = colourOf(mTiles[home].edges, side);
    const Shift shift = intoNeighbourAcross(side, mS.tileSize);
    std::vector<Copy> copies;
    for (int k = 0; k < kWangPrototiles; ++k) {
      if (colourOf(mTiles[k].edges, side) == colour) copies.push_back({k, o.x, o.y});
      if (colourOf(mTiles[k].edges, opposite(side)) == colour)
        copies.push_back({k, o.x + shift.dx, o.y + shift.dy});
    }
    return copies;
  }

  bool clashes(const PlacedObject& o, float x, float y, const std::vector<PlacedObject>& others,
               float dx, float dy) const {
    for (const PlacedObject& p : others) {
      const float ex = p.x + dx - x, ey = p.y + dy - y, r = o.packingRadius + p.packingRadius;
      if (ex * ex + ey * ey < r * r) return true;
    }
    return false;
  }

  // The packing test of one copy: its own prototile's plants, and those of every prototile
  // that can lie across a side its packing disk (with the largest other's) reaches.
  bool copyFits(const PlacedObject& o, const Copy& c) const {
    if (clashes(o, c.x, c.y, mTiles[c.tile].objects, 0, 0)) return false;
    const float reach = o.packingRadius + mMaxPacking;
    for (int s = 0; s < 4; ++s) {
      const Side side = Side(s);
      if (distanceToSide(c.x, c.y, side, mS.tileSize) >= reach) continue;
      const uint8_t colour = colourOf(mTiles[c.tile].edges, side);
      // A point of the neighbour's frame in ours: the inverse of intoNeighbourAcross.
      const Shift back = intoNeighbourAcross(opposite(side), mS.tileSize);
      for (int k = 0; k < kWangPrototiles; ++k)
        if (colourOf(mTiles[k].edges, opposite(side)) == colour &&
            clashes(o, c.x, c.y, mTiles[k].objects, back.dx, back.dy))
          return false;
    }
    return true;
  }

  // The species of a visit, by the mix's weights: chosen once a visit, so that the counts
  // placed follow the weights (per dart, small plants would take the room big ones miss).
  // Species a tile found no room for are left out (`full`, one bit each).
  const SpeciesMix* pickSpecies(RandomStream& rng, uint32_t full) const {
    double total = 0;
    for (size_t k = 0; k < mS.mix.size(); ++k)
      if (!(full >> k & 1)) total += mS.mix[k].weight;
    double pick = rng.uniform() * total;
    const SpeciesMix* last = nullptr;
    for (size_t k = 0; k < mS.mix.size(); ++k)
      if (!(full >> k & 1)) {
        last = &mS.mix[k];
        if ((pick -= mS.mix[k].weight) < 0) break;
      }
    return last;
  }

  PlacedObject dart(const SpeciesMix* mix, RandomStream& rng, const TightRadiusOf& tightRadius,
                    DartArea area) {
    PlacedObject o;
    o.species = mix->species;
    o.version = uint8_t(rng.below(uint32_t(versionCount(mix->species))));
    o.rotation = float(rng.uniform(0, 2 * std::numbers::pi));
    o.scale = float(rng.uniform(mix->minScale, mix->maxScale));
    o.tightRadius = tightRadius(o.species, o.version) * o.scale;
    o.packingRadius = o.tightRadius * std::max(1.0f, mix->packingFactor);
    o.x = float(rng.uniform(0, mS.tileSize));
    o.y = float(rng.uniform(0, mS.tileSize));
    if (area == DartArea::kCorner) {
      const uint32_t corner = rng.below(4);
      const float u = float(rng.uniform(0, mCornerBox)), v = float(rng.uniform(0, mCornerBox));
      o.x = corner & 1 ? mS.tileSize - u : u;
      o.y = corner & 2 ? mS.tileSize - v : v;
    } else if (area != DartArea::kAnywhere) {
      (area == DartArea::kAcrossSouth ? o.y : o.x) =
          float(rng.uniform(-o.tightRadius, o.tightRadius));
    }
    return o;
  }

  // One visit: up to attemptsPerVisit darts of one species; true when one was kept. A
  // species that finds no room is marked full in `full`.
  bool visit(int home, uint32_t& full, RandomStream& rng, const TightRadiusOf& tightRadius,
             DartArea area = DartArea::kAnywhere) {
    const SpeciesMix* mix = pickSpecies(rng, full);
    for (uint32_t a = 0; a < mS.attemptsPerVisit; ++a) {
      const PlacedObject o = dart(mix, rng, tightRadius, area);
      const std::vector<Copy> copies = copiesOf(home, o);
      if (copies.empty()) continue;
      if (!std::all_of(copies.begin(), copies.end(), [&](const Copy& c) { return copyFits(o, c); }))
        continue;
      for (const Copy& c : copies) {
        PlacedObject placed = o;
        placed.x = c.x;
        placed.y = c.y;
        mTiles[c.tile].objects.push_back(placed);
      }
      mMaxPacking = std::max(mMaxPacking, o.packingRadius);
      return true;
    }
    full |= 1u << (mix - mS.mix.data());
    return false;
  }

  // The edges first: plants crossing an edge must find room in all 8 prototiles that carry
  // its colour, which filled tiles rarely offer, so thrown among the rest they stay few and
  // every tile edge shows as a sparse line. Each of the 4 edge colours (2 for south/north
  // edges, 2 for west/east) is visited in turn, darts thrown across its line in a prototile
  // with that colour on its south or west side, until no species finds room or the colour
  // has mEdgeTarget plants (saturated, an edge would pack a denser line than the field).
  void placeEdges(RandomStream& rng, const TightRadiusOf& tightRadius) {
    struct EdgeClass {
      Side side;
      int tile;  // a prototile with this colour on `side`
      uint32_t full = 0;
      bool done = false;
      uint32_t placed = 0;
    };
    std::vector<EdgeClass> classes;
    for (Side side : {kSouth, kWest})
      for (uint8_t colour = 0; colour < 2; ++colour)
        for (int k = 0; k < kWangPrototiles; ++k)
          if (colourOf(mTiles[k].edges, side) == colour) {
            classes.push_back({side, k});
            break;
          }
    const uint32_t allFull = (1u << mS.mix.size()) - 1;
    for (size_t left = classes.size(); left > 0;)
      for (EdgeClass& c : classes) {
        if (c.done) continue;
        const DartArea area = c.side == kSouth ? DartArea::kAcrossSouth : DartArea::kAcrossWest;
        const bool kept = visit(c.tile, c.full, rng, tightRadius, area);
        c.placed += kept;
        if ((!kept && c.full == allFull) || c.placed >= mEdgeTarget) {
          c.done = true;
          --left;
        }
      }
  }

  // Then the corners: a dart there is tested against the prototiles across both edges, so
  // among the rest it rarely finds room once they fill. Each prototile in turn gets darts
  // within twice the largest packing radius of two of its edges, until none fits.
  void placeCorners(RandomStream& rng, const TightRadiusOf& tightRadius) {
    for (const SpeciesMix& m : mS.mix)
      for (int v = 0; v < versionCount(m.species); ++v)
        mCornerBox = std::max(mCornerBox, kCornerBoxScale * tightRadius(m.species, v) * m.maxScale *
                                              std::max(1.0f, m.packingFactor));
    mCornerBox = std::min(mCornerBox, mS.tileSize / 2);
    // A tile's corners are done when a visit finds no room (for any species: the smallest
    // would otherwise pack the corners tighter than the interior, where every species mixes).
    std::array<bool, kWangPrototiles> done{};
    for (int left = kWangPrototiles; left > 0;)
      for (int k = 0; k < kWangPrototiles; ++k) {
        uint32_t full = 0;
        if (!done[k] && !visit(k, full, rng, tightRadius, DartArea::kCorner)) {
          done[k] = true;
          --left;
        }
      }
  }

  Placement run(const TightRadiusOf& tightRadius, Progress& progress) {
    RandomStream rng(mS.seed);
    if (mS.edgesAndCornersFirst) {
      placeEdges(rng, tightRadius);
      placeCorners(rng, tightRadius);
    }
    std::array<bool, kWangPrototiles> done{};
    std::array<uint32_t, kWangPrototiles> full{};
    const uint32_t allFull = (1u << mS.mix.size()) - 1;
    progress.begin("placing plants", kWangPrototiles);
    for (int finished = 0; finished < kWangPrototiles;) {
      for (int k = 0; k < kWangPrototiles; ++k) {
        if (done[k]) continue;
        if (visit(k, full[k], rng, tightRadius) || full[k] != allFull) continue;
        done[k] = true;
        ++finished;
        progress.advance();
      }
    }
    progress.end();
    return {std::move(mTiles)};
  }

 private:
  const PlacementSettings& mS;
  std::vector<PrototileContent> mTiles;
  float mMaxPacking = 0;
  float mCornerBox = 0;
  uint32_t mEdgeTarget;
};

}  // namespace

Placement placeObjects(const PlacementSettings& settings, const TightRadiusOf& tightRadius,
                       Progress& progress) {
  assert(!settings.mix.empty() && settings.tileSize > 0);
  if (!settings.edgesAndCornersFirst) return Placer(settings, 0).run(tightRadius, progress);
  // How many plants the field holds along an edge line: a plain placement (another seed)
  // measures the density and the mean tight radius; a plant crosses the line when its centre
  // is within its tight radius of it. The edge pass places kEdgeShare of that, and leaves the
  // rest to the round-robin, whose darts cross edges too.
  constexpr double kEdgeShare = 0.8;
  PlacementSettings plain = settings;
  plain.edgesAndCornersFirst = false;
  plain.seed = settings.seed ^ 0x5bd1e995ull;
  NullProgress quiet;
  const Placement probe = Placer(plain, 0).run(tightRadius, quiet);
  double count = 0, tight = 0;
  for (const PrototileContent& t : probe.tiles)
    for (const PlacedObject& o : t.objects)
      if (centredIn(o, settings.tileSize)) count += 1, tight += o.tightRadius;
  const double density = count / (kWangPrototiles * double(settings.tileSize) * settings.tileSize);
  const double meanTight = count > 0 ? tight / count : 0;
  const auto edgeTarget =
      uint32_t(std::lround(kEdgeShare * density * settings.tileSize * 2 * meanTight));
  return Placer(settings, std::max(1u, edgeTarget)).run(tightRadius, progress);
}

}  // namespace terralod::veg
