// MinDP (Peiret et al. 2019, after Cuthill-McKee) and MaxDP (docs/design.md#partition): seed at the
// unassigned body of minimum (maximum) degree, then repeatedly add the candidate of minimum (maximum) degree.
// Degrees are fixed, so every candidate is queued once per part with its final key.
#include "partition/grow.hpp"

namespace rbpart {

void partition_island_min_dp(GrowState& s, const PartitionParams&, const int* nodes, int count) {
  DegreeOrder rule(s, +1);
  grow_island(s, rule, nodes, count);
}

void partition_island_max_dp(GrowState& s, const PartitionParams&, const int* nodes, int count) {
  DegreeOrder rule(s, -1);
  grow_island(s, rule, nodes, count);
}

}  // namespace rbpart
