#include "refine/reference.hpp"

#include <algorithm>

namespace rbpart::refine_reference {

WeightSum connection(const ConstraintGraph& g, const std::vector<int>& part_of, int v, int p) {
  WeightSum sum = 0;
  for (int k = g.offset[v]; k < g.offset[v + 1]; ++k)
    if (part_of[g.adjacency[k]] == p) sum += g.weight[k];
  return sum;
}

namespace {

WeightSum edge_weight(const ConstraintGraph& g, int x, int y) {
  WeightSum sum = 0;
  for (int k = g.offset[x]; k < g.offset[x + 1]; ++k)
    if (g.adjacency[k] == y) sum += g.weight[k];
  return sum;
}

// The parts other than its own that v has an edge to, in increasing order.
std::vector<int> other_parts(const ConstraintGraph& g, const std::vector<int>& part_of, int v) {
  std::vector<int> parts;
  for (int k = g.offset[v]; k < g.offset[v + 1]; ++k)
    if (part_of[g.adjacency[k]] != part_of[v]) parts.push_back(part_of[g.adjacency[k]]);
  std::sort(parts.begin(), parts.end());
  parts.erase(std::unique(parts.begin(), parts.end()), parts.end());
  return parts;
}

}  // namespace

bool connected(const ConstraintGraph& g, const std::vector<int>& part_of, int p, int out, int in) {
  const int n = g.node_count();
  auto inside = [&](int u) { return u == in || (part_of[u] == p && u != out); };
  int count = 0, start = -1;
  for (int u = 0; u < n; ++u)
    if (inside(u)) {
      if (start < 0) start = u;
      ++count;
    }
  if (count == 0) return false;
  std::vector<char> seen(n, 0);
  std::vector<int> queue{start};
  seen[start] = 1;
  for (std::size_t head = 0; head < queue.size(); ++head)
    for (int k = g.offset[queue[head]]; k < g.offset[queue[head] + 1]; ++k) {
      const int u = g.adjacency[k];
      if (!seen[u] && inside(u)) {
        seen[u] = 1;
        queue.push_back(u);
      }
    }
  return static_cast<int>(queue.size()) == count;
}

WeightSum edge_cut(const ConstraintGraph& graph, const std::vector<int>& part_of) {
  WeightSum twice = 0;
  for (int v = 0; v < graph.node_count(); ++v)
    for (int k = graph.offset[v]; k < graph.offset[v + 1]; ++k)
      if (part_of[graph.adjacency[k]] != part_of[v]) twice += graph.weight[k];
  return twice / 2;
}

std::vector<std::optional<GainKey>> best_moves(const ConstraintGraph& graph, const std::vector<int>& part_of,
                                               int part_count, int nmax) {
  std::vector<int> size(part_count, 0);
  for (int p : part_of) ++size[p];
  std::vector<std::optional<GainKey>> best(graph.node_count());
  for (int v = 0; v < graph.node_count(); ++v) {
    const WeightSum own = connection(graph, part_of, v, part_of[v]);
    for (int q : other_parts(graph, part_of, v)) {
      if (size[q] >= nmax) continue;
      const GainKey key{connection(graph, part_of, v, q) - own, v, q};
      if (!best[v] || precedes(key, *best[v])) best[v] = key;
    }
  }
  return best;
}

bool can_leave(const ConstraintGraph& graph, const std::vector<int>& part_of, int node) {
  return connected(graph, part_of, part_of[node], node, -1);
}

std::map<std::pair<int, int>, GainKey> best_swaps(const ConstraintGraph& graph, const std::vector<int>& part_of,
                                                  int part_count) {
  std::vector<std::vector<int>> members(part_count);
  for (int v = 0; v < graph.node_count(); ++v) members[part_of[v]].push_back(v);
  std::map<std::pair<int, int>, GainKey> best;
  // Each unordered swap once: βi in the lower-numbered part a, βj in b > a.
  for (int x = 0; x < graph.node_count(); ++x) {
    const int a = part_of[x];
    for (int b : other_parts(graph, part_of, x)) {
      if (b < a) continue;
      const WeightSum dx = connection(graph, part_of, x, b) - connection(graph, part_of, x, a);
      for (int y : members[b]) {
        const WeightSum ey = connection(graph, part_of, y, a);
        if (ey == 0) continue;
        const WeightSum gain = dx + ey - connection(graph, part_of, y, b) - 2 * edge_weight(graph, x, y);
        if (gain <= 0) continue;
        const GainKey key{gain, std::min(x, y), std::max(x, y)};
        const auto found = best.find({a, b});
        if (found != best.end() && !precedes(key, found->second)) continue;
        if (connected(graph, part_of, a, x, y) && connected(graph, part_of, b, y, x)) best[{a, b}] = key;
      }
    }
  }
  return best;
}

}  // namespace rbpart::refine_reference
