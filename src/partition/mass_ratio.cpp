// MR, the mass-ratio partitioner (docs/design.md#partition): seeds and breadth-first order as BFS, but a
// candidate β joins only if max(m_min, m_β) / min(m_min, m_β) < τ_MR, with m_min the smallest mass
// in the part; the part closes when no candidate qualifies (or at nmax).
//
// m_min only falls as the part grows, which settles when a rejected candidate can qualify later:
// - β at least as heavy as m_min that fails fails for good (its ratio m_β / m_min only grows), so it
//   is dropped for the rest of the part;
// - β lighter than m_min that fails (m_min / m_β ≥ τ) may pass once a lighter body has joined: it is
//   held aside, heaviest first, and queued again (with its breadth-first key) when m_min falls
//   enough. The next body is thus always the first qualifying candidate in breadth-first order.
#include <algorithm>
#include <utility>

#include "partition/grow.hpp"

namespace rbpart {

namespace {

struct MassRatioRule : BreadthFirstOrder {
  GrowState& grow;
  const std::vector<double>& mass;
  double tau;
  double m_min = 0;
  std::vector<std::pair<double, int>> held;  // too-light candidates, max-heap by mass

  MassRatioRule(GrowState& s, double tau_mr) : BreadthFirstOrder(s), grow(s), mass(s.graph->mass), tau(tau_mr) {}

  bool qualifies(int u) const { return std::max(m_min, mass[u]) / std::min(m_min, mass[u]) < tau; }

  void begin(int seed) {
    m_min = mass[seed];
    held.clear();
  }
  void joined(int v) {
    if (mass[v] >= m_min) return;
    m_min = mass[v];
    while (!held.empty() && qualifies(held.front().second)) {
      std::pop_heap(held.begin(), held.end());
      grow.push(key(held.back().second), held.back().second);
      held.pop_back();
    }
  }
  bool offer(int u) {
    if (mass[u] >= m_min || qualifies(u)) return true;
    held.emplace_back(mass[u], u);
    std::push_heap(held.begin(), held.end());
    return false;
  }
  bool admit(int u) const { return qualifies(u); }
};

}  // namespace

void partition_island_mr(GrowState& s, const PartitionParams& params, const int* nodes, int count) {
  MassRatioRule rule(s, params.tau_mr);
  grow_island(s, rule, nodes, count);
}

}  // namespace rbpart
