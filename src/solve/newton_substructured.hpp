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

struct NewtonSubstructuredReport {
  SolveReport solve;  // as solve_newton_direct fills it
  // Sums over islands; an island holds the parts of its bodies (a part spanning two islands counts
  // once per island), an island of one part has no interface.
  int parts = 0, interface_rows = 0, interface_bodies = 0;
  int parts_refactored = 0;  // part factorisations (a part whose rows did not change keeps its factor)
  // Work, ms summed over threads and islands: the backends' parallel and serial phases and each
  // island's serial rest (gathering, set-up, the Newton iteration's own products and line search).
  double work_ms = 0;
  // The longest island's critical path (ms): its wall time with every parallel phase over its parts
  // replaced by its slowest part. With c cores a solve takes at least max(critical_path_ms, work_ms / c).
  double critical_path_ms = 0;
};

// Solves every island's coupled problem and writes impulses, states and final friction bounds into
// `rows`, warm started from rows.lambda/state, as solve_newton_direct does. `graph` maps scene
// bodies to nodes and `partition` gives every node a part (any assignment is valid; parts need not be
// connected). Needs sigma_j > 0 on every row, as the monolithic backend does.
NewtonSubstructuredReport solve_newton_substructured(Rows& rows, const Bodies& bodies, const Islands& islands,
                                                     const ConstraintGraph& graph, const Partition& partition,
                                                     const SolverParams& params);

}  // namespace rbpart
