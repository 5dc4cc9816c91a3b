#pragma once
// The one task interface of rbpart: "for each island / part, in parallel" (oneTBB underneath).
#include <tbb/parallel_for.h>

#include <cstddef>

namespace rbpart {

// Calls fn(i) for i in [0, n). Work items must write disjoint data; grain 1 because items (islands,
// parts) are few and uneven.
template <class Fn>
void parallel_for_each(std::size_t n, Fn&& fn) {
  if (n == 0) return;
  if (n == 1) {
    fn(std::size_t{0});
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) fn(i);
  });
}

// Calls fn(i) for i in [0, n) in chunks of at least `grain` items, serially when n <= grain: for
// loops over many small items (contacts, rows), where a task per item would cost more than it.
// Work items must write disjoint data.
template <class Fn>
void parallel_for_chunked(std::size_t n, std::size_t grain, Fn&& fn) {
  if (n <= grain) {
    for (std::size_t i = 0; i < n; ++i) fn(i);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) fn(i);
  });
}

}  // namespace rbpart
