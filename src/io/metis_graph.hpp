#pragma once
// Graphs in METIS format, node masses and METIS-style part files, for `rbpart partition`
// (docs/design.md#contracts: any graph can be partitioned and compared with METIS).
//
// METIS graph format (METIS 5 manual, §4.1.1): lines starting with '%' are comments; the header is
// `n m [fmt [ncon]]`; then one line per vertex (an empty line is a vertex without neighbours)
// listing its 1-based neighbours. fmt is 0 (plain), 1 (edge weights: `neighbour weight` pairs),
// 10 (ncon vertex weights, default 1, first on each line) or 11 (both); vertex sizes (fmt 1xx) are
// not supported.
#include <iosfwd>
#include <string>
#include <vector>

#include "graph/constraint_graph.hpp"
#include "partition/partition.hpp"

namespace rbpart {

struct MetisGraph {
  // Node i is vertex i+1. Edge weight = the file's edge weight (1 without fmt x1), and its row count
  // = its weight: a file knows constraints, not rows, so interface rows equal the edge cut. Masses 1.
  ConstraintGraph graph;
  // METIS's vertex (balance) weights, ncon per vertex, when the file has them (fmt 1x); kept as read
  // and never used as masses, which come from a masses file.
  int ncon = 0;
  std::vector<int> vertex_weights;
};

// Reads a METIS graph. Throws InputError "<name>:<line>: <problem>" on a malformed header, a token
// that is not a number of the expected kind, a neighbour id out of 1..n, a self loop, a neighbour
// listed twice, a non-positive edge weight or negative vertex weight, an edge whose reverse is
// missing or weighted differently, more or fewer vertex lines than n, an edge count other than m,
// or an empty graph (n = 0).
MetisGraph read_metis_graph(const std::string& path);
MetisGraph parse_metis_graph(std::istream& in, const std::string& name);

// The same graph from METIS's arrays (its C API, 0-based): node v's neighbours are
// adjncy[xadj[v] .. xadj[v+1]), in any order, with edge weights adjwgt (empty: 1) and node masses
// (empty: 1). Throws InputError naming the first problem: xadj not starting at 0, decreasing or not
// ending at adjncy's size; a neighbour outside 0..n-1, a self loop, a neighbour listed twice; a
// weight below 1; an edge whose reverse is missing or weighted differently; a mass not positive and
// finite; arrays of the wrong size.
ConstraintGraph graph_from_arrays(const std::vector<int>& xadj, const std::vector<int>& adjncy,
                                  const std::vector<int>& adjwgt = {}, const std::vector<double>& masses = {});

// One mass per line for `count` nodes (blank lines and '%' comment lines skipped); throws
// InputError "<name>:<line>: ..." on a token that is not a number, a non-positive or non-finite
// mass, more than one number on a line, or a count other than `count`.
std::vector<double> read_masses(const std::string& path, int count);
std::vector<double> parse_masses(std::istream& in, const std::string& name, int count);

// One 0-based part id per node per line (the METIS .part layout).
std::string part_file_text(const Partition& partition);
// Writes part_file_text atomically (nothing half written is left behind).
void write_part_file(const std::string& path, const Partition& partition);

}  // namespace rbpart
