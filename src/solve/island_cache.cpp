#include "solve/island_cache.hpp"

namespace rbpart {

std::vector<IslandSlot*> IslandCache::slots_for(const Islands& islands) {
  std::unordered_map<int, std::unique_ptr<IslandSlot>> kept;
  std::vector<IslandSlot*> slots(islands.count());
  for (std::size_t i = 0; i < islands.count(); ++i) {
    const bool empty = islands.body_offset[i] == islands.body_offset[i + 1];
    const int first = empty ? -1 - static_cast<int>(i) : islands.bodies[islands.body_offset[i]];
    const auto found = slots_.find(first);
    std::unique_ptr<IslandSlot>& slot = kept[first];
    slot = found != slots_.end() ? std::move(found->second) : std::make_unique<IslandSlot>();
    slots[i] = slot.get();
  }
  slots_ = std::move(kept);
  return slots;
}

}  // namespace rbpart
