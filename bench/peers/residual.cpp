// The natural-map residual of docs/design.md (contact problem), on the rows an engine solved.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "peers.hpp"

namespace peers {
namespace {

int find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

double natural_map_residual(const std::vector<Row>& rows, int nodes) {
  // Islands: dynamic nodes joined by a row; rows with the world only belong to their body.
  std::vector<int> parent(nodes);
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& r : rows)
    if (r.node_a >= 0 && r.node_b >= 0) parent[find(parent, r.node_a)] = find(parent, r.node_b);
  std::vector<double> worst(nodes, 0), free_velocity(nodes, 0);
  for (const auto& r : rows) {
    const int island = find(parent, r.node_a >= 0 ? r.node_a : r.node_b);
    const double f = r.lambda - std::clamp(r.inner, r.lo, r.hi);
    worst[island] = std::max(worst[island], r.a_jj * std::abs(f));
    free_velocity[island] = std::max(free_velocity[island], std::abs(r.q));
  }
  double residual = 0;
  for (int i = 0; i < nodes; ++i)
    if (free_velocity[i] > 0) residual = std::max(residual, worst[i] / free_velocity[i]);
  return residual;
}

}  // namespace peers
