// KL refinement (docs/design.md#refine): swaps βi ∈ a ↔ βj ∈ b between adjacent parts, gain
// α = D_i + D_j − 2c with D = E − I toward the other part, the legal pair of largest positive gain
// first, until no positive gain is left (the paper's greedy rule).
//
// Pairs are searched per pair of adjacent parts, not per pair of nodes. Each part caches its
// interface as (other part, D, node), sorted by other part then D descending, so a part pair's
// candidates are two sorted runs and its best swap is found by the standard KL scan: βi in
// decreasing D_i, βj in decreasing D_j, stopping as soon as D_i + D_j (an upper bound, c ≥ 0) falls
// below the best gain found. Part pairs sit in a heap keyed by their best swap.
// A swap changes the entries of βi, βj and their neighbours only (for a neighbour u in a third part
// c, only D_u toward a and b), and the shape of a and b only. So those nodes' entries are replaced
// in place, and only the pairs of a or b are searched again: per swap O(deg · (deg + e)) for the
// caches of e entries each and O(q · s) for the q part pairs of a and b, where a search s costs
// O(|A| + |B|) with the bound (O(|A|·|B|) at worst, |A|, |B| ≤ nmax interface nodes), plus the
// legality checks of the candidates that would become a pair's best.
#include <algorithm>
#include <stdexcept>
#include <string>

#include "refine/gain_heap.hpp"
#include "refine/reference.hpp"
#include "refine/refine.hpp"

namespace rbpart {

namespace {

// A node of one part on its interface with `other`: D = (constraints to other) − (to its own part).
struct Candidate {
  int other;
  WeightSum d;
  int node;
};

bool cache_order(const Candidate& x, const Candidate& y) {
  if (x.other != y.other) return x.other < y.other;
  if (x.d != y.d) return x.d > y.d;
  return x.node < y.node;
}

// A pair of adjacent parts a < b and its best legal swap βi ∈ a ↔ βj ∈ b while it is in the heap.
struct PartPair {
  int a, b;
  int i = -1, j = -1;
};

// Buffers kept across runs (one instance per thread): no allocation once warmed up.
class KernighanLin {
 public:
  void run(RefineState& state) {
    s_ = &state;
    const int parts = state.partition().part_count;
    // Inner vectors are cleared, not freed, so that their capacity serves the next run.
    if (static_cast<int>(cache_.size()) < parts) cache_.resize(parts);
    if (static_cast<int>(pairs_of_.size()) < parts) pairs_of_.resize(parts);
    for (int p = 0; p < parts; ++p) pairs_of_[p].clear();
    cache_fresh_.assign(parts, 0);
    pairs_.clear();
    heap_.reset(0);
    const ConstraintGraph& g = s_->graph();
    for (int v = 0; v < g.node_count(); ++v)
      s_->for_each_neighbour(v, [&](int u, int) {
        if (s_->part(v) < s_->part(u)) pair_id(s_->part(v), s_->part(u));
      });
    for (int r = 0; r < static_cast<int>(pairs_.size()); ++r) search(r);
    if (s_->check_passes()) check_swaps("KL start");

    while (!heap_.empty()) {
      const int r = heap_.top();
      const WeightSum gain = heap_.key(r).gain;
      const PartPair swap = pairs_[r];
      // Part pairs to search again: every pair of a or b, adjacent before the swap (its best may be
      // gone) or after. No other pair changes: a neighbour u of βi in a third part c sees only its D
      // toward a and b change, which are pairs of a and b, and only a and b change shape.
      stale_.clear();
      collect_pairs(swap.a);
      collect_pairs(swap.b);
      drop_entries(swap.i);
      drop_entries(swap.j);
      s_->move(swap.i, swap.b);
      s_->move(swap.j, swap.a);
      s_->add_to_cut(-gain);
      // Only βi, βj and their neighbours have other constraints per part now.
      add_entries(swap.i);
      add_entries(swap.j);
      for (int x : {swap.i, swap.j})
        s_->for_each_neighbour(x, [&](int u, int) {
          if (u != swap.i && u != swap.j) {
            drop_entries(u);
            add_entries(u);
          }
        });
      collect_pairs(swap.a);
      collect_pairs(swap.b);
      std::sort(stale_.begin(), stale_.end());
      stale_.erase(std::unique(stale_.begin(), stale_.end()), stale_.end());
      for (int q : stale_) search(q);
      if (s_->check_moves()) {
        s_->check("KL swap");
        check_swaps("KL swap");
      }
    }
    if (s_->check_passes()) check_swaps("KL end");  // no part pair has a positive legal swap left
  }

 private:
  // The index of part pair a < b in pairs_, made on first use.
  int pair_id(int a, int b) {
    for (const auto& [other, id] : pairs_of_[a])
      if (other == b) return id;
    const int id = static_cast<int>(pairs_.size());
    pairs_.push_back({a, b});
    pairs_of_[a].emplace_back(b, id);
    heap_.grow(id + 1);
    return id;
  }

  void refresh(int p) {
    if (cache_fresh_[p]) return;
    std::vector<Candidate>& cache = cache_[p];
    cache.clear();
    s_->for_each_member(p, [&](int x) {
      const Connections& c = s_->connections(x);
      for (const auto& [q, w] : c.external) cache.push_back({q, w - c.internal, x});
    });
    std::sort(cache.begin(), cache.end(), cache_order);
    cache_fresh_[p] = 1;
  }

