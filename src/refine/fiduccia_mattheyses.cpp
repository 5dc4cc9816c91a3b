// FM refinement (docs/design.md#refine): single moves of interface bodies with gain α = E − I, the greedy
// rule of the paper and classic Fiduccia–Mattheyses passes with rollback (an extension).
//
// Every node that may go somewhere (an edge to another part that is not full) sits in a gain heap
// keyed by its best move (gain, node). After every move, rollback included, only what the move can
// change is re-keyed:
//  - the moved node and its neighbours (their constraints per part changed): O(deg) each;
//  - when the source part stops being full, the nodes next to it that may now enter it: one sweep
//    over the part's edges sums their constraints into it, O(nmax · deg), no per-node rescans.
// When the target part becomes full, the keys of the nodes whose best move was into it are left as
// they are: a key can only have dropped, so keys stay upper bounds of the true best gains, exact for
// every node whose target is not full. The top is re-keyed if its target is full and used only when
// exact, and then no other node can do better. This saves re-keying a whole part's neighbourhood,
// most of it never popped.
// Whether the top node may leave its part (not the last node, not an articulation point) is asked
// when it is popped; a node that may not is parked and re-keyed when its part next changes, the only
// event that can free it. A move costs O((deg² + nmax · deg) log n).
#include <algorithm>
#include <stdexcept>
#include <string>

#include "refine/gain_heap.hpp"
#include "refine/reference.hpp"
#include "refine/refine.hpp"

namespace rbpart {

namespace {

// Buffers kept across runs (one instance per thread): no allocation once warmed up.
class FiducciaMattheyses {
 public:
  void run(RefineState& state, bool rollback) {
    s_ = &state;
    rollback_ = rollback;
    n_ = state.graph().node_count();
    heap_.reset(n_);
    target_.assign(n_, -1);
    locked_.assign(n_, 0);
    parked_.assign(n_, 0);
    swept_.assign(n_, 0);
    for (int v = 0; v < n_; ++v) update(v);
    if (s_->check_passes()) check_gains("FM start");
    if (!rollback_) {
      while (!heap_.empty() && heap_.key(heap_.top()).gain > 0) step();
      if (s_->check_passes()) check_gains("FM end");
      return;
    }
    while (pass()) {
    }
  }

 private:
  struct Step {
    int node, from;
  };

  // Takes the top of the heap: re-keys it if its target has filled up, else makes its move if the
  // node may leave its part, else parks the node.
  void step() {
    const int v = heap_.top();
    if (s_->full(target_[v])) {
      update(v);
      return;
    }
    heap_.erase(v);
    if (!s_->can_leave(v)) {
      parked_[v] = 1;
      if (rollback_) parked_list_.push_back(v);
      return;
    }
    if (s_->check_moves() && !refine_reference::can_leave(s_->graph(), s_->partition().part_of, v))
      throw std::logic_error("FM: node " + std::to_string(v) + " moved although it disconnects its part");
    if (rollback_) {
      locked_[v] = 1;
      log_.push_back({v, s_->part(v)});
    }
    apply(v, target_[v]);
    if (s_->check_moves()) {
      s_->check("FM move");
      check_gains("FM move");
    }
  }

  // One classic FM pass: the moves the heap offers, whatever their gain, each node at most once; then
  // back to the pass's best prefix (lowest cut, ties to the shorter prefix). Returns whether the
  // cut went down. As practical FM implementations do, the pass ends early once it has gone
  // max(200, n/20) moves past its best prefix: the moves are ordered by gain over the whole graph,
  // so an improvement spanning several moves is interleaved with moves elsewhere and the distance
  // grows with n. On piles of 4·10³ and 4·10⁴ nodes this gives the cut of unbounded passes with
  // 6-9 times fewer moves (docs/refinement.md).
  bool pass() {
    const WeightSum start_cut = s_->cut();
    const std::size_t patience = std::max<std::size_t>(200, n_ / 20);
    WeightSum best_cut = start_cut;
    std::size_t best_length = 0;
    log_.clear();
    parked_list_.clear();
    while (!heap_.empty() && log_.size() - best_length <= patience) {
      step();
      if (s_->cut() < best_cut) {
        best_cut = s_->cut();
        best_length = log_.size();
      }
    }
    // Unlock and unpark everything, undo the moves past the best prefix newest first (every state on
    // the way back was a legal partition) with the same bookkeeping, and re-key what was held out.
    for (const Step& m : log_) locked_[m.node] = 0;
    for (int v : parked_list_) parked_[v] = 0;
    for (std::size_t k = log_.size(); k-- > best_length;) apply(log_[k].node, log_[k].from);
    for (const Step& m : log_) update(m.node);
    for (int v : parked_list_) update(v);
    if (s_->check_passes()) {
      if (s_->cut() != best_cut) throw std::logic_error("FM rollback: the cut is not the best prefix's");
      s_->check("FM rollback");
      check_gains("FM rollback");
    }
    return best_cut < start_cut;
  }

