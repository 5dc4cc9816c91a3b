#pragma once
// Constraint graphs built from edge lists, and deterministic generated graphs (by seed) for the
// partition and refinement tests and benchmarks: rock-pile-like graphs, grids, folded chains, stars,
// cliques, many small islands. Node i is body i (node_of/body_of are the identity).
#include <cstdint>
#include <string>
#include <vector>

#include "graph/constraint_graph.hpp"

namespace rbpart {

// An undirected edge: `weight` constraints carried by `rows` rows (docs/design.md#graph).
struct GraphEdge {
  int a = 0, b = 0;
  int weight = 1, rows = 1;
};

// Builds the CSR graph of `nodes` nodes. Edges listed more than once (in either direction) are
// merged with their weights and rows summed, as build_constraint_graph merges a pair's rows.
// `masses`: empty (every mass 1) or one positive finite mass per node. Throws std::invalid_argument
// on an end out of range, a self loop, a weight or row count below 1, or bad masses.
ConstraintGraph make_graph(int nodes, const std::vector<GraphEdge>& edges, std::vector<double> masses = {});

// Like a settled rock pile: rocks on a jittered lattice (about twice as wide as high, filled from
// the bottom layer), an edge between rocks closer than 1.3 lattice spacings (degree ~6-10), weights
// 1-4 contact points of 3 rows each. Node order follows the layers, as bodies dropped from a grid.
ConstraintGraph pile_graph(int nodes, std::uint64_t seed);
// Uniform random points in a unit cube, an edge between points closer than the radius that gives
// `mean_degree` neighbours on average (so small graphs break into islands); weights 1-4, 3 rows each.
ConstraintGraph random_geometric_graph(int nodes, double mean_degree, std::uint64_t seed);
// nx x ny x nz lattice (nz = 1: 2D), unit weights and rows; node (i, j, k) = i + nx (j + ny k).
ConstraintGraph grid_graph(int nx, int ny, int nz = 1);
// A chain of ball joints (weight 1, 3 rows) laid as a persistent random walk on a lattice, plus one
// contact (weight 1-2, 3 rows per point) between non-adjacent links that fold onto the same or a
// neighbouring site, as a chain folds when dropped.
ConstraintGraph folded_path_graph(int nodes, std::uint64_t seed);
// Node 0 joined to nodes 1..leaves; unit weights and rows.
ConstraintGraph star_graph(int leaves);
// Every pair joined; unit weights and rows.
ConstraintGraph clique_graph(int nodes);
// `count` islands of 1..max_size nodes (random trees plus a few extra edges, weights 1-4), with the
// islands' nodes interleaved in index order so that islands are not index ranges.
ConstraintGraph islands_graph(int count, int max_size, std::uint64_t seed);

// One mass per node drawn from {10, 100, 1000} kg (the Large Rock Pile's masses, docs/design.md#scenes).
std::vector<double> random_masses(int nodes, std::uint64_t seed);
// Returns `graph` with the masses replaced.
ConstraintGraph with_masses(ConstraintGraph graph, std::vector<double> masses);

struct GeneratedGraph {
  std::string name;  // family and parameters, for test failure messages
  ConstraintGraph graph;
};
// `count` graphs cycling through every family above plus isolated nodes, a single node and the
// empty graph, with sizes 0-300 and, for every other graph, masses from random_masses.
// Deterministic in `seed`.
std::vector<GeneratedGraph> graph_suite(int count, std::uint64_t seed);

}  // namespace rbpart
