#pragma once
// The monolithic direct solve of one island (direct.cpp, DESIGN.md §3), shared with the
// substructured solver, which uses it for islands that are a single sub-system, and its backend as
// the counted fallback when the interface/sub-system iteration does not settle (DESIGN.md §7).
#include <rbpart/params.hpp>

#include "assembly/rows.hpp"
#include "solve/blcp.hpp"
#include "solve/island_system.hpp"
#include "graph/islands.hpp"
#include "scene/bodies.hpp"

#include <memory>
#include <vector>

namespace rbpart {

struct IslandOutcome {
  int iterations = 0, passes = 0, factorizations = 0;
  bool newton = false, failed = false;
  bool unsettled = false;  // the friction loop ended above its tolerance (impulses approximate)
  double residual = 0;

  // Counts a fixed-bounds solve on the monolithic backend; returns whether it converged.
  bool count(const BlcpResult& r) {
    iterations += r.iterations;
    factorizations += r.factorizations;
    newton = newton || r.newton;
    return r.converged;
  }
  // Counts the coupled step's pivots as iterations (each one Woodbury solve on the factor of A_FF)
  // and its factorisations, over all calls on `ws`.
  void count(const CoupledWorkspace& ws) {
    iterations += ws.events;
    factorizations += ws.factorizations;
  }
};

// The BLCP core's settings from the solver's parameters (every solver's friction loop uses them).
BlcpSettings blcp_settings(const SolverParams& params);

// The monolithic solver's factorisation of an island's A (direct.cpp): dense, body-space or CHOLMOD.
std::unique_ptr<BlcpMatrix> make_direct_matrix(const IslandSystem& s, const SolverParams& params);

// Solves island `island` (friction outer loop around the fixed-bounds BLCP core), warm started from
// rows.lambda/state, and writes the impulses, sets and final friction bounds back into `rows`.
// `local_row` is local_row_index(rows, islands).
IslandOutcome solve_island(Rows& rows, const Bodies& bodies, const Islands& islands, int island,
                           const std::vector<int>& local_row, const SolverParams& params);

}  // namespace rbpart
