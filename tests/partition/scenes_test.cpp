// The scenes' constraint graphs (docs/design.md#partition: properties "checked in tests on every scene"):
// small versions of the paper's scenes stepped until contacts form, their graphs partitioned by
// every method; and the World's partition and refine stages (stats from measure_partition).
#include <gtest/gtest.h>

#include <rbpart/world.hpp>

#include <string>
#include <utility>
#include <vector>

#include "graph/constraint_graph.hpp"
#include "partition/partition.hpp"
#include "reference.hpp"
#include "scenes/scenes.hpp"
#include "step/world_internals.hpp"

namespace rbpart {
namespace {

struct SceneCase {
  const char* name;
  std::vector<std::pair<std::string, std::string>> sets;
  int steps;
  int min_edges;  // the settled graph has at least this many edges (contacts have formed)
};

// PGS keeps the stepping fast; the partitioners only need the contact graph.
const std::vector<SceneCase> kScenes = {
    {"rock_pile", {{"rocks", "60"}}, 120, 40},
    {"large_rock_pile", {{"rocks", "60"}}, 120, 40},
    {"chain_drop", {{"links", "40"}}, 150, 39},
    {"log_tower", {{"layers", "8"}}, 3, 40},
};

SolverParams pgs() {
  SolverParams s;
  s.kind = SolverKind::Pgs;
  return s;
}

TEST(SceneGraphs, EveryPartitionerKeepsItsPropertiesOnTheScenes) {
  for (const SceneCase& c : kScenes) {
    World world(make_builtin_scene(c.name, c.sets), {}, pgs());
    for (int i = 0; i < c.steps; ++i) world.step();
    const ConstraintGraph& g = world_graph(world);
    ASSERT_GE(g.edge_count(), c.min_edges) << c.name;
    const std::vector<int> comp = test::components(g);
    for (PartitionerKind kind : {PartitionerKind::Bfs, PartitionerKind::MinDp, PartitionerKind::MaxDp,
                                 PartitionerKind::Mr, PartitionerKind::Mix, PartitionerKind::Metis})
      for (int nmax : {4, 16}) {
        PartitionParams p;
        p.partitioner = kind;
        p.nmax = nmax;
        Partition a, b;
        partition_graph(g, p, a);
        ASSERT_EQ(check_partition(g, a, nmax), "") << c.name << " " << partitioner_name(kind) << " " << nmax;
        partition_graph(g, p, b);
        EXPECT_EQ(a.part_of, b.part_of) << c.name << " " << partitioner_name(kind);
        if (kind != PartitionerKind::Metis)
          EXPECT_EQ(a.part_of, test::reference_partition(g, p).part_of) << c.name << " " << partitioner_name(kind);
        // Islands that fit are single parts.
        std::vector<int> comp_size(g.node_count(), 0), comp_part(g.node_count(), -1);
        for (int x : comp) ++comp_size[x];
        for (int v = 0; v < g.node_count(); ++v)
          if (comp_size[comp[v]] <= nmax) {
            if (comp_part[comp[v]] < 0) comp_part[comp[v]] = a.part_of[v];
            EXPECT_EQ(a.part_of[v], comp_part[comp[v]]) << c.name << " " << partitioner_name(kind);
          }
      }
  }
}

TEST(SceneGraphs, WorldPartitionsEveryStepAndReportsTheQuality) {
  PartitionParams params;
  params.partitioner = PartitionerKind::Mix;
  params.refiner = RefinerKind::Fm;
  params.nmax = 8;
  params.debug_checks = true;  // a broken partition throws from step()
  World world(make_builtin_scene("rock_pile", {{"rocks", "40"}}), {}, pgs(), params);
  EXPECT_EQ(world.partition_params().nmax, 8);
  int steps_with_cut = 0, kept = 0;
  for (int i = 0; i < 100; ++i) {
    const StepStats& s = world.step();
    const ConstraintGraph& g = world_graph(world);
    // The World's parts: MIX then FM, deterministic, so recomputing them gives the same ids.
    Partition expect;
    partition_graph(g, params, expect);
    refine_partition(g, params, expect);
    ASSERT_EQ(world_partition(world).part_of, expect.part_of) << "step " << s.step;
    if (world_partition_kept(world)) {
      ++kept;
      EXPECT_EQ(s.profile.refine_ms, 0);
    }
    const PartitionQuality q = measure_partition(g, expect);
    EXPECT_EQ(s.partition.parts, q.parts);
    EXPECT_EQ(s.partition.edge_cut, q.edge_cut);
    EXPECT_EQ(s.partition.interface_rows, q.interface_rows);
    EXPECT_EQ(s.partition.interface_bodies, q.interface_bodies);
    steps_with_cut += s.partition.edge_cut > 0;
  }
  EXPECT_GT(steps_with_cut, 0);
  // Steps whose graph repeats the step before's kept its parts, checked above to be the parts made
  // afresh; at least the first step made its own.
  EXPECT_LT(kept, 100);
}

// A World whose graph does not change keeps its parts: a tower of logs at rest (the direct solver:
// PGS leaves it jittering, its contacts coming and going).
TEST(SceneGraphs, AWorldAtRestKeepsItsParts) {
  PartitionParams params;
  params.partitioner = PartitionerKind::Metis;
  params.nmax = 10;
  World world(make_builtin_scene("log_tower", {{"layers", "6"}}), {}, {}, params);
  for (int i = 0; i < 30; ++i) world.step();
  for (int i = 0; i < 5; ++i) {
    world.step();
    EXPECT_TRUE(world_partition_kept(world)) << "step " << world.step_count();
  }
}

TEST(SceneGraphs, WithoutAPartitionerThePartsAreTheIslands) {
  World world(make_builtin_scene("rock_pile", {{"rocks", "20"}}), {}, pgs());
  for (int i = 0; i < 60; ++i) {
    const StepStats& s = world.step();
    EXPECT_EQ(s.partition.parts, s.islands);
    EXPECT_EQ(s.partition.edge_cut, 0);
    EXPECT_EQ(s.profile.partition_ms, 0);
    EXPECT_EQ(s.profile.refine_ms, 0);
  }
}

}  // namespace
}  // namespace rbpart
