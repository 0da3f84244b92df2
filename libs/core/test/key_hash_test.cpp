// KeyHash against std::unordered_map: the same answers for keys present and absent, across
// the growth from its first size, and for keys that collide in its low and high bits.

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

}  // namespace
}  // namespace terralod
