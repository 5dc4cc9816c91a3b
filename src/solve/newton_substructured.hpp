#pragma once
// The Newton solver (newton.hpp, DESIGN.md §3) on the substructured backend
// (substructured_system.hpp, DESIGN.md §7): per island, its bodies split by the partition; islands
// in parallel, and the parts of an island in parallel within each factorisation and solve. Its
// iterates are the monolithic backend's (solve_newton_direct) up to round-off.
#include <rbpart/params.hpp>

#include "assembly/rows.hpp"
#include "graph/constraint_graph.hpp"
#include "graph/islands.hpp"
#include "partition/partition.hpp"
#include "scene/bodies.hpp"
#include "solve/solve.hpp"

namespace rbpart {

template <class Backend>
class IslandCache;
class SubstructuredSystem;

struct NewtonSubstructuredReport {
  // As solve_newton_direct fills it, and work_ms: the backends' parallel and serial phases, the
  // Newton iteration's own loops over rows and bodies (in up to 16 chunks) and each island's
  // serial rest (gathering, set-up, copies); critical_path_ms: the longest island's, with every
  // parallel phase and loop at its slowest part or chunk.
  SolveStats solve;
  // Sums over islands; an island holds the parts of its bodies (a part spanning two islands counts
  // once per island), an island of one part has no interface.
  int parts = 0, interface_rows = 0, interface_bodies = 0;
  int parts_refactored = 0;  // part factorisations (a part whose rows did not change keeps its factor)
};

// Solves every island's coupled problem and writes impulses, states and final friction bounds into
// `rows`, warm started from rows.lambda/state, as solve_newton_direct does. `graph` maps scene
// bodies to nodes and `partition` gives every node a part (any assignment is valid; parts need not be
// connected). Needs sigma_j > 0 on every row, as the monolithic backend does. With `cache`
// (solve/island_cache.hpp), the islands' parts keep their analyses and buffers to the next call
// where their patterns hold.
NewtonSubstructuredReport solve_newton_substructured(Rows& rows, const Bodies& bodies, const Islands& islands,
                                                     const ConstraintGraph& graph, const Partition& partition,
                                                     const SolverParams& params,
                                                     IslandCache<SubstructuredSystem>* cache = nullptr);

}  // namespace rbpart
