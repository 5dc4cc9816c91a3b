#pragma once
// Partitions of the constraint graph into sub-systems (docs/design.md#partition) and their refinement
// (#refine). A partition gives every graph node (dynamic body) a part id. Every partitioner and refiner
// returns partitions whose parts are disjoint, cover all nodes, are connected in the graph, hold at most nmax
// nodes and lie within one island; ids are 0..part_count-1, numbered in the order the parts were made; the
// result depends only on the graph and the parameters (ties go to the lowest node index).
#include <rbpart/params.hpp>
#include <rbpart/stats.hpp>

#include <string>
#include <vector>

#include "graph/constraint_graph.hpp"
#include "graph/islands.hpp"

namespace rbpart {

struct Partition {
  std::vector<int> part_of;  // node -> part id
  int part_count = 0;
};

// Quality of a partition (issue #4's report): the step's stats columns (PartitionStats, which a
// World's step takes from it) and what `rbpart partition` reports besides.
struct PartitionQuality : PartitionStats {
  int min_bodies = 0, max_bodies = 0;  // bodies per part
  double mean_bodies = 0;
  double partition_ms = 0, refine_ms = 0;
};

// The monolithic solvers' parts: one per island (graph nodes without rows: one part each), numbered
// in increasing order of their lowest node.
void partition_by_islands(const ConstraintGraph& graph, const Islands& islands, Partition& partition);

// Partitions `graph` with params.partitioner (not None). Islands of at most nmax nodes become one
// part each whatever the partitioner (docs/design.md#graph); isolated nodes are parts of their own.
void partition_graph(const ConstraintGraph& graph, const PartitionParams& params, Partition& partition);

// Refines `partition` in place with params.refiner (None: no change). Never raises the edge cut and
// keeps every property above.
void refine_partition(const ConstraintGraph& graph, const PartitionParams& params, Partition& partition);

// Whether two graphs agree in all that partition_graph and refine_partition read: the nodes (scene
// bodies and masses), the edges and their weights. Under the same parameters their partitions are
// then the same (above), so a step whose graph is the last one's keeps its partition: the World
// and the study's replay do, and at rest, where contacts persist, the two stages cost this check.
bool same_partition_input(const ConstraintGraph& a, const ConstraintGraph& b);

// Parts, sizes, cut, interface rows and bodies (times left 0: the caller measures them).
PartitionQuality measure_partition(const ConstraintGraph& graph, const Partition& partition);

// A whole graph's partition, as `rbpart partition` and the Python module make it: partition_graph,
// refine_partition, each timed into the quality returned; with params.debug_checks a partition
// breaking the properties above throws std::logic_error.
PartitionQuality partition_and_refine(const ConstraintGraph& graph, const PartitionParams& params,
                                      Partition& partition);

// The cap of `parts` balanced parts of `nodes` nodes, ceil(nodes / parts): `--parts K` as METIS users
// mean it (docs/formats.md#partition-report).
inline int nmax_for_parts(int nodes, int parts) { return (nodes + parts - 1) / parts; }

// Checks the properties above (cover, disjoint ids in range, connected parts, at most nmax nodes,
// no empty part); returns "" or the first violation, in words.
std::string check_partition(const ConstraintGraph& graph, const Partition& partition, int nmax);
// Checks partition_by_islands' promise: every part is one whole island (connected, no edge between
// two parts, any size), numbered in increasing order of its lowest node; "" or the first violation.
std::string check_island_partition(const ConstraintGraph& graph, const Partition& partition);

// Names as the CLI spells them: bfs mindp maxdp mr mix metis (none); none kl fm fm-rollback.
const char* partitioner_name(PartitionerKind kind);
const char* refiner_name(RefinerKind kind);
// Throws InputError naming the valid choices on an unknown name.
PartitionerKind parse_partitioner(const std::string& name);
RefinerKind parse_refiner(const std::string& name);

}  // namespace rbpart
