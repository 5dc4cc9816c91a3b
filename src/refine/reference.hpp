#pragma once
// From-scratch recomputations for params.debug_checks and validate builds (docs/design.md#refine),
// written apart from the refiners' incremental bookkeeping (no member lists, heaps, caches or
// articulation points): each gain is summed from a node's edges and each connectivity question
// answered by a breadth-first search over the whole graph, so a bookkeeping slip shows as a
// mismatch. O(n) and more per call: for tests and debugging only.
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "graph/constraint_graph.hpp"
#include "refine/gain_heap.hpp"

namespace rbpart::refine_reference {

// Constraints from node v to the nodes of part p (v's own part included).
WeightSum connection(const ConstraintGraph& graph, const std::vector<int>& part_of, int v, int p);

// Constraints (edge weights) between different parts.
WeightSum edge_cut(const ConstraintGraph& graph, const std::vector<int>& part_of);

// Per node, its best single move as FM ranks them: {gain E − I, node, target part}, the target a
// part other than its own that it has an edge to and that holds fewer than nmax nodes, ties to the
// lowest part id; nullopt when there is none. Whether the node may leave its part is not asked.
std::vector<std::optional<GainKey>> best_moves(const ConstraintGraph& graph, const std::vector<int>& part_of,
                                               int part_count, int nmax);

// Whether the nodes of part p without `out`, plus `in` when in >= 0, are a non-empty connected set.
bool connected(const ConstraintGraph& graph, const std::vector<int>& part_of, int p, int out, int in);

// Whether `node` may leave its part: the part keeps a node and stays connected without it.
bool can_leave(const ConstraintGraph& graph, const std::vector<int>& part_of, int node);

// Per pair of adjacent parts (a < b), the best legal KL swap of positive gain as KL ranks them:
// {gain (E_i − I_i) + (E_j − I_j) − 2c, lower node, higher node}, over βi ∈ a with an edge to b and
// βj ∈ b with an edge to a, such that both parts stay connected. Pairs without one are absent.
std::map<std::pair<int, int>, GainKey> best_swaps(const ConstraintGraph& graph, const std::vector<int>& part_of,
                                                  int part_count);

}  // namespace rbpart::refine_reference
