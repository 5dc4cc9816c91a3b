// The gain heap against an ordered set under random inserts, key changes and erasures.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <tuple>

#include "refine/gain_heap.hpp"

namespace rbpart {
namespace {

TEST(GainHeap, TopFollowsTheGainThenTieBreakOrder) {
  constexpr int kItems = 200;
  std::mt19937 rng(9);
  GainHeap heap;
  heap.reset(kItems);
  // The expected order: larger gain first, then smaller first, then smaller second, then item.
  using Entry = std::tuple<int, int, int, int>;  // (-gain, first, second, item)
  std::set<Entry> expected;
  std::vector<GainKey> key(kItems);
  std::vector<bool> held(kItems, false);
  for (int step = 0; step < 20000; ++step) {
    const int item = static_cast<int>(rng() % kItems);
    if (held[item]) expected.erase({-key[item].gain, key[item].first, key[item].second, item});
    if (rng() % 4 == 0) {
      heap.erase(item);
      held[item] = false;
    } else {
      // Few distinct gains and tie-breaks, so ties are common.
      key[item] = {static_cast<int>(rng() % 9) - 4, static_cast<int>(rng() % 5), item};
      heap.set(item, key[item]);
      held[item] = true;
      expected.insert({-key[item].gain, key[item].first, key[item].second, item});
    }
    ASSERT_EQ(heap.empty(), expected.empty());
    ASSERT_EQ(heap.contains(item), held[item]);
    if (!expected.empty()) ASSERT_EQ(heap.top(), std::get<3>(*expected.begin())) << "step " << step;
  }
  while (!expected.empty()) {
    ASSERT_EQ(heap.top(), std::get<3>(*expected.begin()));
    heap.erase(heap.top());
    expected.erase(expected.begin());
  }
  EXPECT_TRUE(heap.empty());
}

}  // namespace
}  // namespace rbpart
