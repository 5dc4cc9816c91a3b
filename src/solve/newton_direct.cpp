// The Newton solver (newton.hpp, DESIGN.md §3) on the monolithic backend (monolithic.hpp), per
// island, islands in parallel: `--solver newton`.
#include "solve/solve.hpp"

#include "solve/island_system.hpp"
#include "solve/monolithic.hpp"
#include "solve/newton_island.hpp"

namespace rbpart {

SolveReport solve_newton_direct(Rows& rows, const Bodies& bodies, const Islands& islands, const SolverParams& params) {
  const std::vector<int> local_row = local_row_index(rows, islands);
  std::vector<NewtonResult> outcome(islands.count());
  for_each_island(islands, [&](int i) {
    IslandSystem s;
    s.gather(rows, bodies, islands, i, local_row);
    MonolithicSystem system;
    system.assign(s, params.dense_max_bodies);
    outcome[i] = solve_island_newton(s, system, params.max_factorizations, rows);
  });

  SolveReport report;
  for (const NewtonResult& o : outcome) add_island_result(o, report);
  return report;
}

}  // namespace rbpart
