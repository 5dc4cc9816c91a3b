// The quality report of a partition (issue #4, docs/design.md#contracts columns) and the checks of its
// properties (docs/design.md#partition; partition_by_islands' parts), all O(n + m).
#include <algorithm>
#include <string>

#include "partition/partition.hpp"

namespace rbpart {

PartitionQuality measure_partition(const ConstraintGraph& graph, const Partition& partition) {
  PartitionQuality q;
  q.parts = partition.part_count;
  std::vector<int> size(partition.part_count, 0);
  for (int p : partition.part_of) ++size[p];
  if (!size.empty()) {
    const auto [lo, hi] = std::minmax_element(size.begin(), size.end());
    q.min_bodies = *lo;
    q.max_bodies = *hi;
    q.mean_bodies = static_cast<double>(graph.node_count()) / partition.part_count;
  }
  for (int v = 0; v < graph.node_count(); ++v) {
    bool on_interface = false;
    for (int k = graph.offset[v]; k < graph.offset[v + 1]; ++k) {
      const int u = graph.adjacency[k];
      if (partition.part_of[u] == partition.part_of[v]) continue;
      on_interface = true;
      if (u > v) {  // each cut edge once
        q.edge_cut += graph.weight[k];
        q.interface_rows += graph.rows[k];
      }
    }
    q.interface_bodies += on_interface;
  }
  return q;
}

std::string check_partition(const ConstraintGraph& graph, const Partition& partition, int nmax) {
  const int n = graph.node_count(), parts = partition.part_count;
  if (static_cast<int>(partition.part_of.size()) != n)
    return "part_of has " + std::to_string(partition.part_of.size()) + " entries for " + std::to_string(n) + " nodes";
  if (parts < 0) return "negative part count " + std::to_string(parts);
  std::vector<int> size(parts, 0), first(parts, -1);
  for (int v = 0; v < n; ++v) {
    const int p = partition.part_of[v];
    if (p < 0 || p >= parts)
      return "node " + std::to_string(v) + " has part id " + std::to_string(p) + ", outside 0.." +
             std::to_string(parts - 1);
    if (size[p]++ == 0) first[p] = v;
  }
  for (int p = 0; p < parts; ++p) {
    if (size[p] == 0) return "part " + std::to_string(p) + " is empty";
    if (size[p] > nmax)
      return "part " + std::to_string(p) + " has " + std::to_string(size[p]) + " bodies, more than nmax " +
             std::to_string(nmax);
  }
  // Connectivity: a breadth-first search inside each part from its first node reaches all of it.
  std::vector<char> reached(n, 0);
  std::vector<int> queue;
  for (int p = 0; p < parts; ++p) {
    queue.assign(1, first[p]);
    reached[first[p]] = 1;
    for (std::size_t head = 0; head < queue.size(); ++head)
      for (int k = graph.offset[queue[head]]; k < graph.offset[queue[head] + 1]; ++k) {
        const int u = graph.adjacency[k];
        if (!reached[u] && partition.part_of[u] == p) {
          reached[u] = 1;
          queue.push_back(u);
        }
      }
    if (static_cast<int>(queue.size()) != size[p]) {
      int missed = first[p];
      while (reached[missed] || partition.part_of[missed] != p) ++missed;
      return "part " + std::to_string(p) + " is not connected: node " + std::to_string(missed) +
             " is not reached from node " + std::to_string(first[p]);
    }
  }
  return "";
}

std::string check_island_partition(const ConstraintGraph& graph, const Partition& partition) {
  const std::string problem = check_partition(graph, partition, std::max(graph.node_count(), 1));
  if (!problem.empty()) return problem;
  int parts_met = 0;
  for (int v = 0; v < graph.node_count(); ++v) {
    const int p = partition.part_of[v];
    if (p > parts_met)
      return "node " + std::to_string(v) + " is the lowest of part " + std::to_string(p) + ", met before part " +
             std::to_string(parts_met);
    parts_met += p == parts_met;
    for (int k = graph.offset[v]; k < graph.offset[v + 1]; ++k)
      if (partition.part_of[graph.adjacency[k]] != p)
        return "edge " + std::to_string(v) + "-" + std::to_string(graph.adjacency[k]) + " joins parts " +
               std::to_string(p) + " and " + std::to_string(partition.part_of[graph.adjacency[k]]) +
               " of one island";
  }
  return "";
}

}  // namespace rbpart
