// The direct solver: the Newton solver (newton.hpp, DESIGN.md §3) on the monolithic backend
// (monolithic.hpp), per island, islands in parallel: `--solver direct`.
#include "solve/solve.hpp"

#include "solve/island_cache.hpp"
#include "solve/newton_island.hpp"

namespace rbpart {

SolveStats solve_newton_direct(Rows& rows, const Bodies& bodies, const Islands& islands, const SolverParams& params,
                               DirectCache* cache) {
  DirectCache this_step;
  DirectCache& kept = cache ? *cache : this_step;
  local_row_index(rows, islands, kept.local_row);
  const std::vector<IslandSlot<MonolithicSystem>*>& slots = kept.slots_for(islands);
  for_each_island(islands, kept.island_order, [&](int i) {
    IslandSlot<MonolithicSystem>& slot = *slots[i];
    slot.system.gather(rows, bodies, islands, i, kept.local_row);
    slot.backend.assign(slot.system);
    slot.result = solve_island_newton(slot.system, slot.backend, params.max_factorizations, rows, slot.workspace);
  });

  SolveStats stats;
  for (const IslandSlot<MonolithicSystem>* slot : slots) add_island_result(slot->result, stats);
  return stats;
}

}  // namespace rbpart
