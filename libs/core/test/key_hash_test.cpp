// KeyHash and KeyMap against std::unordered_map: the same answers for keys present and
// absent, across the growth from its first size, and for keys that collide in its low and high
// bits (grid keys (y << 32) | x among them).

#include <gtest/gtest.h>

#include <random>
#include <unordered_map>

#include "terralod/core/key_hash.h"

namespace terralod {
namespace {

TEST(KeyHash, AnswersAsAMapDoesAcrossGrowth) {
  for (size_t expected : {size_t{0}, size_t{100}, size_t{1} << 20}) {
    KeyHash hash(expected);
    std::unordered_map<uint32_t, int32_t> map;
    std::mt19937 rng(uint32_t(expected) + 1);
    for (int32_t i = 0; i < 200000; ++i) {
      // Grid-like keys (y * 1025 + x) and arbitrary ones, many repeated.
      const uint32_t key = (i & 1) ? (rng() % 1025) * 1025 + rng() % 1025 : rng() % 4000000;
      const auto [it, added] = map.try_emplace(key, i);
      ASSERT_EQ(hash.findOrAdd(key, i), it->second) << key;
      if (i % 7 == 0) {
        const uint32_t probe = rng();
        const auto found = map.find(probe);
        ASSERT_EQ(hash.find(probe), found == map.end() ? -1 : found->second) << probe;
      }
    }
    EXPECT_EQ(hash.size(), map.size());
    for (const auto& [key, value] : map) ASSERT_EQ(hash.find(key), value);
  }
}

TEST(KeyHash, KeysThatShareLowOrHighBits) {
  KeyHash hash(4);
  for (uint32_t i = 1; i < 5000; ++i) {
    EXPECT_EQ(hash.findOrAdd(i << 16, int32_t(i)), int32_t(i));
    EXPECT_EQ(hash.findOrAdd(i, int32_t(i) + 5000), int32_t(i) + 5000);
    EXPECT_EQ(hash.findOrAdd(i << 16, -7), int32_t(i));  // present: unchanged
  }
  for (uint32_t i = 1; i < 5000; ++i) {
    EXPECT_EQ(hash.find(i << 16), int32_t(i));
    EXPECT_EQ(hash.find(i), int32_t(i) + 5000);
  }
  EXPECT_EQ(hash.find(0), -1);
  EXPECT_EQ(hash.find(KeyHash::kNoKey - 1), -1);
  EXPECT_EQ(hash.size(), 9998u);
}

TEST(KeyMap, GridKeysOfSixtyFourBits) {
  KeyMap<uint64_t, float> map;
  std::unordered_map<uint64_t, float> reference;
  std::mt19937 rng(7);
  for (int i = 0; i < 100000; ++i) {
    // Points of a 70,000-sample grid: rows and columns beyond 2^16 reach the high word.
    const uint64_t key = (uint64_t(rng() % 70000) << 32) | (rng() % 70000);
    const float value = float(i) * 0.5f;
    const auto [it, added] = reference.try_emplace(key, value);
    ASSERT_EQ(map.findOrAdd(key, value), it->second);
  }
  EXPECT_EQ(map.size(), reference.size());
  for (const auto& [key, value] : reference) {
    const float* found = map.find(key);
    ASSERT_NE(found, nullptr);
    EXPECT_EQ(*found, value);
  }
  EXPECT_EQ(map.find(uint64_t{70001} << 32), nullptr);
  EXPECT_EQ(map.find(70001), nullptr);
}

}  // namespace
}  // namespace terralod
