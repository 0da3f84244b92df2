#pragma once
// The plant species of the vegetation scenes and how many modelled versions each has
// (papers/tiling-layered-depth-images.md §3: 11 sunflowers; 15 grass clumps, 9 dandelions and
// 15 small yellow flowers).

#include <cstdint>
#include <optional>
#include <string_view>

namespace terralod::veg {

enum class Species : uint8_t { kSunflower = 0, kGrass = 1, kDandelion = 2, kYellowFlower = 3 };
inline constexpr int kSpeciesCount = 4;

constexpr int versionCount(Species s) {
  switch (s) {
    case Species::kSunflower:
      return 11;
    case Species::kGrass:
      return 15;
    case Species::kDandelion:
      return 9;
    case Species::kYellowFlower:
      return 15;
  }
  return 0;
}

constexpr std::string_view speciesName(Species s) {
  switch (s) {
    case Species::kSunflower:
      return "sunflower";
    case Species::kGrass:
      return "grass";
    case Species::kDandelion:
      return "dandelion";
    case Species::kYellowFlower:
      return "yellow_flower";
  }
  return "?";
}

inline std::optional<Species> speciesFromIndex(uint32_t i) {
  if (i >= uint32_t(kSpeciesCount)) return std::nullopt;
  return Species(i);
}

}  // namespace terralod::veg
