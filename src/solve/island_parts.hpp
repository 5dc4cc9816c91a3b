#pragma once
// The parts of one island's bodies for the substructured solvers (DESIGN.md §7). A partition gives
// every graph node a part id; an island's bodies take their nodes' ids, renumbered 0..P-1 in
// increasing id so that parts are visited in the partition's order.
#include "graph/constraint_graph.hpp"
#include "partition/partition.hpp"
#include "solve/island_system.hpp"

#include <vector>

namespace rbpart {

// Island body -> part 0..P-1 into `part_of_body`; every part in 0..P-1 has a body. `distinct`
// (the island's part ids) is scratch; both keep their capacity.
void island_parts(const IslandSystem& s, const ConstraintGraph& graph, const Partition& partition,
                  std::vector<int>& part_of_body, std::vector<int>& distinct);

}  // namespace rbpart
