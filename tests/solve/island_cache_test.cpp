// The Newton solver's per-island state kept across steps (solve/island_cache.hpp): slots follow an
// island's first body, and a backend assigned again - to the same pattern, keeping its analysis, or
// to another - still solves every piece as a dense LU of its equations does.
#include "solve/island_cache.hpp"
#include "solve/box_scenes.hpp"
#include "solve/random_piece.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <random>

namespace rbpart {
namespace {

using namespace rbpart::testing;

Islands islands_of(const std::vector<std::vector<int>>& bodies) {
  Islands islands;
  for (const std::vector<int>& island : bodies) {
    islands.bodies.insert(islands.bodies.end(), island.begin(), island.end());
    islands.body_offset.push_back(static_cast<int>(islands.bodies.size()));
    islands.row_offset.push_back(0);
  }
  return islands;
}

TEST(IslandCache, AnIslandKeepsTheSlotOfItsFirstBody) {
  DirectCache cache;
  const std::vector<IslandSlot<MonolithicSystem>*> first = cache.slots_for(islands_of({{3, 5}, {7}}));
  ASSERT_EQ(first.size(), 2u);
  EXPECT_NE(first[0], first[1]);
  const std::vector<IslandSlot<MonolithicSystem>*> second = cache.slots_for(islands_of({{1}, {7, 8}, {3}}));
  ASSERT_EQ(second.size(), 3u);
  EXPECT_EQ(second[1], first[1]);  // body 7 still first: the same slot
  EXPECT_EQ(second[2], first[0]);  // body 3 lost body 5: the same slot, its pattern to be rebuilt
  EXPECT_NE(second[0], first[0]);
  EXPECT_NE(second[0], first[1]);
}

// Three boxes on the ground, masses 1 : m : 1, the top two sliding.
Scene stack(double middle_mass, int boxes) {
  Scene s;
  add_box_on(s, -1, 1.0, 0.5, 0.0, 0.5);
  if (boxes > 1) add_box_on(s, 0, middle_mass, 0.5, 0.3, 0.4);
  if (boxes > 2) add_box_on(s, 1, 1.0, 0.5, -0.2, 0.6, 0.1, 0.5);
  finish(s);
  return s;
}

TEST(IslandCache, ABackendAssignedAgainSolvesLikeADenseSolve) {
  std::mt19937 rng(11);
  MonolithicSystem system;  // one backend, as a slot keeps it from step to step
  // The same pattern with other values (the kept analysis),
  // then other patterns (fewer bodies), then the first again.
  const Scene scenes[] = {stack(1000, 3), stack(10, 3), stack(1e4, 3), stack(100, 2), stack(1, 3)};
  for (const Scene& scene : scenes) {
    const std::vector<int> local = local_row_index(scene.rows, scene.islands);
    IslandSystem s;
    s.gather(scene.rows, scene.bodies, scene.islands, 0, local);
    system.assign(s);
    for (bool ties : {false, true, true}) {
      const Piece piece = random_piece(s, rng, ties);
      ASSERT_TRUE(system.factor(piece));
      const Eigen::VectorXd g = Eigen::VectorXd::Random(s.rows);
      Eigen::VectorXd x;
      system.solve(g, x);
      const Eigen::VectorXd reference = piece_matrix(s, piece).partialPivLu().solve(g);
      EXPECT_LE((x - reference).norm(), 1e-6 * reference.norm()) << s.bodies << " bodies, ties " << ties;
    }
  }
}

}  // namespace
}  // namespace rbpart
