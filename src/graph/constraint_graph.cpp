#include "graph/constraint_graph.hpp"

#include <algorithm>
#include <numeric>

namespace rbpart {

WeightSum ConstraintGraph::degree(int node) const {
  return std::accumulate(weight.begin() + offset[node], weight.begin() + offset[node + 1], WeightSum{0});
}

namespace {

// A row starts a constraint if it is a contact's normal row or a joint's first row (row keys put
// the row's index within its joint in the low three bits, assembly/assemble.hpp).
bool starts_constraint(const Rows& rows, std::size_t r) {
  return rows.kind[r] == RowKind::Normal || (rows.kind[r] == RowKind::Joint && (rows.key[r] & 7) == 0);
}

struct Edge {
  int a, b, weight, rows;
};

}  // namespace

void build_constraint_graph(const Rows& rows, const Bodies& bodies, ConstraintGraph& g) {
  g.body_of.clear();
  g.mass.clear();
  g.node_of.assign(bodies.size(), -1);
  for (int i = 0; i < bodies.size(); ++i)
    if (!bodies.is_static[i]) {
      g.node_of[i] = static_cast<int>(g.body_of.size());
      g.body_of.push_back(i);
      g.mass.push_back(bodies.mass[i]);
    }

  // One entry per row between two dynamic bodies, in both directions, bucketed by its first node
  // (counting sort), each node's entries sorted by the other node, then merged per pair (scratch
  // kept per thread, so that a warm step allocates nothing).
  const int n = g.node_count();
  thread_local std::vector<int> start;
  thread_local std::vector<Edge> half_edges;
  start.assign(n + 1, 0);
  const auto row_nodes = [&](std::size_t r, int& a, int& b) {
    a = rows.body[r][0] >= 0 ? g.node_of[rows.body[r][0]] : -1;
    b = rows.body[r][1] >= 0 ? g.node_of[rows.body[r][1]] : -1;
    return a >= 0 && b >= 0 && a != b;
  };
  for (std::size_t r = 0; r < rows.size(); ++r) {
    int a, b;
    if (!row_nodes(r, a, b)) continue;
    ++start[a + 1];
    ++start[b + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  half_edges.resize(start[n]);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    int a, b;
    if (!row_nodes(r, a, b)) continue;
    const int w = starts_constraint(rows, r) ? 1 : 0;
    half_edges[start[a]++] = {a, b, w, 1};
    half_edges[start[b]++] = {b, a, w, 1};
  }
  // start[a] is now the end of node a's entries, the start of a + 1's.
  for (int a = 0; a < n; ++a)
    std::sort(half_edges.begin() + (a > 0 ? start[a - 1] : 0), half_edges.begin() + start[a],
              [](const Edge& x, const Edge& y) { return x.b < y.b; });

  g.offset.assign(n + 1, 0);
  g.adjacency.clear();
  g.weight.clear();
  g.rows.clear();
  for (std::size_t i = 0; i < half_edges.size();) {
    const Edge& e = half_edges[i];
    int w = 0, count = 0;
    std::size_t j = i;
    for (; j < half_edges.size() && half_edges[j].a == e.a && half_edges[j].b == e.b; ++j) {
      w += half_edges[j].weight;
      count += half_edges[j].rows;
    }
    g.adjacency.push_back(e.b);
    g.weight.push_back(w);
    g.rows.push_back(count);
    ++g.offset[e.a + 1];
    i = j;
  }
  std::partial_sum(g.offset.begin(), g.offset.end(), g.offset.begin());
}

}  // namespace rbpart
