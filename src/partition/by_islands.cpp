#include "core/validate.hpp"
#include "partition/partition.hpp"

namespace rbpart {

void partition_by_islands(const ConstraintGraph& graph, const Islands& islands, Partition& partition) {
  const int n = graph.node_count();
  // Scratch kept per thread, so that a warm step allocates nothing.
  thread_local std::vector<int> island_of, part_of_island;
  island_of.assign(n, -1);
  for (std::size_t i = 0; i < islands.count(); ++i)
    for (int k = islands.body_offset[i]; k < islands.body_offset[i + 1]; ++k) {
      const int node = graph.node_of[islands.bodies[k]];
      if (node >= 0) island_of[node] = static_cast<int>(i);
    }
  // Islands list their bodies in increasing order, and node order follows body order, so numbering
  // parts as their first node is met gives increasing lowest nodes.
  part_of_island.assign(islands.count(), -1);
  partition.part_of.assign(n, -1);
  partition.part_count = 0;
  for (int v = 0; v < n; ++v) {
    const int i = island_of[v];
    if (i < 0) {
      partition.part_of[v] = partition.part_count++;
    } else {
      if (part_of_island[i] < 0) part_of_island[i] = partition.part_count++;
      partition.part_of[v] = part_of_island[i];
    }
  }
  RBPART_CHECK(check_island_partition(graph, partition));
}

}  // namespace rbpart
