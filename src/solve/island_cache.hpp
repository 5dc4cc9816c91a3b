#pragma once
// Per-island state of the Newton solver kept from one step to the next (DESIGN.md §3: symbolic
// analysis reused across iterations and steps, no allocation per step once warm). An island is
// matched to the last step's by its first body. When its body-space pattern is unchanged (a
// resting island), its CHOLMOD or KLU analysis is reused (KLU's pivots are searched afresh:
// pattern_factor.hpp); its buffers keep their capacity either way.
#include "graph/islands.hpp"
#include "solve/island_system.hpp"
#include "solve/monolithic.hpp"
#include "solve/newton.hpp"

#include <memory>
#include <unordered_map>
#include <vector>

namespace rbpart {

struct IslandSlot {
  IslandSystem system;
  MonolithicSystem backend;
  NewtonWorkspace workspace;
  bool used = false;  // by an island of the current step (slots_for)
};

class IslandCache {
 public:
  // A slot per island of `islands`, in island order: the last step's slot of the island's first
  // body if there was one, else a new one. Slots of islands that are gone are freed.
  std::vector<IslandSlot*> slots_for(const Islands& islands);

 private:
  std::unordered_map<int, std::unique_ptr<IslandSlot>> slots_;
};

}  // namespace rbpart
