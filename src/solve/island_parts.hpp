#pragma once
// The parts of one island's bodies for the substructured solvers (DESIGN.md §7). A partition gives
// every graph node a part id; an island's bodies take their nodes' ids, renumbered 0..P-1 in
// increasing id so that parts are visited in the partition's order.
#include "graph/constraint_graph.hpp"
#include "partition/partition.hpp"
#include "solve/island_system.hpp"

#include <vector>

namespace rbpart {

// Island body -> part 0..P-1; every part in 0..P-1 has a body.
std::vector<int> island_parts(const IslandSystem& s, const ConstraintGraph& graph, const Partition& partition);

}  // namespace rbpart