  // Re-keys v by its best move; a locked or parked node stays out of the heap.
  void update(int v) {
    if (locked_[v] || parked_[v]) return;
    const BestMove m = s_->best_move(v);
    target_[v] = m.target;
    if (m.target < 0) heap_.erase(v);
    else heap_.set(v, {m.gain, v, 0});
  }

  // Moves v to part `to` and re-keys what the move changed.
  void apply(int v, int to) {
    const int from = s_->part(v);
    const bool from_was_full = s_->full(from);
    WeightSum external = 0;
    s_->for_each_neighbour(v, [&](int u, int w) { external += s_->part(u) == to ? w : 0; });
    s_->add_to_cut(s_->internal(v) - external);  // the gain E − I comes off the cut
    s_->move(v, to);
    update(v);
    s_->for_each_neighbour(v, [&](int u, int) { update(u); });
    unpark(from);
    unpark(to);
    if (from_was_full && !s_->full(from)) opened(from);
  }

  // Part p changed: its parked nodes may be free to leave now.
  void unpark(int p) {
    s_->for_each_member(p, [&](int x) {
      if (!parked_[x]) return;
      parked_[x] = 0;
      update(x);
    });
  }

  // Part p can take a node again: offer it to every node of another part with an edge into it, at
  // gain (constraints into p, summed over p's edges) − (constraints to its own part).
  void opened(int p) {
    swept_list_.clear();
    s_->for_each_member(p, [&](int x) {
      s_->for_each_neighbour(x, [&](int u, int w) {
        if (s_->part(u) == p) return;
        if (swept_[u] == 0) swept_list_.push_back(u);
        swept_[u] += w;
      });
    });
    for (int u : swept_list_) {
      const WeightSum gain = swept_[u] - s_->internal(u);
      swept_[u] = 0;
      if (locked_[u] || parked_[u]) continue;
      if (!heap_.contains(u) || gain > heap_.key(u).gain || (gain == heap_.key(u).gain && p < target_[u])) {
        heap_.set(u, {gain, u, 0});
        target_[u] = p;
      }
    }
  }

  // Every free node's heap key and target against a recomputation from scratch (exact when the
  // target is not full, an upper bound when it is); every parked node indeed unable to leave.
  void check_gains(const char* where) const {
    const auto& part_of = s_->partition().part_of;
    const auto best = refine_reference::best_moves(s_->graph(), part_of, s_->partition().part_count, s_->nmax());
    auto fail = [&](int v, const std::string& what) {
      throw std::logic_error(std::string(where) + ": node " + std::to_string(v) + ": " + what);
    };
    for (int v = 0; v < n_; ++v) {
      if (locked_[v]) continue;
      if (parked_[v]) {
        if (refine_reference::can_leave(s_->graph(), part_of, v)) fail(v, "parked although free to leave");
        continue;
      }
      if (heap_.contains(v) && s_->full(target_[v])) {
        if (best[v] && best[v]->gain > heap_.key(v).gain) fail(v, "kept key below the best gain");
        continue;
      }
      if (!best[v]) {
        if (heap_.contains(v)) fail(v, "in the gain heap without a legal target");
        continue;
      }
      if (!heap_.contains(v)) fail(v, "missing from the gain heap");
      if (heap_.key(v).gain != best[v]->gain || target_[v] != best[v]->second)
        fail(v, "gain " + std::to_string(heap_.key(v).gain) + " to part " + std::to_string(target_[v]) +
                    ", recomputed " + std::to_string(best[v]->gain) + " to part " + std::to_string(best[v]->second));
    }
  }

  RefineState* s_ = nullptr;
  bool rollback_ = false;
  int n_ = 0;
  GainHeap heap_;
  std::vector<int> target_;            // node -> target of its keyed move (-1: none)
  std::vector<char> locked_, parked_;  // moved this pass (rollback); may not leave its part
  std::vector<int> parked_list_;       // parked this pass (rollback), to re-key at its end
  std::vector<Step> log_;              // this pass's moves (rollback)
  std::vector<WeightSum> swept_;
  std::vector<int> swept_list_;  // opened(): node -> constraints into the opened part
};

}  // namespace

void refine_fiduccia_mattheyses(RefineState& state, bool rollback) {
  thread_local FiducciaMattheyses fm;
  fm.run(state, rollback);
}

}  // namespace rbpart
