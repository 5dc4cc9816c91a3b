// KL and FM on hand-made graphs whose gains, moves and results are worked out by hand from the
// formulas of docs/design.md#refine: FM α = E − I, KL α = (E_i − I_i) + (E_j − I_j) − 2c.
#include <gtest/gtest.h>


#include "graph/generate.hpp"
#include "refine/reference.hpp"
#include "refine/refine_state.hpp"
#include "refine_testing.hpp"

namespace rbpart {
namespace {

int cut_of(const ConstraintGraph& g, const Partition& p) { return measure_partition(g, p).edge_cut; }

// Parts A = {0,1,2} (0-1:2, 1-2:1) and B = {3,4,5} (3-4:1, 4-5:1), joined by 2-3:3, 2-4:1, 0-3:1,
// 0-5:2. Cut 3+1+1+2 = 7.
ConstraintGraph two_triples() {
  return make_graph(6, {{0, 1, 2}, {1, 2, 1}, {3, 4, 1}, {4, 5, 1}, {2, 3, 3}, {2, 4, 1}, {0, 3, 1}, {0, 5, 2}});
}
const std::vector<int> kTriples{0, 0, 0, 1, 1, 1};

TEST(RefineGains, FmGainsMatchTheFormulaByHand) {
  const ConstraintGraph g = two_triples();
  Partition p = make_partition(kTriples);
  PartitionParams params;
  params.nmax = 6;
  RefineState s(g, params, p);
  EXPECT_EQ(s.cut(), 7);
  // node: E to the other part, I to its own -> α = E − I.
  // 0: E = 0-3 + 0-5 = 3, I = 0-1 = 2 -> +1.   1: no edge out of A.
  // 2: E = 3 + 1 = 4, I = 1 -> +3.             3: E = 3 + 1 = 4, I = 1 -> +3.
  // 4: E = 1, I = 1 + 1 = 2 -> -1.             5: E = 2, I = 1 -> +1.
  const int gain[6] = {1, 0, 3, 3, -1, 1};
  const int target[6] = {1, -1, 1, 0, 0, 0};
  const auto reference = refine_reference::best_moves(g, p.part_of, 2, 6);
  for (int v = 0; v < 6; ++v) {
    const BestMove m = s.best_move(v);
    EXPECT_EQ(m.target, target[v]) << "node " << v;
    if (target[v] >= 0) {
      EXPECT_EQ(m.gain, gain[v]) << "node " << v;
      ASSERT_TRUE(reference[v]) << "node " << v;
      EXPECT_EQ(reference[v]->gain, gain[v]) << "node " << v;
      EXPECT_EQ(reference[v]->second, target[v]) << "node " << v;
    } else {
      EXPECT_FALSE(reference[v]) << "node " << v;
    }
  }
  const Connections& c = s.connections(2);
  EXPECT_EQ(c.internal, 1);
  ASSERT_EQ(c.external.size(), 1u);
  EXPECT_EQ(c.external[0], std::make_pair(1, WeightSum{4}));
}

TEST(RefineGains, FullPartsAreNoTarget) {
  const ConstraintGraph g = two_triples();
  Partition p = make_partition(kTriples);
  PartitionParams params;
  params.nmax = 3;  // both parts full
  RefineState s(g, params, p);
  for (int v = 0; v < 6; ++v) EXPECT_EQ(s.best_move(v).target, -1) << "node " << v;
  EXPECT_EQ(refined(g, make_partition(kTriples), RefinerKind::Fm, 3).part_of, kTriples);
}

TEST(RefineGains, KlPairGainsByHandAndTheChosenSwap) {
  const ConstraintGraph g = two_triples();
  // D toward the other part: A: 0 -> 3-2 = +1, 2 -> 4-1 = +3; B: 3 -> 4-1 = +3, 4 -> 1-2 = -1,
  // 5 -> 2-1 = +1. Pairs: (2,3) 3+3-2·3 = 0 (the largest D's, but joined by c = 3), (2,5) 3+1 = 4,
  // (0,3) 1+3-2·1 = 2, (0,4) 0, (0,5) 1+1-2·2 = -2, (2,4) 3-1-2·1 = 0.
  const auto swaps = refine_reference::best_swaps(g, kTriples, 2);
  ASSERT_EQ(swaps.size(), 1u);
  const GainKey best = swaps.at({0, 1});
  EXPECT_EQ(best.gain, 4);
  EXPECT_EQ(best.first, 2);
  EXPECT_EQ(best.second, 5);
  // The swap 2 <-> 5 leaves A' = {0,1,5}, B' = {2,3,4}: cut 7 - 4 = 3, after which every D is
  // negative, so KL stops. Swaps keep sizes: full parts do not matter.
  for (int nmax : {3, 6}) {
    const Partition out = refined(g, make_partition(kTriples), RefinerKind::Kl, nmax);
    EXPECT_EQ(out.part_of, (std::vector<int>{0, 0, 1, 1, 1, 0})) << "nmax " << nmax;
    EXPECT_EQ(cut_of(g, out), 3);
  }
}

TEST(RefineGains, GreedyFmSequenceByHand) {
  const ConstraintGraph g = two_triples();
  // nmax 6: 2 and 3 tie at +3, the lower index moves: 2 -> B (cut 4). Then 0 (+1: E = 0-3 + 0-5 = 3,
  // I = 2) and 5 (+1) tie: 0 -> B (cut 3). Node 1 would gain +3 but would empty A; all else <= 0.
  Partition out = refined(g, make_partition(kTriples), RefinerKind::Fm, 6);
  EXPECT_EQ(out.part_of, (std::vector<int>{1, 0, 1, 1, 1, 1}));
  EXPECT_EQ(cut_of(g, out), 3);
  // nmax 4: after 2 -> B, B is full so 0 has no target; 5 (+1) -> A (cut 3), then nothing positive.
  out = refined(g, make_partition(kTriples), RefinerKind::Fm, 4);
  EXPECT_EQ(out.part_of, (std::vector<int>{0, 0, 1, 1, 1, 0}));
  EXPECT_EQ(cut_of(g, out), 3);
}

TEST(RefineLegality, FmRefusesToDisconnectAPart) {
  // A = path 0-1-2, B = 3-4-5 (weights 5), 1-3 weight 5: moving 1 gains 5 - 2 = +3 but splits A.
  std::vector<GraphEdge> edges{{0, 1, 1}, {1, 2, 1}, {3, 4, 5}, {4, 5, 5}, {1, 3, 5}};
  const std::vector<int> start{0, 0, 0, 1, 1, 1};
  EXPECT_EQ(refined(make_graph(6, edges), make_partition(start), RefinerKind::Fm, 10).part_of, start);
  EXPECT_EQ(refined(make_graph(6, edges), make_partition(start), RefinerKind::FmRollback, 10).part_of, start);
  // Closing A into a triangle makes the same move legal: cut 5 -> 2.
  edges.push_back({0, 2, 1});
  const ConstraintGraph triangle = make_graph(6, edges);
  const Partition out = refined(triangle, make_partition(start), RefinerKind::Fm, 10);
  EXPECT_EQ(out.part_of, (std::vector<int>{0, 1, 0, 1, 1, 1}));
  EXPECT_EQ(cut_of(triangle, out), 2);
}

TEST(RefineLegality, FmRefusesToEmptyAPart) {
  // A = {0}, B = {1,2}; 0-1:3, 1-2:1. Node 0 (+3) would empty A; node 1 (+2) moves instead, after
  // which node 2 (+1) would empty B.
  const ConstraintGraph g = make_graph(3, {{0, 1, 3}, {1, 2, 1}});
  const Partition out = refined(g, make_partition({0, 1, 1}), RefinerKind::Fm, 3);
  EXPECT_EQ(out.part_of, (std::vector<int>{0, 0, 1}));
  EXPECT_EQ(out.part_count, 2);
  EXPECT_EQ(cut_of(g, out), 1);
}

TEST(RefineLegality, FmRefusesToOverfillAPart) {
  // A = {0,1}, B = {2,3}; 1-2:5. Nodes 1 and 2 gain 5 - 1 = +4, but with nmax 2 both parts are full.
  const ConstraintGraph g = make_graph(4, {{0, 1, 1}, {1, 2, 5}, {2, 3, 1}});
  const std::vector<int> start{0, 0, 1, 1};
  EXPECT_EQ(refined(g, make_partition(start), RefinerKind::Fm, 2).part_of, start);
  EXPECT_EQ(refined(g, make_partition(start), RefinerKind::FmRollback, 2).part_of, start);
  // nmax 3: node 1 (the lower of the tie) joins B, which is then full.
  EXPECT_EQ(refined(g, make_partition(start), RefinerKind::Fm, 3).part_of, (std::vector<int>{0, 1, 1, 1}));
}

TEST(RefineLegality, KlRefusesASwapThatDisconnects) {
  // A = path 0-1-2, B = path 3-4-5 (unit weights); 1-3:3, 1-5:3, 0-4:3. D: 1 -> 6-2 = 4, 4 -> 3-2 = 1,
  // 0 -> 3-1 = 2, 3 -> 3-1 = 2, 5 -> 2. The best gain, 1 <-> 4 (5), leaves 2 alone in {0,2,4}; the
  // best legal swap is 0 <-> 3 (2+2 = 4, before 0 <-> 5 by node index): cut 9 -> 5, then none.
  const ConstraintGraph g = make_graph(6, {{0, 1, 1}, {1, 2, 1}, {3, 4, 1}, {4, 5, 1}, {1, 3, 3}, {1, 5, 3}, {0, 4, 3}});
  const Partition out = refined(g, make_partition({0, 0, 0, 1, 1, 1}), RefinerKind::Kl, 3);
  EXPECT_EQ(out.part_of, (std::vector<int>{1, 0, 0, 0, 1, 1}));
  EXPECT_EQ(cut_of(g, out), 5);
}

TEST(RefineLegality, KlSwapMayReplaceAnArticulationPoint) {
  // A = path 0-1-2, B = path 3-4-5; 1-3:2, 1-5:2, 4-0:2, 4-2:2. Swapping the two middles (gain
  // 2+2 = 4) removes A's articulation point 1, but 4 joins 0 and 2 again: legal, cut 8 -> 4.
  const ConstraintGraph g = make_graph(6, {{0, 1, 1}, {1, 2, 1}, {3, 4, 1}, {4, 5, 1}, {1, 3, 2}, {1, 5, 2}, {0, 4, 2}, {2, 4, 2}});
  const Partition out = refined(g, make_partition({0, 0, 0, 1, 1, 1}), RefinerKind::Kl, 3);
  EXPECT_EQ(out.part_of, (std::vector<int>{0, 1, 0, 1, 0, 1}));
  EXPECT_EQ(cut_of(g, out), 4);
}

TEST(RefineRollback, LeavesALocalMinimumThatGreedyRulesCannot) {
  // A = triangle 0-1:1, 0-2:1, 1-2:3; B = {3,4} with 3-4:5; 1-3:2, 2-4:2. Cut 4. Every single move
  // and every swap has negative gain (1, 2: 2-4 = -2; 3, 4: 2-5 = -3), so greedy FM and KL stop.
  // Classic FM: 1 -> B (-2, cut 6), then 2 -> B (+4: E = 3+2, I = 1; cut 2), then 0 may not leave;
  // the best prefix is both moves. The next pass finds no better prefix.
  const ConstraintGraph g = make_graph(5, {{0, 1, 1}, {0, 2, 1}, {1, 2, 3}, {3, 4, 5}, {1, 3, 2}, {2, 4, 2}});
  const std::vector<int> start{0, 0, 0, 1, 1};
  EXPECT_EQ(refined(g, make_partition(start), RefinerKind::Fm, 5).part_of, start);
  EXPECT_EQ(refined(g, make_partition(start), RefinerKind::Kl, 5).part_of, start);
  const Partition out = refined(g, make_partition(start), RefinerKind::FmRollback, 5);
  EXPECT_EQ(out.part_of, (std::vector<int>{0, 1, 1, 1, 1}));
  EXPECT_EQ(cut_of(g, out), 2);
  // nmax 3: 2 cannot follow 1 into the full B; the pass's moves never get below cut 4: rolled back.
  EXPECT_EQ(refined(g, make_partition(start), RefinerKind::FmRollback, 3).part_of, start);
}

}  // namespace
}  // namespace rbpart
