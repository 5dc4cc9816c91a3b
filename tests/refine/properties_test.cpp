// Refinement over hundreds of generated graphs (piles, geometric graphs, grids, folded chains, stars,
// cliques, islands, isolated nodes, one node, none), from every partitioner and from random
// connected partitions: the partition keeps every property of docs/design.md#partition, the cut never rises,
// the result is deterministic, and the refiner stopped where its rule says (checked from scratch).
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "graph/generate.hpp"
#include "refine/reference.hpp"
#include "refine_testing.hpp"

namespace rbpart {
namespace {

constexpr RefinerKind kRefiners[] = {RefinerKind::Kl, RefinerKind::Fm, RefinerKind::FmRollback};
constexpr PartitionerKind kPartitioners[] = {PartitionerKind::Bfs, PartitionerKind::MinDp, PartitionerKind::MaxDp,
                                             PartitionerKind::Mr,  PartitionerKind::Mix,   PartitionerKind::Metis};
constexpr int kNmax[] = {2, 3, 5, 8, 16, 32};

// The refiner's stopping rule, recomputed from scratch: KL stops when no legal swap has positive
// gain; FM when no legal move has; classic FM too, since a last pass whose best move gained would
// have kept that move.
std::string stopping_rule_violation(const ConstraintGraph& g, const Partition& p, RefinerKind refiner, int nmax) {
  if (refiner == RefinerKind::Kl) {
    const auto swaps = refine_reference::best_swaps(g, p.part_of, p.part_count);
    if (swaps.empty()) return "";
    const GainKey& s = swaps.begin()->second;
    return "swap " + std::to_string(s.first) + "<->" + std::to_string(s.second) + " still gains " + std::to_string(s.gain);
  }
  const auto moves = refine_reference::best_moves(g, p.part_of, p.part_count, nmax);
  for (int v = 0; v < g.node_count(); ++v)
    if (moves[v] && moves[v]->gain > 0 && refine_reference::can_leave(g, p.part_of, v))
      return "node " + std::to_string(v) + " still gains " + std::to_string(moves[v]->gain) + " moving to part " +
             std::to_string(moves[v]->second);
  return "";
}

void expect_good_refinement(const ConstraintGraph& g, const Partition& start, RefinerKind refiner, int nmax,
                            bool debug_checks) {
  SCOPED_TRACE(std::string("refiner ") + refiner_name(refiner) + ", nmax " + std::to_string(nmax));
  ASSERT_EQ(check_partition(g, start, nmax), "") << "bad starting partition";
  const Partition out = refined(g, start, refiner, nmax, debug_checks);
  EXPECT_EQ(check_partition(g, out, nmax), "");
  EXPECT_EQ(out.part_count, start.part_count);
  EXPECT_LE(measure_partition(g, out).edge_cut, measure_partition(g, start).edge_cut);
  EXPECT_EQ(stopping_rule_violation(g, out, refiner, nmax), "");
}

TEST(RefineProperties, FromEveryPartitionerOnGeneratedGraphs) {
  const auto suite = graph_suite(330, 17);
  for (std::size_t i = 0; i < suite.size(); ++i) {
    SCOPED_TRACE(suite[i].name);
    PartitionParams params;
    params.nmax = kNmax[i % std::size(kNmax)];
    for (PartitionerKind partitioner : kPartitioners) {
      SCOPED_TRACE(partitioner_name(partitioner));
      params.partitioner = partitioner;
      Partition start;
      partition_graph(suite[i].graph, params, start);
      for (RefinerKind refiner : kRefiners) expect_good_refinement(suite[i].graph, start, refiner, params.nmax, false);
    }
  }
}

TEST(RefineProperties, FromRandomConnectedPartitions) {
  const auto suite = graph_suite(220, 29);
  std::mt19937 rng(3);
  for (std::size_t i = 0; i < suite.size(); ++i) {
    SCOPED_TRACE(suite[i].name);
    for (int trial = 0; trial < 3; ++trial) {
      const int nmax = kNmax[(i + trial) % std::size(kNmax)];
      const Partition start = random_connected_partition(suite[i].graph, nmax, rng);
      for (RefinerKind refiner : kRefiners) expect_good_refinement(suite[i].graph, start, refiner, nmax, false);
    }
  }
}

// params.debug_checks recompute every gain and the cut from scratch after every move and throw on a
// mismatch: the incremental bookkeeping (gain heap, parking, KL's part-pair caches, articulation
// points) agrees with the references at every step.
TEST(RefineProperties, IncrementalGainsAgreeWithRecomputationAtEveryMove) {
  const auto suite = graph_suite(88, 41);
  std::mt19937 rng(5);
  for (std::size_t i = 0; i < suite.size(); ++i) {
    const ConstraintGraph& g = suite[i].graph;
    if (g.node_count() > 150) continue;
    SCOPED_TRACE(suite[i].name);
    PartitionParams params;
    params.nmax = kNmax[i % std::size(kNmax)];
    params.partitioner = PartitionerKind::MinDp;
    Partition from_min_dp;
    partition_graph(g, params, from_min_dp);
    const Partition random = random_connected_partition(g, params.nmax, rng);
    for (RefinerKind refiner : kRefiners)
      for (const Partition& start : {from_min_dp, random})
        EXPECT_NO_THROW(expect_good_refinement(g, start, refiner, params.nmax, true));
  }
}

// The same input gives the same output, also after refining other graphs in between (the
// refiners keep their buffers across calls).
TEST(RefineProperties, Deterministic) {
  const auto suite = graph_suite(66, 61);
  std::mt19937 rng(13);
  std::vector<Partition> start, first;
  for (std::size_t i = 0; i < suite.size(); ++i)
    start.push_back(random_connected_partition(suite[i].graph, kNmax[i % std::size(kNmax)], rng));
  for (RefinerKind refiner : kRefiners) {
    first.clear();
    for (std::size_t i = 0; i < suite.size(); ++i)
      first.push_back(refined(suite[i].graph, start[i], refiner, kNmax[i % std::size(kNmax)], false));
    for (std::size_t i = suite.size(); i-- > 0;)
      EXPECT_EQ(refined(suite[i].graph, start[i], refiner, kNmax[i % std::size(kNmax)], false).part_of,
                first[i].part_of)
          << suite[i].name << ", refiner " << refiner_name(refiner);
  }
}

TEST(RefineProperties, LargePileFromMinDpAndMix) {
  const ConstraintGraph g = pile_graph(4000, 11);
  for (PartitionerKind partitioner : {PartitionerKind::MinDp, PartitionerKind::Mix}) {
    PartitionParams params;
    params.partitioner = partitioner;
    params.nmax = 24;
    Partition start;
    partition_graph(g, params, start);
    const int cut = measure_partition(g, start).edge_cut;
    for (RefinerKind refiner : kRefiners) {
      SCOPED_TRACE(std::string(partitioner_name(partitioner)) + " + " + refiner_name(refiner));
      const Partition out = refined(g, start, refiner, params.nmax, false);
      EXPECT_EQ(check_partition(g, out, params.nmax), "");
      // Greedy partitions of a pile leave many improving moves: refinement must find some.
      EXPECT_LT(measure_partition(g, out).edge_cut, cut);
      EXPECT_EQ(refined(g, start, refiner, params.nmax, false).part_of, out.part_of) << "not deterministic";
    }
  }
}

}  // namespace
}  // namespace rbpart
