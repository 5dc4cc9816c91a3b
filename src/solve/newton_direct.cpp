// The direct solver: the Newton solver (newton.hpp, DESIGN.md §3) on the monolithic backend
// (monolithic.hpp), per island, islands in parallel: `--solver direct`.
#include "solve/solve.hpp"

#include "solve/island_cache.hpp"
#include "solve/newton_island.hpp"

namespace rbpart {

SolveStats solve_newton_direct(Rows& rows, const Bodies& bodies, const Islands& islands, const SolverParams& params,
                               DirectCache* cache) {
  const std::vector<int> local_row = local_row_index(rows, islands);
  std::vector<NewtonResult> outcome(islands.count());
  DirectCache this_step;
  const std::vector<IslandSlot<MonolithicSystem>*> slots = (cache ? *cache : this_step).slots_for(islands);
  for_each_island(islands, [&](int i) {
    IslandSlot<MonolithicSystem>& slot = *slots[i];
    slot.system.gather(rows, bodies, islands, i, local_row);
    slot.backend.assign(slot.system, params.dense_max_bodies);
    outcome[i] = solve_island_newton(slot.system, slot.backend, params.max_factorizations, rows, slot.workspace);
  });

  SolveStats stats;
  for (const NewtonResult& o : outcome) add_island_result(o, stats);
  return stats;
}

}  // namespace rbpart
