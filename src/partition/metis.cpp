// METIS, the min-cut reference (docs/design.md#partition): multilevel recursive bisection
// (METIS_PartGraphRecursive) of each island of more than nmax bodies, edge weights = constraint
// counts, unit vertex weights (nmax caps bodies, whatever their mass), fixed seed.
//
// Choices, measured on pile_graph graphs of 10^3-3·10^4 bodies (docs/partitioning.md):
// - Recursive bisection rather than k-way: with parts of 8-128 bodies (thousands of parts) k-way was
//   3-5x slower, cut up to 40 % more and left many parts disconnected.
// - nparts: METIS balances only to within its tolerance, and a part over nmax must be split below,
//   leaving a fragment. One bisection (bodies <= 2 nmax) is tried at the cap, nparts =
//   ceil(bodies / nmax), which it meets exactly where the graph allows (two cliques of nmax); if a
//   part exceeds nmax, and always for more parts, METIS aims 5 % below the cap, nparts =
//   ceil(bodies / (0.95 nmax)): recursive bisection's imbalance compounds over its levels, and
//   trying the cap first there gave the same parts on every pile graph of partition_bench in
//   twice the time. Where that many parts would be one body each, every body is its own part and
//   METIS is not called.
//
// METIS's parts are then made to meet docs/design.md#partition: each is cut into pieces by breadth-first
// growth restricted to the part's bodies (seeded at its lowest-index unassigned body, at most nmax bodies per
// piece). A connected METIS part of at most nmax bodies stays whole; a disconnected one becomes one piece per
// connected component; an oversized one is cut into breadth-first chunks of nmax (each connected, being a
// breadth-first prefix) and a remainder.
#include <metis.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include "partition/grow.hpp"

namespace rbpart {

namespace {

// Breadth-first growth that offers only bodies of the seed's METIS part (s.label).
struct MetisPieceRule : BreadthFirstOrder {
  const std::vector<int>& label;
  int current = -1;
  explicit MetisPieceRule(const GrowState& s) : BreadthFirstOrder(s), label(s.label) {}
  void begin(int seed) { current = label[seed]; }
  bool offer(int u) const { return label[u] == current; }
};

}  // namespace

void partition_island_metis(GrowState& s, const PartitionParams& params, const int* nodes, int count) {
  const ConstraintGraph& g = *s.graph;
  // The island as a METIS graph with local ids (s.label holds node -> local id meanwhile).
  thread_local std::vector<idx_t> xadj, adjncy, adjwgt, part;
  for (int i = 0; i < count; ++i) s.label[nodes[i]] = i;
  xadj.assign(1, 0);
  adjncy.clear();
  adjwgt.clear();
  for (int i = 0; i < count; ++i) {
    const int v = nodes[i];
    for (int k = g.offset[v]; k < g.offset[v + 1]; ++k) {
      adjncy.push_back(s.label[g.adjacency[k]]);
      adjwgt.push_back(g.weight[k]);
    }
    xadj.push_back(static_cast<idx_t>(adjncy.size()));
  }
  thread_local std::vector<int> size;
  // Runs METIS into `part`; returns whether every part fits in nmax.
  auto run_metis = [&](idx_t nparts) {
    if (nparts >= count) {
      std::iota(part.begin(), part.end(), 0);
      return true;
    }
    idx_t nvtxs = count, ncon = 1, objval = 0;
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_SEED] = 1;
    const int status = METIS_PartGraphRecursive(&nvtxs, &ncon, xadj.data(), adjncy.data(), nullptr, nullptr,
                                                adjwgt.data(), &nparts, nullptr, nullptr, options, &objval, part.data());
    if (status != METIS_OK)
      throw std::runtime_error("METIS_PartGraphRecursive failed with status " + std::to_string(status));
    size.assign(nparts, 0);
    for (idx_t p : part) ++size[p];
    return *std::max_element(size.begin(), size.end()) <= params.nmax;
  };
  part.resize(count);
  const idx_t at_cap = (count + params.nmax - 1) / params.nmax;
  const idx_t below = static_cast<idx_t>(std::ceil(count / (0.95 * params.nmax)));
  if (at_cap > 2 || below == at_cap || !run_metis(at_cap)) run_metis(below);
  for (int i = 0; i < count; ++i) s.label[nodes[i]] = part[i];
  MetisPieceRule rule(s);
  grow_island(s, rule, nodes, count);
}

}  // namespace rbpart
