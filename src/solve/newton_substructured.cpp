#include "solve/newton_substructured.hpp"

#include "core/timer.hpp"
#include "solve/island_cache.hpp"
#include "solve/island_parts.hpp"
#include "solve/island_system.hpp"
#include "solve/newton_island.hpp"
#include "solve/substructured_system.hpp"

#include <algorithm>
#include <stdexcept>

namespace rbpart {

namespace {

// The Newton iteration's own loops run in one chunk per part (island_chunks.hpp), but never in
// chunks of fewer rows than this, so that timing a chunk (two clock reads) stays small beside it.
constexpr int kMinRowsPerChunk = 64;

struct IslandOutcome {
  NewtonResult newton;
  int parts = 0, interface_rows = 0, interface_bodies = 0, parts_refactored = 0;
  double work_ms = 0, critical_path_ms = 0;
};

}  // namespace

NewtonSubstructuredReport solve_newton_substructured(Rows& rows, const Bodies& bodies, const Islands& islands,
                                                     const ConstraintGraph& graph, const Partition& partition,
                                                     const SolverParams& params, SubstructuredCache* cache) {
  if (static_cast<int>(partition.part_of.size()) != graph.node_count())
    throw std::invalid_argument("solve_newton_substructured: the partition does not cover the graph's nodes");
  const std::vector<int> local_row = local_row_index(rows, islands);
  std::vector<IslandOutcome> outcome(islands.count());
  SubstructuredCache this_step;
  const std::vector<IslandSlot<SubstructuredSystem>*> slots = (cache ? *cache : this_step).slots_for(islands);
  for_each_island(islands, [&](int i) {
    const Timer wall;
    IslandSlot<SubstructuredSystem>& slot = *slots[i];
    IslandSystem& s = slot.system;
    s.gather(rows, bodies, islands, i, local_row);
    SubstructuredSystem& system = slot.backend;
    system.assign(s, island_parts(s, graph, partition), params.dense_max_bodies);
    IslandOutcome& o = outcome[i];
    NewtonWorkspace& ws = slot.workspace;
    ws.chunks.set_count(std::min(system.parts(), s.rows / kMinRowsPerChunk));
    o.newton = solve_island_newton(s, system, params.max_factorizations, rows, ws);
    o.parts = system.parts();
    o.interface_rows = system.interface_rows();
    o.interface_bodies = system.interface_bodies();
    const SubstructuredCost& cost = system.total();
    o.parts_refactored = cost.parts_refactored;
    // Outside the backend's calls and the chunked loops the island is serial.
    const IslandChunks& loops = ws.chunks;
    const double rest = wall.ms() - cost.wall_ms - loops.wall_ms;
    o.work_ms = rest + cost.work_ms + loops.work_ms;
    o.critical_path_ms = rest + cost.critical_path_ms + loops.critical_path_ms;
  });

  NewtonSubstructuredReport report;
  for (const IslandOutcome& o : outcome) {
    add_island_result(o.newton, report.solve);
    report.parts += o.parts;
    report.interface_rows += o.interface_rows;
    report.interface_bodies += o.interface_bodies;
    report.parts_refactored += o.parts_refactored;
    report.solve.work_ms += o.work_ms;
    report.solve.critical_path_ms = std::max(report.solve.critical_path_ms, o.critical_path_ms);
  }
  return report;
}

}  // namespace rbpart
