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

NewtonSubstructuredReport solve_newton_substructured(Rows& rows, const Bodies& bodies, const Islands& islands,
                                                     const ConstraintGraph& graph, const Partition& partition,
                                                     const SolverParams& params, SubstructuredCache* cache) {
  if (static_cast<int>(partition.part_of.size()) != graph.node_count())
    throw std::invalid_argument("solve_newton_substructured: the partition does not cover the graph's nodes");
  SubstructuredCache this_step;
  SubstructuredCache& kept = cache ? *cache : this_step;
  local_row_index(rows, islands, kept.local_row);
  const std::vector<IslandSlot<SubstructuredSystem>*>& slots = kept.slots_for(islands);
  for_each_island(islands, kept.island_order, [&](int i) {
    const Timer wall;
    IslandSlot<SubstructuredSystem>& slot = *slots[i];
    IslandSystem& s = slot.system;
    NewtonWorkspace& ws = slot.workspace;
    ws.chunks.set_count(chunks_for_rows(islands.row_offset[i + 1] - islands.row_offset[i]));
    s.gather(rows, bodies, islands, i, kept.local_row, ws.chunks);
    SubstructuredSystem& system = slot.backend;
    island_parts(s, graph, partition, slot.part_of_body, slot.distinct);
    system.assign(s, slot.part_of_body);
    slot.result = solve_island_newton(s, system, params.max_factorizations, rows, ws);
    // Outside the backend's calls and the chunked loops the island is serial.
    const SubstructuredCost& cost = system.total();
    const IslandChunks& loops = ws.chunks;
    const double rest = wall.ms() - cost.wall_ms - loops.wall_ms;
    slot.work_ms = rest + cost.work_ms + loops.work_ms;
    slot.critical_path_ms = rest + cost.critical_path_ms + loops.critical_path_ms;
  });

  NewtonSubstructuredReport report;
  for (const IslandSlot<SubstructuredSystem>* slot : slots) {
    const SubstructuredSystem& system = slot->backend;
    add_island_result(slot->result, report.solve);
    report.parts += system.parts();
    report.interface_rows += system.interface_rows();
    report.interface_bodies += system.interface_bodies();
    report.parts_refactored += system.total().parts_refactored;
    report.solve.work_ms += slot->work_ms;
    report.solve.critical_path_ms = std::max(report.solve.critical_path_ms, slot->critical_path_ms);
  }
  return report;
}

}  // namespace rbpart
