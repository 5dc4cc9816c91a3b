#include "graph/islands.hpp"

#include <numeric>

namespace rbpart {

namespace {
int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}
}  // namespace

void build_islands(const Rows& rows, int body_count, Islands& islands) {
  // Scratch kept per thread, so that a warm step allocates nothing.
  thread_local std::vector<int> parent, island_of, row_island, fill;
  thread_local std::vector<char> in_row;
  parent.resize(body_count);
  std::iota(parent.begin(), parent.end(), 0);
  in_row.assign(body_count, 0);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto [a, b] = rows.body[r];
    if (a >= 0) in_row[a] = 1;
    if (b >= 0) in_row[b] = 1;
    if (a >= 0 && b >= 0) {
      const int ra = find_root(parent, a), rb = find_root(parent, b);
      // Union towards the lower index keeps the root = lowest body of the island (deterministic).
      if (ra < rb) parent[rb] = ra;
      else if (rb < ra) parent[ra] = rb;
    }
  }
  // Island number per root, in order of the lowest body index.
  island_of.assign(body_count, -1);
  int count = 0;
  for (int i = 0; i < body_count; ++i) {
    if (!in_row[i]) continue;
    const int root = find_root(parent, i);
    if (island_of[root] < 0) island_of[root] = count++;
    island_of[i] = island_of[root];
  }
  // Counting sort of bodies and rows into islands.
  islands.body_offset.assign(count + 1, 0);
  islands.row_offset.assign(count + 1, 0);
  for (int i = 0; i < body_count; ++i)
    if (island_of[i] >= 0) ++islands.body_offset[island_of[i] + 1];
  row_island.resize(rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const int b = rows.body[r][0] >= 0 ? rows.body[r][0] : rows.body[r][1];
    row_island[r] = b >= 0 ? island_of[b] : -1;
    if (row_island[r] >= 0) ++islands.row_offset[row_island[r] + 1];
  }
  std::partial_sum(islands.body_offset.begin(), islands.body_offset.end(), islands.body_offset.begin());
  std::partial_sum(islands.row_offset.begin(), islands.row_offset.end(), islands.row_offset.begin());
  islands.bodies.resize(islands.body_offset.back());
  islands.rows.resize(islands.row_offset.back());
  fill.assign(islands.body_offset.begin(), islands.body_offset.end() - 1);
  for (int i = 0; i < body_count; ++i)
    if (island_of[i] >= 0) islands.bodies[fill[island_of[i]]++] = i;
  fill.assign(islands.row_offset.begin(), islands.row_offset.end() - 1);
  for (std::size_t r = 0; r < rows.size(); ++r)
    if (row_island[r] >= 0) islands.rows[fill[row_island[r]]++] = static_cast<int>(r);
}

}  // namespace rbpart
