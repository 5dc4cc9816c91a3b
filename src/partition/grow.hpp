#pragma once
// Seed-and-grow, the engine shared by BFS, MinDP, MaxDP, MR, MIX and METIS's post-processing
// (docs/design.md#partition). A part starts at a seed and grows one body at a time: the body added next is
// the candidate (an unassigned body adjacent to the part) that comes first in the rule's order, until the
// part holds nmax bodies or no candidate is left; then the next seed starts a new part, until every body of
// the island is assigned. The rules differ only in their order and filters, so each is a small policy struct:
//
//   int64 seed_key(v)     seeds are taken in increasing (seed_key, node) order;
//   void  begin(seed)     a new part starts;
//   void  joined(v)       v joined the part (before its neighbours are offered);
//   bool  offer(u)        u became a candidate: true queues it now, false lets the rule hold it;
//   bool  rekeys()        whether a joining neighbour changes candidates' keys (they are re-queued);
//   int64 key(u)          candidates leave the queue in increasing (key, node) order;
//   bool  admit(u)        checked when u leaves the queue; false drops u for the rest of the part.
//
// The queue is a binary heap with lazy deletion: an entry whose key is no longer the candidate's
// key, or whose body has joined, is skipped when popped. A push follows the scan of an edge of a
// joining body (MR's releases and MIX's switch re-push bodies already pushed), and every body joins
// once, so growing all parts costs O((n + m) log n).
#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>

#include "graph/constraint_graph.hpp"
#include "partition/partition.hpp"

namespace rbpart {

// Per-node scratch of the growth, sized for one graph and reused across parts (and across calls:
// partition_graph keeps one per thread, so a warmed-up step does not allocate).
struct GrowState {
  const ConstraintGraph* graph = nullptr;
  int nmax = 0;
  std::vector<int>* part_of = nullptr;  // the output: -1 while unassigned
  int part_count = 0;

  // Per node, packed so that offering a neighbour touches one cache line besides part_of. The
  // candidate fields are valid while seen == the current part id (no clearing between parts).
  struct Node {
    WeightSum degree;  // constraints to other dynamic bodies (docs/design.md#graph)
    WeightSum conn;    // constraints from the candidate into that part
    int seen;          // last part that discovered the node as a candidate
    int seq;           // discovery order within that part (breadth-first order)
  };
  std::vector<Node> node;
  std::vector<int> candidates;  // discovered by the current part, in discovery order
  int size = 0;                 // bodies in the current part

  struct Entry {
    std::int64_t key;
    int node;
    bool operator>(const Entry& o) const { return key != o.key ? key > o.key : node > o.node; }
  };
  std::vector<Entry> heap;  // min-heap of (key, node)
  std::vector<int> order;   // an island's seeds in order
  std::vector<int> bucket;  // counting sort of the seeds
  std::vector<int> label;   // free for a partitioner's own per-node data (METIS: its part)

