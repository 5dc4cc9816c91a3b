// The growth rules of docs/design.md#partition step by step on small hand-made graphs; expected parts worked
// out by hand in the comments.
#include <gtest/gtest.h>

#include <vector>

#include "core/error.hpp"
#include "graph/generate.hpp"
#include "partition/partition.hpp"

namespace rbpart {
namespace {

std::vector<int> parts(const ConstraintGraph& g, PartitionerKind kind, int nmax, double tau_mr = 10,
                       double tau_mix = 0.5) {
  PartitionParams p;
  p.partitioner = kind;
  p.nmax = nmax;
  p.tau_mr = tau_mr;
  p.tau_mix = tau_mix;
  Partition out;
  partition_graph(g, p, out);
  EXPECT_EQ(check_partition(g, out, nmax), "");
  return out.part_of;
}

// Seven bodies, weights in brackets:
//   0-1 [1], 1-2 [3], 1-3 [1], 2-3 [2], 3-4 [1], 2-5 [1], 4-6 [2], 5-6 [1]
// Degrees: 0:1  1:5  2:6  3:4  4:3  5:2  6:3.
ConstraintGraph seven() {
  return make_graph(7, {{0, 1, 1, 3}, {1, 2, 3, 9}, {1, 3, 1, 3}, {2, 3, 2, 6}, {3, 4, 1, 3}, {2, 5, 1, 3},
                        {4, 6, 2, 6}, {5, 6, 1, 3}});
}

TEST(GrowthRules, BfsTakesBreadthFirstOrderInBodyOrder) {
  // Seed 0; queue 1; 1 joins -> queue 2, 3; 2 joins -> queue 3, 5; 3 joins: 4 bodies, closed.
  // Seed 4 (lowest unassigned); queue 6; 6 joins -> queue 5; 5 joins.
  EXPECT_EQ(parts(seven(), PartitionerKind::Bfs, 4), (std::vector<int>{0, 0, 0, 0, 1, 1, 1}));
}

TEST(GrowthRules, MinDpTakesTheCandidateOfMinimumDegree) {
  // Seed 0 (degree 1); candidates {1:5} -> 1; {2:6, 3:4} -> 3; {2:6, 4:3} -> 4: closed at 4.
  // Seed: unassigned {2:6, 5:2, 6:3} -> 5; candidates {2:6, 6:3} -> 6; {2:6} -> 2.
  EXPECT_EQ(parts(seven(), PartitionerKind::MinDp, 4), (std::vector<int>{0, 0, 1, 0, 0, 1, 1}));
}

TEST(GrowthRules, MaxDpTakesTheCandidateOfMaximumDegree) {
  // Seed 2 (degree 6); candidates {1:5, 3:4, 5:2} -> 1; {0:1, 3:4, 5:2} -> 3; {0:1, 4:3, 5:2} -> 4.
  // Seed: unassigned {0:1, 5:2, 6:3} -> 6; candidates {5} -> 5; none left. Then seed 0 alone.
  EXPECT_EQ(parts(seven(), PartitionerKind::MaxDp, 4), (std::vector<int>{2, 0, 0, 0, 0, 1, 1}));
}

TEST(GrowthRules, MixSwitchesFromMinDegreeToMaximumGain) {
  // nmax 4, tau_mix 0.5: MinDP while |part| < 2, then gain = 2 C_in - degree.
  // Seed 0; {1} -> 1 (MinDP). |part| = 2: gains 2: 2*3-6 = 0, 3: 2*1-4 = -2 -> 2 (MinDP would take 3).
  // Gains 3: 2*(1+2)-4 = 2, 5: 2*1-2 = 0 -> 3. Closed at 4.
  // Seed 5 (degree 2); {6} -> 6 (MinDP); gain 4: 2*2-3 = 1 -> 4.
  EXPECT_EQ(parts(seven(), PartitionerKind::Mix, 4), (std::vector<int>{0, 0, 0, 0, 1, 1, 1}));
  // tau_mix 0.25: gains from |part| = 1 on. Seed 0; {1} -> 1 (its only candidate); then as above.
  EXPECT_EQ(parts(seven(), PartitionerKind::Mix, 4, 10, 0.25), (std::vector<int>{0, 0, 0, 0, 1, 1, 1}));
  // tau_mix 0.75: MinDP while |part| < 3. Seed 0; 1; {2:6, 3:4} -> 3 (MinDP); then gains
  // 2: 2*(3+2)-6 = 4, 4: 2*1-3 = -1 -> 2. Seed 5; 6 and then 4, both by MinDP.
  EXPECT_EQ(parts(seven(), PartitionerKind::Mix, 4, 10, 0.75), (std::vector<int>{0, 0, 0, 0, 1, 1, 1}));
}

TEST(GrowthRules, MixGainCountsConstraintsToEveryBodyOutsideThePart) {
  // A path 0-1-2 [1, 1] with a heavy side link 2-3 [5] and 1-4 [1], 4-5 [1]; nmax 3, tau_mix 0.1
  // (gain from the first step). Degrees 0:1 1:3 2:6 3:5 4:2 5:1.
  // Seed 0 (degree 1, lower index than 5); {1} -> 1; gains 2: 2*1-6 = -4, 4: 2*1-2 = 0 -> 4.
  // Seed 5 (degree 1); no candidate (4 taken). Seed 3 (degree 5); {2} -> 2.
  const ConstraintGraph g = make_graph(6, {{0, 1}, {1, 2}, {2, 3, 5, 15}, {1, 4}, {4, 5}});
  EXPECT_EQ(parts(g, PartitionerKind::Mix, 3, 10, 0.1), (std::vector<int>{0, 0, 2, 2, 0, 1}));
}

TEST(GrowthRules, MinDpBreaksTiesByLowestIndex) {
  // A 2x3 grid, unit weights: 0 1 2 / 3 4 5. Degrees: corners 2, middles 3.
  // Seed 0; candidates {1:3, 3:2} -> 3; {1:3, 4:3} -> 1 (tie, lower index). Closed at 3.
  // Seed 2 (corner, degree 2); {5:2} -> 5; {4:3} -> 4.
  EXPECT_EQ(parts(grid_graph(3, 2), PartitionerKind::MinDp, 3), (std::vector<int>{0, 0, 1, 0, 1, 1}));
}

TEST(GrowthRules, MrLetsAHeldBackLightBodyInOnceTheLightestMassFalls) {
  // Masses 0:100 1:5 2:20 3:1000 4:100 5:2; edges 0-1, 0-2, 0-3, 2-4, 1-5, 3-4; tau 10, nmax 5.
  // Seed 0, m_min 100, breadth-first order 1, 2, 3.
  //  1: 100/5 = 20 fails (held); 2: 100/20 = 5 -> joins, m_min 20; order 1, 3, 4.
  //  1: 20/5 = 4 -> joins, m_min 5; order 3, 4, 5.
  //  3: 1000/5 fails; 4: 100/5 = 20 fails; 5: 5/2 = 2.5 -> joins, m_min 2.  3, 4 fail: closed.
  // Seed 3: candidate 4: 1000/100 = 10, not < 10: closed. Seed 4 alone.
  const ConstraintGraph g =
      make_graph(6, {{0, 1}, {0, 2}, {0, 3}, {2, 4}, {1, 5}, {3, 4}}, {100, 5, 20, 1000, 100, 2});
  EXPECT_EQ(parts(g, PartitionerKind::Mr, 5), (std::vector<int>{0, 0, 0, 1, 2, 0}));
  // BFS ignores masses: 0, 1, 2, 3, 5 then 4.
  EXPECT_EQ(parts(g, PartitionerKind::Bfs, 5), (std::vector<int>{0, 0, 0, 0, 1, 0}));
  // tau 10.5: 3 may join 4 (ratio 10).
  EXPECT_EQ(parts(g, PartitionerKind::Mr, 5, 10.5), (std::vector<int>{0, 0, 0, 1, 1, 0}));
}

TEST(GrowthRules, MrComparesWithTheLightestBodyNotTheSeed) {
  // A path 0-1-2-3 with masses 10, 4, 30, 4, tau 5, nmax 3: 1 joins (10/4 = 2.5), m_min 4; then
  // 2: 30/4 = 7.5 fails although 30/10 = 3 would pass against the seed. Then {2} (30/4 fails), {3}.
  const ConstraintGraph g = make_graph(4, {{0, 1}, {1, 2}, {2, 3}}, {10, 4, 30, 4});
  EXPECT_EQ(parts(g, PartitionerKind::Mr, 3, 5), (std::vector<int>{0, 0, 1, 2}));
}

TEST(GrowthRules, IslandsOfAtMostNmaxAreOnePartWhateverTheRule) {
  // Island {0, 2, 4} (masses 1, 1000, 1) and island {1, 3} and isolated 5; nmax 3. MR would split
  // the first island by mass, but an island that fits is one sub-system (docs/design.md#graph).
  const ConstraintGraph g = make_graph(6, {{0, 2}, {2, 4}, {1, 3}}, {1, 1, 1000, 1, 1, 1});
  for (PartitionerKind kind : {PartitionerKind::Bfs, PartitionerKind::MinDp, PartitionerKind::MaxDp,
                               PartitionerKind::Mr, PartitionerKind::Mix, PartitionerKind::Metis})
    EXPECT_EQ(parts(g, kind, 3), (std::vector<int>{0, 1, 0, 1, 0, 2})) << partitioner_name(kind);
}

TEST(GrowthRules, NmaxOneGivesSingletonsInSeedOrder) {
  // Star with centre 0: MinDP seeds the leaves (degree 1) in index order, then the centre.
  EXPECT_EQ(parts(star_graph(3), PartitionerKind::MinDp, 1), (std::vector<int>{3, 0, 1, 2}));
  EXPECT_EQ(parts(star_graph(3), PartitionerKind::MaxDp, 1), (std::vector<int>{0, 1, 2, 3}));
}

TEST(GrowthRules, NoPartitionerOrBadNmaxIsAProgrammingError) {
  PartitionParams p;
  Partition out;
  EXPECT_THROW(partition_graph(seven(), p, out), std::invalid_argument);
  p.partitioner = PartitionerKind::Bfs;
  p.nmax = 0;
  EXPECT_THROW(partition_graph(seven(), p, out), std::invalid_argument);
}

}  // namespace
}  // namespace rbpart
