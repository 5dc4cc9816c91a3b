#pragma once
// The substructured direct solver (Peiret et al., ACM TOG 2019; DESIGN.md §7): per island, the
// rows are split by a partition of the bodies into sub-system rows and interface rows; every
// sub-system is factored on its own thread and coupled to the others through the interface
// problem (a Schur complement), alternating interface and sub-system solves until no sub-system's
// index sets change. The answer is then the monolithic direct solver's (solve.hpp) up to round-off,
// with the same friction outer loop, so the two agree row by row. docs/substructured.md describes
// the algorithm, the phases and the critical-path estimate.
#include <rbpart/params.hpp>

#include "assembly/rows.hpp"
#include "graph/constraint_graph.hpp"
#include "graph/islands.hpp"
#include "partition/partition.hpp"
#include "scene/bodies.hpp"
#include "solve/solve.hpp"

namespace rbpart {

struct SubstructuredReport {
  // As solve_direct fills it; iterations are the BLCP-core iterations of every interface and
  // sub-system solve (and of the monolithic island solves), factorizations the Cholesky
  // factorisations of parts, interfaces and monolithic islands.
  SolveReport solve;
  // Sums over islands. An island is split into the parts the partition gives its bodies (a part
  // spanning two islands counts once per island); an island with one part has no interface.
  int parts = 0, interface_rows = 0, interface_bodies = 0;
  int loop_iterations = 0;  // iterations of DESIGN.md §7 steps 1-4, over all fixed-bounds solves
  int fallbacks = 0;        // islands solved monolithically after the iteration cap or a failed BLCP
  // Work per phase, ms summed over threads and islands (sub_island.hpp's SubPhase): Cholesky
  // factorisations; Schur complement (W_p, blocks of S, q~, assembly); interface BLCPs; sub-system
  // BLCPs; the coupled friction steps; monolithic solves (one-part islands and fallbacks).
  double factor_ms = 0, schur_ms = 0, interface_ms = 0, subsystem_ms = 0, coupled_ms = 0, monolithic_ms = 0;
  double work_ms = 0;           // all of the above plus the islands' serial set-up
  // The longest island's critical path: its wall time with every parallel section over parts
  // replaced by its slowest part (ms). With c cores a solve takes at least
  // max(critical_path_ms, work_ms / c): the estimate docs/substructured.md uses for 8 and 16 cores.
  double critical_path_ms = 0;
};

// Solves every island's BLCP (islands in parallel, parts within an island in parallel) and writes
// impulses, sets and final friction bounds into `rows`, warm started from rows.lambda/state as
// solve_direct is. `graph` maps scene bodies to nodes and `partition` gives every node a part (any
// assignment is valid; parts need not be connected). Islands with one part, or with a row without
// regularisation (sigma = 0: the body-space sub-systems need sigma > 0), are solved monolithically.
SubstructuredReport solve_substructured(Rows& rows, const Bodies& bodies, const Islands& islands,
                                        const ConstraintGraph& graph, const Partition& partition,
                                        const SolverParams& params);

}  // namespace rbpart
