#pragma once
// The refiners' priority queue of moves (docs/design.md#refine: gain buckets with incremental updates).
// Gains are small integers, so bucket lists would do for the gain alone, but the tie rule (the
// lowest node index wins) needs an order inside a bucket, which lists give only by scanning the
// bucket. An indexed binary heap keeps the whole order (gain, then the tie-breaks) and updates an
// item in O(log n): O(m log n) for a pass instead of O(m), with small constants.
#include <vector>

#include "graph/constraint_graph.hpp"

namespace rbpart {

// Larger gain first; ties go to the smaller `first`, then the smaller `second`.
struct GainKey {
  WeightSum gain = 0;
  int first = 0, second = 0;
};

inline bool precedes(const GainKey& x, const GainKey& y) {
  if (x.gain != y.gain) return x.gain > y.gain;
  if (x.first != y.first) return x.first < y.first;
  return x.second < y.second;
}

// Items are 0..capacity-1 (nodes, or KL's part pairs); each is in the heap at most once.
class GainHeap {
 public:
  // Empties the heap and admits items 0..capacity-1.
  void reset(int capacity) {
    heap_.clear();
    pos_.assign(capacity, -1);
    key_.resize(capacity);
  }
  // Admits items up to capacity-1, keeping the ones held.
  void grow(int capacity) {
    if (capacity <= static_cast<int>(pos_.size())) return;
    pos_.resize(capacity, -1);
    key_.resize(capacity);
  }

  bool empty() const { return heap_.empty(); }
  bool contains(int item) const { return pos_[item] >= 0; }
  int top() const { return heap_.front(); }
  const GainKey& key(int item) const { return key_[item]; }

  // Inserts `item` or changes its key.
  void set(int item, const GainKey& key) {
    if (pos_[item] < 0) {
      pos_[item] = static_cast<int>(heap_.size());
      heap_.push_back(item);
      key_[item] = key;
      sift_up(pos_[item]);
      return;
    }
    const bool up = precedes(key, key_[item]);
    key_[item] = key;
    if (up) sift_up(pos_[item]);
    else sift_down(pos_[item]);
  }

  void erase(int item) {
    const int at = pos_[item];
    if (at < 0) return;
    pos_[item] = -1;
    const int last = heap_.back();
    heap_.pop_back();
    if (last == item) return;
    heap_[at] = last;
    pos_[last] = at;
    sift_up(at);
    sift_down(pos_[last]);
  }

 private:
  void place(int at, int item) {
    heap_[at] = item;
    pos_[item] = at;
  }
  void sift_up(int at) {
    const int item = heap_[at];
    while (at > 0) {
      const int parent = (at - 1) / 2;
      if (!precedes(key_[item], key_[heap_[parent]])) break;
      place(at, heap_[parent]);
      at = parent;
    }
    place(at, item);
  }
  void sift_down(int at) {
    const int item = heap_[at];
    const int n = static_cast<int>(heap_.size());
    for (;;) {
      int child = 2 * at + 1;
      if (child >= n) break;
      if (child + 1 < n && precedes(key_[heap_[child + 1]], key_[heap_[child]])) ++child;
      if (!precedes(key_[heap_[child]], key_[item])) break;
      place(at, heap_[child]);
      at = child;
    }
    place(at, item);
  }

  std::vector<int> heap_;    // items in heap order
  std::vector<int> pos_;     // item -> index in heap_, -1 when absent
  std::vector<GainKey> key_; // item -> key (meaningful while present)
};

}  // namespace rbpart
