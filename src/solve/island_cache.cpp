#include "solve/island_cache.hpp"

#include <iterator>

namespace rbpart {

template <class Backend>
const std::vector<IslandSlot<Backend>*>& IslandCache<Backend>::slots_for(const Islands& islands) {
  std::vector<IslandSlot<Backend>*>& slots = current_;
  slots.resize(islands.count());
  for (std::size_t i = 0; i < islands.count(); ++i) {
    const bool empty = islands.body_offset[i] == islands.body_offset[i + 1];
    const int first = empty ? -1 - static_cast<int>(i) : islands.bodies[islands.body_offset[i]];
    std::unique_ptr<IslandSlot<Backend>>& slot = slots_[first];
    if (!slot) slot = std::make_unique<IslandSlot<Backend>>();
    slot->used = true;
    slots[i] = slot.get();
  }
  // Islands own disjoint bodies, so no slot serves two; the ones no island used are freed.
  for (auto it = slots_.begin(); it != slots_.end();) it = it->second->used ? std::next(it) : slots_.erase(it);
  for (IslandSlot<Backend>* slot : slots) slot->used = false;
  return slots;
}

template class IslandCache<MonolithicSystem>;
template class IslandCache<SubstructuredSystem>;

}  // namespace rbpart
