#pragma once
// The refiners behind refine_partition (partition/partition.hpp), on a shared RefineState.
#include "refine/refine_state.hpp"

namespace rbpart {

// Greedy Kernighan–Lin (docs/design.md#refine): swaps the legal pair of largest positive gain until none.
void refine_kernighan_lin(RefineState& state);

// Fiduccia–Mattheyses (docs/design.md#refine). Greedy (rollback false): moves the legal body of largest
// positive gain until none. Rollback (classic FM, an extension): passes that take the best legal
// move whatever its gain, lock moved bodies, and keep the pass's best prefix; repeated while a pass
// lowers the cut.
void refine_fiduccia_mattheyses(RefineState& state, bool rollback);

}  // namespace rbpart
