#pragma once
// Islands: connected components of the constraint graph (docs/design.md#graph). Independent BLCPs.
#include "assembly/rows.hpp"

#include <vector>

namespace rbpart {

// Flat CSR layout: island i owns bodies[body_offset[i] .. body_offset[i+1]) and
// rows[row_offset[i] .. row_offset[i+1]), both in increasing index order. Only islands with at
// least one row are listed; islands are ordered by their lowest body index.
struct Islands {
  std::vector<int> body_offset{0}, bodies;
  std::vector<int> row_offset{0}, rows;
  std::size_t count() const { return body_offset.size() - 1; }
};

// Connected components over the rows' dynamic bodies (union-find). `body_count` = scene bodies.
void build_islands(const Rows& rows, int body_count, Islands& islands);

}  // namespace rbpart
