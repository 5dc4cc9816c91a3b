// METIS as the min-cut reference (docs/design.md#partition): the obvious minimum cuts on small graphs, parts
// made connected and capped, and a lower cut than the growth partitioners on pile-like graphs.
#include <gtest/gtest.h>

#include <vector>

#include "graph/generate.hpp"
#include "partition/partition.hpp"

namespace rbpart {
namespace {

Partition metis(const ConstraintGraph& g, int nmax) {
  PartitionParams p;
  p.partitioner = PartitionerKind::Metis;
  p.nmax = nmax;
  Partition out;
  partition_graph(g, p, out);
  EXPECT_EQ(check_partition(g, out, nmax), "");
  return out;
}

TEST(Metis, FindsTheBridgeBetweenTwoCliques) {
  // Cliques {0..9} and {10..19} (unit weights) joined by one edge 4-15: the only cut of 1 into two
  // parts of at most 10 bodies.
  std::vector<GraphEdge> edges;
  for (int c = 0; c < 2; ++c)
    for (int a = 0; a < 10; ++a)
      for (int b = a + 1; b < 10; ++b) edges.push_back({10 * c + a, 10 * c + b});
  edges.push_back({4, 15});
  const ConstraintGraph g = make_graph(20, edges);
  const Partition p = metis(g, 10);
  EXPECT_EQ(p.part_count, 2);
  EXPECT_EQ(measure_partition(g, p).edge_cut, 1);
  for (int v = 0; v < 20; ++v) EXPECT_EQ(p.part_of[v], p.part_of[v < 10 ? 0 : 10]) << v;
}

TEST(Metis, CutsAHeavilyWeightedPathAtItsLightestEdges) {
  // A path of 8 whose edges weigh 9 except 2-3 and 5-6 (weight 1); nmax 3 forces three parts, and
  // {0,1,2} {3,4,5} {6,7} is the only partition into 3 connected parts cutting weight 2.
  std::vector<GraphEdge> edges;
  for (int v = 0; v + 1 < 8; ++v) edges.push_back({v, v + 1, (v == 2 || v == 5) ? 1 : 9, 3});
  const ConstraintGraph g = make_graph(8, edges);
  const Partition p = metis(g, 3);
  EXPECT_EQ(measure_partition(g, p).edge_cut, 2);
  EXPECT_EQ(p.part_of, (std::vector<int>{0, 0, 0, 1, 1, 1, 2, 2}));
}

TEST(Metis, BeatsTheGrowthPartitionersOnPiles) {
  for (int n : {500, 3000}) {
    const ConstraintGraph g = pile_graph(n, 7);
    for (int nmax : {8, 32}) {
      const PartitionQuality reference = measure_partition(g, metis(g, nmax));
      // Splitting the parts METIS overfills adds parts, but not many (measured: 1.26x at nmax 8).
      EXPECT_LE(reference.parts, 1.3 * ((n + nmax - 1) / nmax)) << n << " " << nmax;
      for (PartitionerKind kind : {PartitionerKind::Bfs, PartitionerKind::MinDp, PartitionerKind::MaxDp,
                                   PartitionerKind::Mix}) {
        PartitionParams p;
        p.partitioner = kind;
        p.nmax = nmax;
        Partition grown;
        partition_graph(g, p, grown);
        EXPECT_LT(reference.edge_cut, measure_partition(g, grown).edge_cut)
            << partitioner_name(kind) << " n " << n << " nmax " << nmax;
      }
    }
  }
}

TEST(Metis, EveryBodyAloneWithNmaxOne) {
  const ConstraintGraph g = clique_graph(6);
  const Partition p = metis(g, 1);
  EXPECT_EQ(p.part_of, (std::vector<int>{0, 1, 2, 3, 4, 5}));
}

}  // namespace
}  // namespace rbpart
