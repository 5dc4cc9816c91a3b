#pragma once
// How the solve stage runs the Newton solver (newton.hpp) on its islands, whatever the backend
// (linear_system.hpp): islands in parallel, the largest first, each warm started from the rows'
// impulses and states and its answer written back.
#include "assembly/rows.hpp"
#include "core/parallel.hpp"
#include "graph/islands.hpp"
#include "solve/island_system.hpp"
#include "solve/linear_system.hpp"
#include "solve/newton.hpp"
#include "solve/solve.hpp"

namespace rbpart {

// Calls fn(island) for every island, islands in parallel, the largest first (`order`: the
// caller's buffer for that order).
template <class Fn>
void for_each_island(const Islands& islands, std::vector<int>& order, Fn&& fn) {
  largest_islands_first(islands, order);
  parallel_for_each(islands.count(), [&](std::size_t t) { fn(order[t]); });
}

// The island's warm start: its rows' impulses and states from `rows`, in island numbering.
void island_warm_start(const IslandSystem& s, const Rows& rows, Eigen::VectorXd& lambda, std::vector<RowState>& state);

// Solves island `s` with `system` (assigned to s) and writes the impulses, states and final
// friction bounds (into s.lo/s.hi too) of its answer into `rows`. Islands own disjoint rows, so
// islands may run this in parallel on the same `rows`.
NewtonResult solve_island_newton(IslandSystem& s, LinearSystem& system, int max_factorizations, Rows& rows,
                                 NewtonWorkspace& ws);

// Adds one island's result to the solve stage's statistics.
void add_island_result(const NewtonResult& result, SolveStats& stats);

}  // namespace rbpart
