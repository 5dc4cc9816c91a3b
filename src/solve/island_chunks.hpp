#pragma once
// The Newton solver's own vector work on an island (A x, the natural map, the Newton states, the
// refinement's residuals, the interior point's updates) in chunks of rows or of bodies, each chunk
// timed, in parallel on large islands: the substructured solver's critical path (DESIGN.md §7)
// then counts a loop's slowest chunk, not the whole loop. One chunk (the default) runs every loop
// serially and untimed. A loop body writes only its own row's or body's entries; the reductions
// are a min and a sum over fixed blocks of rows added in block order, so results do not depend on
// the chunks or the threads.
#include "core/parallel.hpp"
#include "core/timer.hpp"

#include <algorithm>
#include <limits>
#include <vector>

namespace rbpart {

// Work whose items are independent (rows, bodies, a factorisation's updates) is split in this
// many chunks for the substructured solver's critical path: the most cores the study estimates a
// solve's time for (study/report.hpp).
constexpr int kMaxChunks = 16;
// An island's (or a part's) loops run in at most kMaxChunks chunks (their rows are independent, so
// the partition does not bound how finely they split), but never in chunks of fewer rows than
// this, so that timing a chunk (two clock reads, ~60 ns) stays small beside it: with 64 rows a
// chunk, Chain Drop's solve took 10 % longer at 2 threads.
constexpr int kMinRowsPerChunk = 256;
inline int chunks_for_rows(int rows, int min_rows = kMinRowsPerChunk) { return std::min(kMaxChunks, rows / min_rows); }
// A substructured part's loops (its assembly, ~36 ns a row against the Newton loops' ~5 ns) keep the
// same ratio of timing to work with fewer rows a chunk.
constexpr int kMinPartRowsPerChunk = 64;

class IslandChunks {
 public:
  // A loop over fewer items runs its chunks one after another on the calling thread, still timed
  // one by one: handing them to other threads would cost more than it saves (a few microseconds a
  // loop against ~5 ns a row), while each chunk's own time is what the critical path needs.
  static constexpr int kMinParallelItems = 4096;

  // Loops split into `chunks` equal ranges (at least one) from here on; the tallies below restart.
  void set_count(int chunks) {
    count_ = std::max(1, chunks);
    work_ms = critical_path_ms = wall_ms = 0;
    ms_.assign(count_, 0.0);
    low_.assign(count_, 0.0);
  }

  int count() const { return count_; }
  // fn(k) for every k in [0, n): n rows or n bodies (or `items` of such work in all).
  template <class Fn>
  void each(int n, Fn&& fn, int items = -1) {
    run(n, [&](int, int begin, int end) {
      for (int k = begin; k < end; ++k) fn(k);
    }, items);
  }
  // The least fn(k) over k in [0, n) (+inf if n is 0).
  template <class Fn>
  double min(int n, Fn&& fn) {
    double serial = std::numeric_limits<double>::infinity();
    run(n, [&](int c, int begin, int end) {
      double low = std::numeric_limits<double>::infinity();
      for (int k = begin; k < end; ++k) low = std::min(low, fn(k));
      (count_ == 1 ? serial : low_[c]) = low;
    });
    return count_ == 1 ? serial : *std::min_element(low_.begin(), low_.end());
  }
  // The sum of fn(k) over k in [0, n), added in blocks of kSumBlock items, then block by block, so
  // that the round-off is the same in any number of chunks.
  template <class Fn>
  double sum(int n, Fn&& fn) {
    const int blocks = (n + kSumBlock - 1) / kSumBlock;
    partial_.resize(blocks);
    run(blocks, [&](int, int begin, int end) {
      for (int b = begin; b < end; ++b) {
        double total = 0;
        for (int k = b * kSumBlock, last = std::min(n, k + kSumBlock); k < last; ++k) total += fn(k);
        partial_[b] = total;
      }
    }, n);
    double total = 0;
    for (const double v : partial_) total += v;
    return total;
  }

  // Of the loops run in more than one chunk so far: the chunks' times summed, each loop's slowest
  // chunk summed, and the loops' wall time.
  double work_ms = 0, critical_path_ms = 0, wall_ms = 0;

 private:
  static constexpr int kSumBlock = 256;

  // chunk(c, begin, end) over [0, n) in count_ ranges; `items` (default n) is the work's size in
  // rows or bodies, which decides whether the chunks run in parallel.
  template <class Chunk>
  void run(int n, Chunk&& chunk, int items = -1) {
    if (count_ == 1) {
      chunk(0, 0, n);
      return;
    }
    const Timer wall;
    const auto timed = [&](std::size_t c) {
      const Timer timer;
      const long long total = n;
      chunk(static_cast<int>(c), static_cast<int>(total * static_cast<long long>(c) / count_),
            static_cast<int>(total * static_cast<long long>(c + 1) / count_));
      ms_[c] = timer.ms();
    };
    if ((items < 0 ? n : items) >= kMinParallelItems) {
      parallel_for_each(static_cast<std::size_t>(count_), timed);
    } else {
      for (int c = 0; c < count_; ++c) timed(static_cast<std::size_t>(c));
    }
    wall_ms += wall.ms();
    double slowest = 0;
    for (const double ms : ms_) {
      work_ms += ms;
      slowest = std::max(slowest, ms);
    }
    critical_path_ms += slowest;
  }

  int count_ = 1;
  std::vector<double> ms_, low_, partial_;
};

}  // namespace rbpart
