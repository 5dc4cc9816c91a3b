#pragma once
// Shared by the refinement tests: run a refiner on a given partition.
#include <algorithm>
#include <random>
#include <vector>

#include "partition/partition.hpp"

namespace rbpart {

inline Partition make_partition(std::vector<int> part_of) {
  Partition p;
  p.part_count = part_of.empty() ? 0 : *std::max_element(part_of.begin(), part_of.end()) + 1;
  p.part_of = std::move(part_of);
  return p;
}

inline Partition refined(const ConstraintGraph& graph, Partition partition, RefinerKind refiner, int nmax,
                         bool debug_checks = true) {
  PartitionParams params;
  params.refiner = refiner;
  params.nmax = nmax;
  params.debug_checks = debug_checks;
  refine_partition(graph, params, partition);
  return partition;
}

// Connected parts of at most nmax nodes, grown from random seeds by random frontier picks up to
// random sizes: starting points no partitioner would produce.
inline Partition random_connected_partition(const ConstraintGraph& g, int nmax, std::mt19937& rng) {
  const int n = g.node_count();
  std::vector<int> order(n);
  for (int v = 0; v < n; ++v) order[v] = v;
  for (int v = n - 1; v > 0; --v) std::swap(order[v], order[rng() % (v + 1)]);
  Partition p;
  p.part_of.assign(n, -1);
  std::vector<int> frontier;
  for (int seed : order) {
    if (p.part_of[seed] >= 0) continue;
    const int part = p.part_count++;
    const int target = 1 + static_cast<int>(rng() % nmax);
    int size = 0;
    frontier.assign(1, seed);
    while (size < target && !frontier.empty()) {
      const std::size_t k = rng() % frontier.size();
      const int v = frontier[k];
      frontier[k] = frontier.back();
      frontier.pop_back();
      if (p.part_of[v] >= 0) continue;
      p.part_of[v] = part;
      ++size;
      for (int e = g.offset[v]; e < g.offset[v + 1]; ++e)
        if (p.part_of[g.adjacency[e]] < 0) frontier.push_back(g.adjacency[e]);
    }
  }
  return p;
}

}  // namespace rbpart