  // Removes node u's entries from its part's cache (a cache not made yet is made whole when needed).
  void drop_entries(int u) {
    const int p = s_->part(u);
    if (!cache_fresh_[p]) return;
    std::vector<Candidate>& entries = cache_[p];
    entries.erase(std::remove_if(entries.begin(), entries.end(), [u](const Candidate& e) { return e.node == u; }),
                  entries.end());
  }

  // Inserts node u's entries into its part's cache, in cache_order.
  void add_entries(int u) {
    const int p = s_->part(u);
    if (!cache_fresh_[p]) return;
    std::vector<Candidate>& entries = cache_[p];
    const Connections& c = s_->connections(u);
    for (const auto& [q, w] : c.external) {
      const Candidate e{q, w - c.internal, u};
      entries.insert(std::upper_bound(entries.begin(), entries.end(), e, cache_order), e);
    }
  }

  // The pairs of part p with each part it is adjacent to, into stale_.
  void collect_pairs(int p) {
    refresh(p);
    const std::vector<Candidate>& cache = cache_[p];
    for (std::size_t k = 0; k < cache.size(); ++k)
      if (k == 0 || cache[k].other != cache[k - 1].other)
        stale_.push_back(pair_id(std::min(p, cache[k].other), std::max(p, cache[k].other)));
  }

  // Part p's candidates toward part q, D descending.
  std::pair<const Candidate*, const Candidate*> run_of(int p, int q) {
    refresh(p);
    const auto range = std::equal_range(cache_[p].begin(), cache_[p].end(), Candidate{q, 0, 0},
                                        [](const Candidate& x, const Candidate& y) { return x.other < y.other; });
    return {cache_[p].data() + (range.first - cache_[p].begin()), cache_[p].data() + (range.second - cache_[p].begin())};
  }

  // The best legal swap of part pair r, by the KL scan with the bound D_i + D_j ≥ gain; re-keys r.
  void search(int r) {
    PartPair& pair = pairs_[r];
    const auto [a_begin, a_end] = run_of(pair.a, pair.b);
    const auto [b_begin, b_end] = run_of(pair.b, pair.a);
    GainKey best{0, 0, 0};
    bool found = false;
    for (const Candidate* x = a_begin; x != a_end && b_begin != b_end; ++x) {
      for (const Candidate* y = b_begin; y != b_end; ++y) {
        const WeightSum bound = x->d + y->d;
        // A tie in gain may still win on node indices, so only a strictly lower bound stops.
        if (bound <= 0 || (found && bound < best.gain)) break;
        const GainKey key{bound - 2 * WeightSum{s_->edge_weight(x->node, y->node)}, std::min(x->node, y->node),
                          std::max(x->node, y->node)};
        if (key.gain <= 0 || (found && !precedes(key, best))) continue;
        if (!s_->swap_keeps_connected(pair.a, x->node, y->node) || !s_->swap_keeps_connected(pair.b, y->node, x->node))
          continue;
        best = key;
        found = true;
        pair.i = x->node;
        pair.j = y->node;
      }
      if (x->d + b_begin->d <= 0 || (found && x->d + b_begin->d < best.gain)) break;
    }
    if (found) heap_.set(r, best);
    else heap_.erase(r);
  }

  // Every part pair's heap entry against the best swaps recomputed from scratch.
  void check_swaps(const char* where) const {
    const auto best = refine_reference::best_swaps(s_->graph(), s_->partition().part_of, s_->partition().part_count);
    std::size_t held = 0;
    for (int r = 0; r < static_cast<int>(pairs_.size()); ++r) {
      if (!heap_.contains(r)) continue;
      ++held;
      const PartPair& p = pairs_[r];
      const auto found = best.find({p.a, p.b});
      const GainKey& key = heap_.key(r);
      if (found == best.end() || found->second.gain != key.gain || found->second.first != key.first ||
          found->second.second != key.second || std::min(p.i, p.j) != key.first || std::max(p.i, p.j) != key.second)
        throw std::logic_error(std::string(where) + ": parts " + std::to_string(p.a) + "-" + std::to_string(p.b) +
                               " hold swap " + std::to_string(p.i) + "<->" + std::to_string(p.j) + " of gain " +
                               std::to_string(key.gain) + ", not the best swap recomputed");
    }
    if (held != best.size())
      throw std::logic_error(std::string(where) + ": " + std::to_string(best.size()) +
                             " part pairs have a positive swap, the heap holds " + std::to_string(held));
  }

  RefineState* s_ = nullptr;
  std::vector<std::vector<Candidate>> cache_;  // part -> interface candidates in cache_order
  std::vector<char> cache_fresh_;
  std::vector<PartPair> pairs_;
  std::vector<std::vector<std::pair<int, int>>> pairs_of_;  // part a -> (b > a, index in pairs_)
  GainHeap heap_;                                           // part pairs with a positive legal swap
  std::vector<int> stale_;
};

}  // namespace

void refine_kernighan_lin(RefineState& state) {
  thread_local KernighanLin kl;
  kl.run(state);
}

}  // namespace rbpart
