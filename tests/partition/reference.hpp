#pragma once
// Naive references for the partition tests, written from the text of docs/design.md#graph and #partition
// without the library's queues: components by union-find, and each growth rule by scanning every candidate at
// every step (O(n^2) per island; for graphs of a few hundred nodes).
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

#include <rbpart/params.hpp>

#include "graph/constraint_graph.hpp"
#include "partition/partition.hpp"

namespace rbpart::test {

// Component id per node, numbered in order of the lowest node.
inline std::vector<int> components(const ConstraintGraph& g) {
  const int n = g.node_count();
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (int v = 0; v < n; ++v)
    for (int k = g.offset[v]; k < g.offset[v + 1]; ++k) {
      const int a = find(v), b = find(g.adjacency[k]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  std::vector<int> id(n, -1), comp(n);
  int count = 0;
  for (int v = 0; v < n; ++v) {
    const int root = find(v);
    if (id[root] < 0) id[root] = count++;
    comp[v] = id[root];
  }
  return comp;
}

inline int edge_weight(const ConstraintGraph& g, int a, int b) {
  for (int k = g.offset[a]; k < g.offset[a + 1]; ++k)
    if (g.adjacency[k] == b) return g.weight[k];
  return 0;
}

// docs/design.md#partition read literally, for BFS, MinDP, MaxDP, MR and MIX.
inline Partition reference_partition(const ConstraintGraph& g, const PartitionParams& p) {
  const int n = g.node_count();
  const std::vector<int> comp = components(g);
  const int comps = n ? *std::max_element(comp.begin(), comp.end()) + 1 : 0;
  std::vector<int> comp_size(comps, 0);
  for (int c : comp) ++comp_size[c];
  auto degree = [&](int v) { return g.degree(v); };
  auto ratio = [](double a, double b) { return std::max(a, b) / std::min(a, b); };
  const bool by_degree = p.partitioner == PartitionerKind::MinDp || p.partitioner == PartitionerKind::MaxDp ||
                         p.partitioner == PartitionerKind::Mix;
  const int sign = p.partitioner == PartitionerKind::MaxDp ? -1 : 1;

  Partition out;
  out.part_of.assign(n, -1);
  for (int c = 0; c < comps; ++c) {
    auto in_comp = [&](int v) { return comp[v] == c; };
    if (comp_size[c] <= p.nmax) {
      for (int v = 0; v < n; ++v)
        if (in_comp(v)) out.part_of[v] = out.part_count;
      ++out.part_count;
      continue;
    }
    for (;;) {
      // Seed: lowest index (BFS, MR), or minimum (maximum) degree then lowest index.
      int seed = -1;
      for (int v = 0; v < n; ++v) {
        if (!in_comp(v) || out.part_of[v] >= 0) continue;
        if (seed < 0 || (by_degree && sign * degree(v) < sign * degree(seed))) seed = v;
      }
      if (seed < 0) break;
      const int part = out.part_count++;
      std::vector<int> members{seed}, discovered;
      out.part_of[seed] = part;
      double m_min = g.mass[seed];
      auto discover = [&](int v) {  // breadth-first order: a joining body's neighbours, in index order
        for (int k = g.offset[v]; k < g.offset[v + 1]; ++k) {
          const int u = g.adjacency[k];
          if (out.part_of[u] < 0 && std::find(discovered.begin(), discovered.end(), u) == discovered.end())
            discovered.push_back(u);
        }
      };
      discover(seed);
      while (static_cast<int>(members.size()) < p.nmax) {
        int next = -1;
        if (p.partitioner == PartitionerKind::Bfs || p.partitioner == PartitionerKind::Mr) {
          for (int u : discovered)
            if (out.part_of[u] < 0 && (p.partitioner == PartitionerKind::Bfs || ratio(m_min, g.mass[u]) < p.tau_mr)) {
              next = u;
              break;
            }
        } else {
          const bool gain_phase = p.partitioner == PartitionerKind::Mix && members.size() >= p.tau_mix * p.nmax;
          std::int64_t best = 0;
          for (int u = 0; u < n; ++u) {
            if (out.part_of[u] >= 0) continue;
            int inside = 0;
            bool adjacent = false;
            for (int v : members) {
              const int w = edge_weight(g, u, v);
              inside += w;
              adjacent = adjacent || w > 0;
            }
            if (!adjacent) continue;
            // Smaller key first: degree (MinDP), minus degree (MaxDP), minus gain (MIX).
            const std::int64_t key = gain_phase ? -(inside - (degree(u) - inside)) : sign * degree(u);
            if (next < 0 || key < best) {
              next = u;
              best = key;
            }
          }
        }
        if (next < 0) break;
        out.part_of[next] = part;
        members.push_back(next);
        m_min = std::min(m_min, g.mass[next]);
        discover(next);
      }
    }
  }
  return out;
}

}  // namespace rbpart::test
