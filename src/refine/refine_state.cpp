#include "refine/refine_state.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "core/validate.hpp"
#include "refine/reference.hpp"

namespace rbpart {

void RefineState::reset(const ConstraintGraph& graph, const PartitionParams& params, Partition& partition) {
  const int n = graph.node_count(), parts = partition.part_count;
  if (static_cast<int>(partition.part_of.size()) != n)
    throw std::invalid_argument("refine: the partition has " + std::to_string(partition.part_of.size()) +
                                " part ids for " + std::to_string(n) + " nodes");
  graph_ = &graph;
  partition_ = &partition;
  part_of_ = partition.part_of.data();
  nmax_ = params.nmax;
  checks_ = params.debug_checks || (kValidate && n <= kValidateMoveNodes) ? Checks::Moves
            : kValidate                                                  ? Checks::Passes
                                                                         : Checks::None;
  size_.assign(parts, 0);
  head_.assign(parts, -1);
  next_.assign(n, -1);
  prev_.assign(n, -1);
  for (int v = n - 1; v >= 0; --v) {
    const int p = part_of_[v];
    if (p < 0 || p >= parts)
      throw std::invalid_argument("refine: node " + std::to_string(v) + " has part id " + std::to_string(p) +
                                  " outside 0.." + std::to_string(parts - 1));
    ++size_[p];
    next_[v] = head_[p];
    if (head_[p] >= 0) prev_[head_[p]] = v;
    head_[p] = v;
  }
  check_nmax_ = std::max(nmax_, size_.empty() ? 0 : *std::max_element(size_.begin(), size_.end()));
  cut_ = refine_reference::edge_cut(graph, partition.part_of);
  internal_.assign(n, 0);
  for (int v = 0; v < n; ++v)
    for (int k = graph.offset[v]; k < graph.offset[v + 1]; ++k)
      if (part_of_[graph.adjacency[k]] == part_of_[v]) internal_[v] += graph.weight[k];
  slot_.assign(parts, -1);
  articulation_.assign(n, 0);
  articulation_fresh_.assign(parts, 0);
  discovery_.assign(n, -1);
  low_.assign(n, 0);
  dfs_parent_.assign(n, -1);
  subtree_size_.assign(n, 1);
  seen_.assign(n, 0);
  stamp_ = 0;
  if (check_passes()) check("refine input");
}

const Connections& RefineState::connections(int node) {
  const int own = part_of_[node];
  Connections& c = connections_;
  c.internal = 0;
  c.external.clear();
  for (int k = graph_->offset[node]; k < graph_->offset[node + 1]; ++k) {
    const int p = part_of_[graph_->adjacency[k]];
    if (p == own) {
      c.internal += graph_->weight[k];
      continue;
    }
    if (slot_[p] < 0) {
      slot_[p] = static_cast<int>(c.external.size());
      c.external.emplace_back(p, 0);
    }
    c.external[slot_[p]].second += graph_->weight[k];
  }
  for (const auto& [p, w] : c.external) slot_[p] = -1;
  return c;
}

BestMove RefineState::best_move(int node) {
  const Connections& c = connections(node);
  BestMove best;
  WeightSum best_external = 0;
  for (const auto& [p, w] : c.external) {
    if (full(p)) continue;
    if (best.target < 0 || w > best_external || (w == best_external && p < best.target)) {
      best.target = p;
      best_external = w;
    }
  }
  best.gain = best_external - c.internal;
  return best;
}

int RefineState::edge_weight(int x, int y) const {
  const auto begin = graph_->adjacency.begin() + graph_->offset[x], end = graph_->adjacency.begin() + graph_->offset[x + 1];
  const auto it = std::lower_bound(begin, end, y);
  return it != end && *it == y ? graph_->weight[it - graph_->adjacency.begin()] : 0;
}

bool RefineState::can_leave(int node) {
  const int p = part_of_[node];
  if (size_[p] < 2) return false;
  // The part without `node` is connected iff one of node's neighbours in it reaches all the others
  // there. With one such neighbour, node is a leaf of the part: no search. Otherwise, unless the
  // part's articulation points are at hand, a breadth-first search from one of them that stops once
  // all are reached: node's neighbours in a pile are mostly near one another, so this usually ends
  // after a few nodes, where recomputing the articulation points costs the whole part.
  stamp_ += 2;
  const int target = stamp_, visited = stamp_ + 1;
  int inside = 0, first = -1;
  for (int k = graph_->offset[node]; k < graph_->offset[node + 1]; ++k)
    if (part_of_[graph_->adjacency[k]] == p) {
      first = graph_->adjacency[k];
      seen_[first] = target;
      ++inside;
    }
  if (inside < 2) return true;
  if (articulation_fresh_[p]) return !articulation_[node];
  int remaining = inside - 1;
  seen_[first] = visited;
  queue_.assign(1, first);
  for (std::size_t head = 0; head < queue_.size(); ++head)
    for (int k = graph_->offset[queue_[head]]; k < graph_->offset[queue_[head] + 1]; ++k) {
      const int u = graph_->adjacency[k];
      if (u == node || part_of_[u] != p || seen_[u] == visited) continue;
      if (seen_[u] == target && --remaining == 0) return true;
      seen_[u] = visited;
      queue_.push_back(u);
    }
  return false;
}

bool RefineState::swap_keeps_connected(int p, int out, int in) {
  if (size_[p] == 1) return true;  // the part becomes {in}
  int touches = 0;  // nodes of the rest that `in` has an edge to, counted up to 2
  for (int k = graph_->offset[in]; k < graph_->offset[in + 1] && touches < 2; ++k)
    touches += part_of_[graph_->adjacency[k]] == p && graph_->adjacency[k] != out;
  if (touches == 0) return false;
  // Part p is searched for many swaps between two changes (KL searches all its pairs after each
  // change of a neighbouring part), so its articulation points are worth computing.
  if (!articulation_fresh_[p]) find_articulation_points(p);
  if (!articulation_[out]) return true;  // the rest is connected and `in` attaches to it
  // `out` is an articulation point, so the rest falls into pieces (two at least): `in` must have an
  // edge into each. In the depth-first tree of the part, the pieces are the subtrees of the children
  // c of `out` with low[c] >= discovery[out], plus, unless `out` is the root, everything else. A
  // subtree is an interval of discovery times, so locating a node is a comparison per piece.
  if (touches < 2) return false;
  pieces_.clear();
  for (int k = graph_->offset[out]; k < graph_->offset[out + 1]; ++k) {
    const int c = graph_->adjacency[k];
    if (part_of_[c] == p && dfs_parent_[c] == out && low_[c] >= discovery_[out]) pieces_.push_back({c, false});
  }
  bool rest_reached = dfs_parent_[out] < 0;  // the root leaves no piece above it
  for (int k = graph_->offset[in]; k < graph_->offset[in + 1]; ++k) {
    const int w = graph_->adjacency[k];
    if (part_of_[w] != p || w == out) continue;
    bool in_subtree = false;
    for (auto& [c, reached] : pieces_)
      if (discovery_[w] >= discovery_[c] && discovery_[w] < discovery_[c] + subtree_size_[c]) {
        reached = in_subtree = true;
        break;
      }
    rest_reached |= !in_subtree;
  }
  if (!rest_reached) return false;
  for (const auto& [c, reached] : pieces_)
    if (!reached) return false;
  return true;
}

void RefineState::move(int node, int to) {
  const int from = part_of_[node];
  if (prev_[node] >= 0) next_[prev_[node]] = next_[node];
  else head_[from] = next_[node];
  if (next_[node] >= 0) prev_[next_[node]] = prev_[node];
  prev_[node] = -1;
  next_[node] = head_[to];
  if (head_[to] >= 0) prev_[head_[to]] = node;
  head_[to] = node;
  --size_[from];
  ++size_[to];
  part_of_[node] = to;
  internal_[node] = 0;
  for (int k = graph_->offset[node]; k < graph_->offset[node + 1]; ++k) {
    const int u = graph_->adjacency[k], w = graph_->weight[k];
    if (part_of_[u] == from) internal_[u] -= w;
    else if (part_of_[u] == to) {
      internal_[u] += w;
      internal_[node] += w;
    }
  }
  articulation_fresh_[from] = articulation_fresh_[to] = 0;
}

void RefineState::find_articulation_points(int p) {
  // Hopcroft–Tarjan by an iterative depth-first search restricted to the part: v is an articulation
  // point iff it is the root with two or more tree children, or a non-root with a tree child c whose
  // subtree reaches no node discovered before v (low[c] >= discovery[v]). Parents and subtree sizes
  // are kept for swap_keeps_connected.
  for_each_member(p, [&](int v) {
    discovery_[v] = -1;
    articulation_[v] = 0;
    subtree_size_[v] = 1;
  });
  const int root = head_[p];
  int time = 0, root_children = 0;
  discovery_[root] = low_[root] = time++;
  dfs_parent_[root] = -1;
  dfs_stack_.assign(1, {root, graph_->offset[root]});
  while (!dfs_stack_.empty()) {
    const int v = dfs_stack_.back().first;
    int& next_edge = dfs_stack_.back().second;
    if (next_edge < graph_->offset[v + 1]) {
      const int u = graph_->adjacency[next_edge++];
      if (part_of_[u] != p) continue;
      if (discovery_[u] >= 0) {
        // Includes the edge back to v's parent: harmless for articulation points, since the test
        // at the parent is low >= discovery[parent].
        low_[v] = std::min(low_[v], discovery_[u]);
        continue;
      }
      discovery_[u] = low_[u] = time++;
      dfs_parent_[u] = v;
      root_children += v == root;
      dfs_stack_.emplace_back(u, graph_->offset[u]);
      continue;
    }
    dfs_stack_.pop_back();
    if (dfs_stack_.empty()) break;
    const int parent = dfs_stack_.back().first;
    low_[parent] = std::min(low_[parent], low_[v]);
    subtree_size_[parent] += subtree_size_[v];
    if (parent != root && low_[v] >= discovery_[parent]) articulation_[parent] = 1;
  }
  articulation_[root] = root_children >= 2;
  articulation_fresh_[p] = 1;
}

std::string RefineState::violation() const {
  const WeightSum cut = refine_reference::edge_cut(*graph_, partition_->part_of);
  if (cut != cut_) return "tracked edge cut " + std::to_string(cut_) + ", recomputed " + std::to_string(cut);
  std::vector<int> size(size_.size(), 0);
  for (int p : partition_->part_of) ++size[p];
  if (size != size_) return "tracked part sizes differ from the recount";
  for (int v = 0; v < graph_->node_count(); ++v) {
    const WeightSum internal = refine_reference::connection(*graph_, partition_->part_of, v, part_of_[v]);
    if (internal_[v] != internal)
      return "node " + std::to_string(v) + ": tracked internal constraints " + std::to_string(internal_[v]) +
             ", recomputed " + std::to_string(internal);
  }
  return check_partition(*graph_, *partition_, check_nmax_);
}

void RefineState::check(const char* where) const {
  const std::string problem = violation();
  if (!problem.empty()) throw std::logic_error(std::string(where) + ": " + problem);
}

}  // namespace rbpart
