#include "solve/island_parts.hpp"

#include <algorithm>

namespace rbpart {

void island_parts(const IslandSystem& s, const ConstraintGraph& graph, const Partition& partition,
                  std::vector<int>& part_of_body, std::vector<int>& distinct) {
  const auto id = [&](int b) { return partition.part_of[graph.node_of[s.global_bodies[b]]]; };
  distinct.resize(s.bodies);
  for (int b = 0; b < s.bodies; ++b) distinct[b] = id(b);
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  part_of_body.resize(s.bodies);
  for (int b = 0; b < s.bodies; ++b)
    part_of_body[b] = static_cast<int>(std::lower_bound(distinct.begin(), distinct.end(), id(b)) - distinct.begin());
}

}  // namespace rbpart
