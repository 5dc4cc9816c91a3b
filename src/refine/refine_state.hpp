#pragma once
// What KL and FM share (docs/design.md#refine): the partition being refined with its part sizes and member
// lists, each node's constraints per part, the legality of moves (a part is never emptied,
// disconnected or filled beyond nmax) and the debug checks against from-scratch recomputation.
#include <rbpart/params.hpp>

#include <string>
#include <utility>
#include <vector>

#include "graph/constraint_graph.hpp"
#include "partition/partition.hpp"

namespace rbpart {

// A node's constraints to the parts it touches: `internal` to its own part, `external` one
// (part, constraints) entry per other part, in the order the node's edges first reach them.
struct Connections {
  WeightSum internal = 0;
  std::vector<std::pair<int, WeightSum>> external;
};

// The best single move of a node (FM's gain α = E − I, docs/design.md#refine): to the part that takes most
// of its constraints among the other parts it touches that are not full (ties: lowest part id).
struct BestMove {
  WeightSum gain = 0;
  int target = -1;  // -1: no adjacent part can take the node
};

// Its buffers are kept across reset() calls, so a state reused for every step allocates nothing
// once warmed up (STYLE.md habit 6).
class RefineState {
 public:
  RefineState() = default;
  RefineState(const ConstraintGraph& graph, const PartitionParams& params, Partition& partition) {
    reset(graph, params, partition);
  }
  // Starts refining `partition` of `graph` in place; params.nmax caps the parts a move may enter.
  // Throws std::invalid_argument when the partition does not match the graph.
  void reset(const ConstraintGraph& graph, const PartitionParams& params, Partition& partition);

  const ConstraintGraph& graph() const { return *graph_; }
  const Partition& partition() const { return *partition_; }
  int nmax() const { return nmax_; }
  int part(int node) const { return part_of_[node]; }
  int size(int part) const { return size_[part]; }
  bool full(int part) const { return size_[part] >= nmax_; }
  // Edge cut of the current partition, kept up to date by the refiners through add_to_cut.
  WeightSum cut() const { return cut_; }
  void add_to_cut(WeightSum delta) { cut_ += delta; }

  // Constraints from `node` to its own part, kept up to date by move().
  WeightSum internal(int node) const { return internal_[node]; }
  // Valid until the next call.
  const Connections& connections(int node);
  BestMove best_move(int node);
  // Weight of the edge x-y (0 when absent), by binary search in x's sorted neighbours.
  int edge_weight(int x, int y) const;

  // Whether `node` may leave its part: the part keeps at least one node and stays connected.
  bool can_leave(int node);
  // Whether part `p` stays connected when `out` (a member) is swapped for `in` (not a member).
  bool swap_keeps_connected(int p, int out, int in);

  // Moves `node` to part `to` (legality is the caller's business).
  void move(int node, int to);

  template <class F>
  void for_each_member(int p, F&& f) const {
    for (int v = head_[p]; v >= 0; v = next_[v]) f(v);
  }
  template <class F>
  void for_each_neighbour(int node, F&& f) const {
    for (int k = graph_->offset[node]; k < graph_->offset[node + 1]; ++k) f(graph_->adjacency[k], graph_->weight[k]);
  }

  // When the refiners re-check their bookkeeping against reference.hpp: at the start and end of a
  // run and of each rollback pass (check_passes), and after every move too (check_moves).
  // params.debug_checks asks for every move; validate builds (core/validate.hpp) check every move on
  // graphs of at most kValidateMoveNodes nodes, where the O(n)-and-more recomputations stay cheap,
  // and the passes on larger ones.
  static constexpr int kValidateMoveNodes = 100;
  bool check_passes() const { return checks_ != Checks::None; }
  bool check_moves() const { return checks_ == Checks::Moves; }
  // The tracked cut, part sizes and internal constraints against a recount from scratch, and the
  // partition's properties (docs/design.md#partition, with nmax raised to any part that was already
  // larger): "" or the first violation.
  std::string violation() const;
  // Throws std::logic_error naming `where` on a violation.
  void check(const char* where) const;

 private:
  void find_articulation_points(int p);

  const ConstraintGraph* graph_ = nullptr;
  Partition* partition_ = nullptr;
  int* part_of_ = nullptr;  // partition_->part_of, whose size the refiners never change
  int nmax_ = 0;
  enum class Checks : char { None, Passes, Moves } checks_ = Checks::None;
  int check_nmax_ = 0;  // nmax for check_partition: parts given larger than nmax may stay so
  WeightSum cut_ = 0;
  std::vector<int> size_;
  std::vector<WeightSum> internal_;  // node -> constraints to its own part
  // Members of each part as doubly linked lists through the nodes (parts may be larger than nmax
  // when given so, so no fixed-size slots).
  std::vector<int> head_, next_, prev_;

  Connections connections_;
  std::vector<int> slot_;  // part -> index in connections_.external, -1 when untouched

  // Articulation points per part (Hopcroft–Tarjan) with the depth-first tree they come from,
  // recomputed lazily for the parts a move touched.
  std::vector<char> articulation_, articulation_fresh_;
  std::vector<int> discovery_, low_, dfs_parent_, subtree_size_;
  std::vector<std::pair<int, int>> dfs_stack_;  // (node, next edge)
  std::vector<std::pair<int, bool>> pieces_;    // swap_keeps_connected: (subtree root, reached)
  // can_leave's search: seen_[v] == stamp_ marks a neighbour still to reach, stamp_ + 1 a visit.
  std::vector<int> seen_, queue_;
  int stamp_ = 0;
};

}  // namespace rbpart
