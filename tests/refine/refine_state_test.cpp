// RefineState's bookkeeping: articulation points, the legality of moves and swaps and the
// constraints per part, against breadth-first searches and sums over edges from scratch.
#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

#include "core/validate.hpp"
#include "graph/generate.hpp"
#include "refine/reference.hpp"
#include "refine/refine_state.hpp"
#include "refine_testing.hpp"

namespace rbpart {
namespace {

TEST(RefineState, ArticulationPointsByHand) {
  // Part 0 = path 0-1-2-3 plus the pendant 4 on 2; part 1 = cycle 5-6-7-8; part 2 = {9}.
  const ConstraintGraph g = make_graph(10, {{0, 1}, {1, 2}, {2, 3}, {2, 4}, {5, 6}, {6, 7}, {7, 8}, {8, 5}, {3, 5}, {8, 9}});
  Partition p = make_partition({0, 0, 0, 0, 0, 1, 1, 1, 1, 2});
  PartitionParams params;
  RefineState s(g, params, p);
  const bool can_leave[10] = {true, false, false, true, true, true, true, true, true, false};
  for (int v = 0; v < 10; ++v) EXPECT_EQ(s.can_leave(v), can_leave[v]) << "node " << v;
  // After 3 leaves for part 1, node 2 is still the cut vertex between {0,1} and {4}.
  s.move(3, 1);
  EXPECT_FALSE(s.can_leave(2));
  EXPECT_TRUE(s.can_leave(4));
  EXPECT_FALSE(s.can_leave(5));  // 3 hangs on 5 now
}

TEST(RefineState, RejectsAPartitionOfAnotherGraph) {
  const ConstraintGraph g = make_graph(3, {{0, 1}, {1, 2}});
  PartitionParams params;
  params.refiner = RefinerKind::Fm;
  Partition wrong_size = make_partition({0, 0});
  EXPECT_THROW(refine_partition(g, params, wrong_size), std::invalid_argument);
  Partition bad_id = make_partition({0, 0, 1});
  bad_id.part_count = 1;
  EXPECT_THROW(refine_partition(g, params, bad_id), std::invalid_argument);
  params.refiner = RefinerKind::None;
  Partition untouched = make_partition({0, 1, 2});
  refine_partition(g, params, untouched);
  EXPECT_EQ(untouched.part_of, (std::vector<int>{0, 1, 2}));
}

TEST(RefineState, DebugChecksRejectAnInvalidInput) {
  // Part 0 = {0, 2} is not connected: the debug checks refuse to start.
  const ConstraintGraph g = make_graph(3, {{0, 1}, {1, 2}});
  EXPECT_THROW(refined(g, make_partition({0, 1, 0}), RefinerKind::Fm, 3, true), std::logic_error);
}

// The from-scratch check names bookkeeping that drifted from the partition: a cut not kept, then a
// move that breaks a part.
TEST(RefineState, ViolationNamesWhatDrifted) {
  // Path 0-1-2-3, parts {0, 1} and {2, 3}: cut 1.
  const ConstraintGraph g = make_graph(4, {{0, 1}, {1, 2}, {2, 3}});
  Partition p = make_partition({0, 0, 1, 1});
  PartitionParams params;
  RefineState s(g, params, p);
  EXPECT_EQ(s.violation(), "");
  s.add_to_cut(1);
  EXPECT_EQ(s.violation(), "tracked edge cut 2, recomputed 1");
  s.add_to_cut(-1);
  s.move(3, 0);  // parts {0, 1, 3} and {2}: cut 2, part 0 in two pieces
  EXPECT_EQ(s.violation(), "tracked edge cut 1, recomputed 2");
  s.add_to_cut(1);
  EXPECT_EQ(s.violation(), "part 0 is not connected: node 3 is not reached from node 0");
  EXPECT_THROW(s.check("test"), std::logic_error);
}

// How often the refiners re-check: every move with debug_checks; in validate builds every move up to
// kValidateMoveNodes nodes and every pass beyond; never otherwise.
TEST(RefineState, CheckFrequency) {
  PartitionParams params;
  for (const int n : {1, RefineState::kValidateMoveNodes, RefineState::kValidateMoveNodes + 1}) {
    SCOPED_TRACE(n);
    const ConstraintGraph g = make_graph(n, {});
    std::vector<int> part_of(n);
    for (int v = 0; v < n; ++v) part_of[v] = v;
    Partition p = make_partition(part_of);
    params.debug_checks = false;
    RefineState s(g, params, p);
    EXPECT_EQ(s.check_passes(), kValidate);
    EXPECT_EQ(s.check_moves(), kValidate && n <= RefineState::kValidateMoveNodes);
    params.debug_checks = true;
    s.reset(g, params, p);
    EXPECT_TRUE(s.check_passes());
    EXPECT_TRUE(s.check_moves());
  }
}

// Random connected partitions of generated graphs, then random legal moves: after each, every
// node's may-leave answer, every sampled swap's connectivity answer and every node's constraints to
// its own part agree with the references.
TEST(RefineState, LegalityAndInternalConstraintsMatchBreadthFirstSearch) {
  const auto suite = graph_suite(110, 53);
  std::mt19937 rng(8);
  for (const GeneratedGraph& gg : suite) {
    const ConstraintGraph& g = gg.graph;
    if (g.node_count() == 0) continue;
    SCOPED_TRACE(gg.name);
    Partition p = random_connected_partition(g, 2 + static_cast<int>(rng() % 12), rng);
    PartitionParams params;
    params.nmax = g.node_count();
    RefineState s(g, params, p);
    for (int round = 0; round < 6; ++round) {
      for (int v = 0; v < g.node_count(); ++v) {
        ASSERT_EQ(s.can_leave(v), refine_reference::can_leave(g, p.part_of, v)) << "node " << v;
        ASSERT_EQ(s.internal(v), refine_reference::connection(g, p.part_of, v, p.part_of[v])) << "node " << v;
      }
      // Swaps of a member `out` of part q for a neighbour `in` of q from another part.
      for (int trial = 0; trial < 40; ++trial) {
        const int in = static_cast<int>(rng() % g.node_count());
        if (g.offset[in] == g.offset[in + 1]) continue;
        const int q = p.part_of[g.adjacency[g.offset[in] + rng() % (g.offset[in + 1] - g.offset[in])]];
        if (q == p.part_of[in]) continue;
        std::vector<int> members;
        for (int v = 0; v < g.node_count(); ++v)
          if (p.part_of[v] == q) members.push_back(v);
        const int out = members[rng() % members.size()];
        ASSERT_EQ(s.swap_keeps_connected(q, out, in), refine_reference::connected(g, p.part_of, q, out, in))
            << "part " << q << " out " << out << " in " << in;
      }
      // A few legal moves to neighbouring parts, so that the lazily recomputed answers are exercised.
      for (int moves = 0; moves < 5; ++moves) {
        const int v = static_cast<int>(rng() % g.node_count());
        const BestMove m = s.best_move(v);
        if (m.target >= 0 && s.can_leave(v)) s.move(v, m.target);
      }
    }
  }
}

}  // namespace
}  // namespace rbpart
