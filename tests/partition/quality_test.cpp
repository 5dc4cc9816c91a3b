// measure_partition against hand-counted cuts, check_partition and check_island_partition against
// each violation they must name, and the partitioner and refiner names.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "core/error.hpp"
#include "graph/generate.hpp"
#include "partition/partition.hpp"

namespace rbpart {
namespace {

// A ring 0-1-2-3-4-0; (weight, rows): 0-1 (2, 5), 1-2 (1, 4), 2-3 (3, 7), 3-4 (1, 1), 4-0 (1, 2).
ConstraintGraph ring() { return make_graph(5, {{0, 1, 2, 5}, {1, 2, 1, 4}, {2, 3, 3, 7}, {3, 4, 1, 1}, {0, 4, 1, 2}}); }

TEST(MeasurePartition, HandCountedCutRowsAndBodies) {
  // Parts {0, 1, 2} and {3, 4}: cut edges 2-3 (3, 7) and 4-0 (1, 2); node 1 is inside.
  const PartitionQuality q = measure_partition(ring(), Partition{{0, 0, 0, 1, 1}, 2});
  EXPECT_EQ(q.parts, 2);
  EXPECT_EQ(q.min_bodies, 2);
  EXPECT_EQ(q.max_bodies, 3);
  EXPECT_DOUBLE_EQ(q.mean_bodies, 2.5);
  EXPECT_EQ(q.edge_cut, 4);
  EXPECT_EQ(q.interface_rows, 9);
  EXPECT_EQ(q.interface_bodies, 4);
  EXPECT_EQ(q.partition_ms, 0);
  EXPECT_EQ(q.refine_ms, 0);
}

TEST(MeasurePartition, SingletonsCutEveryEdgeAndOnePartCutsNone) {
  const PartitionQuality all = measure_partition(ring(), Partition{{0, 1, 2, 3, 4}, 5});
  EXPECT_EQ(all.edge_cut, 2 + 1 + 3 + 1 + 1);
  EXPECT_EQ(all.interface_rows, 5 + 4 + 7 + 1 + 2);
  EXPECT_EQ(all.interface_bodies, 5);
  const PartitionQuality one = measure_partition(ring(), Partition{{0, 0, 0, 0, 0}, 1});
  EXPECT_EQ(one.edge_cut, 0);
  EXPECT_EQ(one.interface_rows, 0);
  EXPECT_EQ(one.interface_bodies, 0);
  EXPECT_EQ(one.min_bodies, 5);
  const PartitionQuality empty = measure_partition(make_graph(0, {}), Partition{});
  EXPECT_EQ(empty.parts, 0);
  EXPECT_EQ(empty.max_bodies, 0);
  EXPECT_EQ(empty.mean_bodies, 0);
}

// A METIS file's edge weights reach 2^31 - 1: two cut edges of that weight read as a cut of -2 in
// 32-bit sums (issue #26).
TEST(MeasurePartition, SumsWeightsBeyondTheIntRange) {
  const int big = std::numeric_limits<int>::max();
  const ConstraintGraph g = make_graph(3, {{0, 1, big, big}, {1, 2, big, big}});
  const PartitionQuality q = measure_partition(g, Partition{{0, 1, 2}, 3});
  EXPECT_EQ(q.edge_cut, 2 * WeightSum{big});
  EXPECT_EQ(q.interface_rows, 2 * WeightSum{big});
  EXPECT_EQ(g.degree(1), 2 * WeightSum{big});
}

void expect_violation(const Partition& p, int nmax, const std::string& words) {
  const std::string message = check_partition(ring(), p, nmax);
  EXPECT_NE(message.find(words), std::string::npos) << "'" << message << "' lacks '" << words << "'";
}

TEST(CheckPartition, NamesEachViolation) {
  EXPECT_EQ(check_partition(ring(), Partition{{0, 0, 0, 1, 1}, 2}, 3), "");
  expect_violation(Partition{{0, 0, 0, 1}, 2}, 3, "4 entries for 5 nodes");
  expect_violation(Partition{{0, 0, 0, 1, 2}, 2}, 3, "node 4 has part id 2, outside 0..1");
  expect_violation(Partition{{-1, 0, 0, 1, 1}, 2}, 3, "node 0 has part id -1");
  expect_violation(Partition{{0, 0, 0, 2, 2}, 3}, 3, "part 1 is empty");
  expect_violation(Partition{{0, 0, 0, 1, 1}, 2}, 2, "part 0 has 3 bodies, more than nmax 2");
  expect_violation(Partition{{0, 1, 0, 1, 1}, 2}, 3, "part 0 is not connected: node 2 is not reached from node 0");
  expect_violation(Partition{{0, 0, 1, 2, 1}, 3}, 3, "part 1 is not connected: node 4 is not reached from node 2");
  EXPECT_EQ(check_partition(make_graph(0, {}), Partition{}, 1), "");
}

TEST(CheckIslandPartition, NamesEachViolation) {
  // The ring's island {0..4} and the island {5, 6}.
  const ConstraintGraph g = make_graph(7, {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {0, 4}, {5, 6}});
  auto violation = [&](std::vector<int> part_of, int parts) { return check_island_partition(g, Partition{part_of, parts}); };
  EXPECT_EQ(violation({0, 0, 0, 0, 0, 1, 1}, 2), "");
  EXPECT_EQ(violation({0, 0, 0, 1, 1, 2, 2}, 3), "edge 0-4 joins parts 0 and 1 of one island");
  EXPECT_EQ(violation({0, 0, 0, 0, 0, 0, 0}, 1), "part 0 is not connected: node 5 is not reached from node 0");
  EXPECT_EQ(violation({1, 1, 1, 1, 1, 0, 0}, 2), "node 0 is the lowest of part 1, met before part 0");
  EXPECT_EQ(violation({0, 0, 0, 0, 0, 1}, 2), "part_of has 6 entries for 7 nodes");
}

TEST(PartitionNames, RoundTripAndUnknownNamesListTheChoices) {
  for (PartitionerKind k : {PartitionerKind::None, PartitionerKind::Bfs, PartitionerKind::MinDp, PartitionerKind::MaxDp,
                            PartitionerKind::Mr, PartitionerKind::Mix, PartitionerKind::Metis})
    EXPECT_EQ(parse_partitioner(partitioner_name(k)), k);
  for (RefinerKind k : {RefinerKind::None, RefinerKind::Kl, RefinerKind::Fm, RefinerKind::FmRollback})
    EXPECT_EQ(parse_refiner(refiner_name(k)), k);
  EXPECT_STREQ(partitioner_name(PartitionerKind::MinDp), "mindp");
  EXPECT_STREQ(refiner_name(RefinerKind::FmRollback), "fm-rollback");
  try {
    parse_partitioner("kway");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "unknown partitioner 'kway' (choose one of none, bfs, mindp, maxdp, mr, mix, metis)");
  }
  try {
    parse_refiner("FM");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "unknown refiner 'FM' (choose one of none, kl, fm, fm-rollback)");
  }
}

}  // namespace
}  // namespace rbpart
