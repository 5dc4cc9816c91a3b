#include "solve/island_parts.hpp"

#include <algorithm>

namespace rbpart {

std::vector<int> island_parts(const IslandSystem& s, const ConstraintGraph& graph, const Partition& partition) {
  std::vector<int> part_of_body(s.bodies), ids(s.bodies);
  for (int b = 0; b < s.bodies; ++b) ids[b] = partition.part_of[graph.node_of[s.global_bodies[b]]];
  std::vector<int> distinct = ids;
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  for (int b = 0; b < s.bodies; ++b)
    part_of_body[b] = static_cast<int>(std::lower_bound(distinct.begin(), distinct.end(), ids[b]) - distinct.begin());
  return part_of_body;
}

}  // namespace rbpart
