#pragma once
// Per-island state of the Newton solver kept from one step to the next (DESIGN.md §3: symbolic
// analysis reused across iterations and steps, no allocation per step once warm), for either
// backend. An island is matched to the last step's by its first body. When its body-space patterns
// are unchanged (a resting island; for the substructured backend also the same parts), their block
// LU analyses (order and fill: block_lu.hpp) are reused; its buffers keep their capacity either
// way, so that a step whose islands keep their bodies and contacts allocates nothing
// (tests/step/warm_step_test.cpp).
#include "graph/islands.hpp"
#include "solve/island_system.hpp"
#include "solve/monolithic.hpp"
#include "solve/newton.hpp"
#include "solve/substructured_system.hpp"

#include <memory>
#include <unordered_map>
#include <vector>

namespace rbpart {

template <class Backend>
struct IslandSlot {
  IslandSystem system;
  Backend backend;
  NewtonWorkspace workspace;
  // The island's last solve: its result and, on the substructured backend, its cost (ms) and
  // parts (island body -> part; `distinct`, the part ids, is island_parts()'s scratch).
  NewtonResult result;
  double work_ms = 0, critical_path_ms = 0;
  std::vector<int> part_of_body, distinct;
  bool used = false;  // by an island of the current step (slots_for)
};

template <class Backend>
class IslandCache {
 public:
  // A slot per island of `islands`, in island order: the last step's slot of the island's first
  // body if there was one, else a new one. Slots of islands that are gone are freed. Valid until
  // the next call.
  const std::vector<IslandSlot<Backend>*>& slots_for(const Islands& islands);

  // The solve stage's own buffers (local_row_index, largest_islands_first), kept with the slots.
  std::vector<int> local_row, island_order;

 private:
  std::unordered_map<int, std::unique_ptr<IslandSlot<Backend>>> slots_;
  std::vector<IslandSlot<Backend>*> current_;
};

using DirectCache = IslandCache<MonolithicSystem>;
using SubstructuredCache = IslandCache<SubstructuredSystem>;

}  // namespace rbpart
