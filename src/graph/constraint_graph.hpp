#pragma once
// The constraint graph (docs/design.md#graph): nodes are dynamic bodies, one edge per pair of dynamic bodies
// sharing at least one constraint, weighted by the number of constraints between them (a contact
// point or a joint is one constraint); the rows between the pair are kept beside the weight.
// Constraints with a static body or the world are not edges. Flat CSR with an n+1 offset sentinel.
#include <cstdint>
#include <vector>

#include "assembly/rows.hpp"
#include "scene/bodies.hpp"

namespace rbpart {

// Sums of edge weights (degrees, connections, gains, cuts): a METIS file's weights reach 2^31 - 1
// each, so two of them overflow an int (issue #26).
using WeightSum = std::int64_t;

struct ConstraintGraph {
  std::vector<int> body_of;   // node -> scene body index
  std::vector<int> node_of;   // scene body index -> node, -1 for static bodies
  std::vector<double> mass;   // node -> mass (kg)
  // Node i's neighbours are adjacency[offset[i] .. offset[i+1]), in increasing node order, with the
  // edge's constraint count in weight[] and its row count in rows[] (both stored in both directions).
  std::vector<int> offset{0}, adjacency, weight, rows;

  int node_count() const { return static_cast<int>(body_of.size()); }
  int edge_count() const { return static_cast<int>(adjacency.size()) / 2; }
  // Sum of the weights of a node's edges: its constraints to other dynamic bodies.
  WeightSum degree(int node) const;
};

// Builds the graph of the step's rows (docs/design.md#graph).
void build_constraint_graph(const Rows& rows, const Bodies& bodies, ConstraintGraph& graph);

}  // namespace rbpart
