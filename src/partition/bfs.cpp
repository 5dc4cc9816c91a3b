// BFS (docs/design.md#partition): seed at the lowest-index unassigned body, grow in breadth-first order with
// neighbours in natural body order.
#include "partition/grow.hpp"

namespace rbpart {

void partition_island_bfs(GrowState& s, const PartitionParams&, const int* nodes, int count) {
  BreadthFirstOrder rule(s);
  grow_island(s, rule, nodes, count);
}

}  // namespace rbpart