  void reset(const ConstraintGraph& g, int nmax_, std::vector<int>& out) {
    graph = &g;
    nmax = nmax_;
    part_of = &out;
    part_count = 0;
    const int n = g.node_count();
    node.resize(n);
    for (int v = 0; v < n; ++v) node[v] = {g.degree(v), 0, -1, 0};
    label.resize(n);
  }
  void push(std::int64_t key, int u) {
    heap.push_back({key, u});
    std::push_heap(heap.begin(), heap.end(), std::greater<Entry>());
  }
  Entry pop() {
    std::pop_heap(heap.begin(), heap.end(), std::greater<Entry>());
    const Entry e = heap.back();
    heap.pop_back();
    return e;
  }
  // Whether u is a live candidate of the current part.
  bool is_candidate(int u) const { return node[u].seen == part_count - 1 && (*part_of)[u] < 0; }
};

// Adds v to the current part and offers its unassigned neighbours (in increasing node order, so a
// breadth-first order visits neighbours in natural body order).
template <class Rule>
void join_part(GrowState& s, Rule& rule, int v) {
  const ConstraintGraph& g = *s.graph;
  std::vector<int>& part_of = *s.part_of;
  const int part = s.part_count - 1;
  part_of[v] = part;
  ++s.size;
  rule.joined(v);
  for (int k = g.offset[v]; k < g.offset[v + 1]; ++k) {
    const int u = g.adjacency[k];
    if (part_of[u] >= 0) continue;
    GrowState::Node& c = s.node[u];
    const bool first = c.seen != part;
    if (first) {
      c = {c.degree, 0, part, static_cast<int>(s.candidates.size())};
      s.candidates.push_back(u);
    }
    c.conn += g.weight[k];
    if (first ? rule.offer(u) : rule.rekeys()) s.push(rule.key(u), u);
  }
}

// Grows one part from `seed` (docs/design.md#partition: growth stops at nmax or when no candidate is left).
template <class Rule>
void grow_part(GrowState& s, Rule& rule, int seed) {
  ++s.part_count;
  s.size = 0;
  s.heap.clear();
  s.candidates.clear();
  rule.begin(seed);
  join_part(s, rule, seed);
  while (s.size < s.nmax && !s.heap.empty()) {
    const GrowState::Entry e = s.pop();
    if ((*s.part_of)[e.node] >= 0 || e.key != rule.key(e.node)) continue;  // joined, or a stale key
    if (rule.admit(e.node)) join_part(s, rule, e.node);
  }
}

// Partitions the connected island `nodes` (increasing order): every unassigned body, in seed order,
// seeds a part. Bodies a part left unassigned are thus grown into later parts by the same rule.
template <class Rule>
void grow_island(GrowState& s, Rule& rule, const int* nodes, int count) {
  // Seed order by a counting sort of the keys (degrees, or one constant: ranges of O(count)), which
  // keeps equal keys in increasing node order; a comparison sort if the range is large.
  if (count <= 0) return;
  std::int64_t lo = rule.seed_key(nodes[0]), hi = lo;
  for (int i = 1; i < count; ++i) {
    lo = std::min(lo, rule.seed_key(nodes[i]));
    hi = std::max(hi, rule.seed_key(nodes[i]));
  }
  s.order.resize(count);
  if (hi - lo <= 4 * std::int64_t{count}) {
    s.bucket.assign(hi - lo + 2, 0);
    for (int i = 0; i < count; ++i) ++s.bucket[rule.seed_key(nodes[i]) - lo + 1];
    for (std::size_t b = 1; b < s.bucket.size(); ++b) s.bucket[b] += s.bucket[b - 1];
    for (int i = 0; i < count; ++i) s.order[s.bucket[rule.seed_key(nodes[i]) - lo]++] = nodes[i];
  } else {
    s.order.assign(nodes, nodes + count);
    std::sort(s.order.begin(), s.order.end(), [&rule](int a, int b) {
      const std::int64_t ka = rule.seed_key(a), kb = rule.seed_key(b);
      return ka != kb ? ka < kb : a < b;
    });
  }
  for (int v : s.order)
    if ((*s.part_of)[v] < 0) grow_part(s, rule, v);
}

// Defaults for the hooks most rules leave alone.
struct RuleBase {
  void begin(int) {}
  void joined(int) {}
  bool offer(int) { return true; }
  bool rekeys() const { return false; }
  bool admit(int) { return true; }
};

// Breadth-first order: candidates leave the queue in discovery order (BFS, MR, METIS pieces).
struct BreadthFirstOrder : RuleBase {
  const GrowState& s;
  explicit BreadthFirstOrder(const GrowState& state) : s(state) {}
  std::int64_t seed_key(int) const { return 0; }  // lowest-index unassigned body
  std::int64_t key(int u) const { return s.node[u].seq; }
};

// Degree order (MinDP: sign +1, MaxDP: sign -1): the seed and every next body are those of minimum
// (maximum) degree among the unassigned bodies / the candidates, ties to the lowest index.
struct DegreeOrder : RuleBase {
  const GrowState& s;
  int sign;
  DegreeOrder(const GrowState& state, int sign_) : s(state), sign(sign_) {}
  std::int64_t seed_key(int v) const { return sign * std::int64_t{s.node[v].degree}; }
  std::int64_t key(int u) const { return seed_key(u); }
};

// The partitioners' island entry points (one file each), called by partition_graph for every
// island of more than nmax bodies; they append parts to s.part_count.
void partition_island_bfs(GrowState& s, const PartitionParams& params, const int* nodes, int count);
void partition_island_min_dp(GrowState& s, const PartitionParams& params, const int* nodes, int count);
void partition_island_max_dp(GrowState& s, const PartitionParams& params, const int* nodes, int count);
void partition_island_mr(GrowState& s, const PartitionParams& params, const int* nodes, int count);
void partition_island_mix(GrowState& s, const PartitionParams& params, const int* nodes, int count);
void partition_island_metis(GrowState& s, const PartitionParams& params, const int* nodes, int count);

}  // namespace rbpart
