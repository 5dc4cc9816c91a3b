// The METIS graph reader (every fmt code, every rejected input naming its line), the masses reader
// and the part file writer.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "io/metis_graph.hpp"
#include "temp_dir.hpp"

namespace rbpart {
namespace {

MetisGraph parse(const std::string& text) {
  std::istringstream in(text);
  return parse_metis_graph(in, "g.graph");
}

// The error message of parsing `text`, or "" if it parses.
std::string error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MetisGraph, PlainFormatWithCommentsAndAnIsolatedVertex) {
  // Triangle 1-2-3, vertex 4 alone (its line is empty), comment lines anywhere.
  const MetisGraph m = parse("% a triangle\n4 3\n2 3\n% between vertex lines\n1 3\n1 2\n\n");
  const ConstraintGraph& g = m.graph;
  EXPECT_EQ(g.node_count(), 4);
  EXPECT_EQ(g.edge_count(), 3);
  EXPECT_EQ(g.offset, (std::vector<int>{0, 2, 4, 6, 6}));
  EXPECT_EQ(g.adjacency, (std::vector<int>{1, 2, 0, 2, 0, 1}));
  EXPECT_EQ(g.weight, (std::vector<int>(6, 1)));
  EXPECT_EQ(g.rows, g.weight);
  EXPECT_EQ(g.mass, (std::vector<double>(4, 1.0)));
  EXPECT_EQ(g.body_of, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(g.node_of, g.body_of);
  EXPECT_EQ(m.ncon, 0);
  EXPECT_TRUE(m.vertex_weights.empty());
}

TEST(MetisGraph, EdgeWeightsBecomeWeightsAndRows) {
  // fmt 1, neighbours listed out of order; tabs and CR line ends tolerated.
  const MetisGraph m = parse("3 2 1\r\n3 4\t2 7\r\n1 7\r\n1 4\r\n");
  EXPECT_EQ(m.graph.adjacency, (std::vector<int>{1, 2, 0, 0}));
  EXPECT_EQ(m.graph.weight, (std::vector<int>{7, 4, 7, 4}));
  EXPECT_EQ(m.graph.rows, m.graph.weight);
  EXPECT_EQ(parse("3 2 001\n3 4 2 7\n1 7\n1 4\n").graph.weight, m.graph.weight);
}

TEST(MetisGraph, VertexWeightsAreKeptApartFromMasses) {
  const MetisGraph a = parse("3 2 10\n5 2\n0 1 3\n9 2\n");
  EXPECT_EQ(a.ncon, 1);
  EXPECT_EQ(a.vertex_weights, (std::vector<int>{5, 0, 9}));
  EXPECT_EQ(a.graph.adjacency, (std::vector<int>{1, 0, 2, 1}));
  EXPECT_EQ(a.graph.mass, (std::vector<double>(3, 1.0)));
  const MetisGraph b = parse("2 1 10 2\n1 2 2\n3 4 1\n");
  EXPECT_EQ(b.ncon, 2);
  EXPECT_EQ(b.vertex_weights, (std::vector<int>{1, 2, 3, 4}));
}

TEST(MetisGraph, VertexAndEdgeWeights) {
  const MetisGraph m = parse("3 2 011\n1 2 5\n2 1 5 3 6\n3 2 6\n");
  EXPECT_EQ(m.vertex_weights, (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(m.graph.weight, (std::vector<int>{5, 5, 6, 6}));
  EXPECT_EQ(parse("3 2 11 1\n1 2 5\n2 1 5 3 6\n3 2 6\n").graph.weight, m.graph.weight);
}

// Each malformed input with the exact message: "<file>:<line>: <problem>".
TEST(MetisGraph, RejectsBadInputNamingTheLine) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      // header
      {"", "g.graph:1: no header line (n m [fmt [ncon]])"},
      {"% only a comment\n\n", "g.graph:2: no header line (n m [fmt [ncon]])"},
      {"3\n", "g.graph:1: header needs at least n and m"},
      {"3 2 1 1 1\n", "g.graph:1: header has more than 4 fields (n m [fmt [ncon]])"},
      {"3 x\n", "g.graph:1: edge count 'x' is not an integer"},
      {"3.0 2\n", "g.graph:1: vertex count '3.0' is not an integer"},
      {"99999999999 2\n", "g.graph:1: vertex count '99999999999' is out of range"},
      {"-3 2\n", "g.graph:1: negative vertex or edge count"},
      {"% empty\n0 0\n", "g.graph:2: empty graph (no vertices)"},
      {"2 1 2\n2\n1\n", "g.graph:1: fmt 2 is not one of 0, 1, 10, 11"},
      {"2 1 100\n2\n1\n", "g.graph:1: vertex sizes (fmt 1xx) are not supported"},
      {"2 1 1 2\n2 1\n1 1\n", "g.graph:1: ncon given but fmt has no vertex weights"},
      {"2 1 10 0\n2\n1\n", "g.graph:1: ncon must be at least 1"},
      // vertex lines
      {"3 2\n2\n1 x\n2\n", "g.graph:3: neighbour 'x' is not an integer"},
      {"3 2\n2\n1 3\n% c\n0\n", "g.graph:5: neighbour 0 is outside 1..3"},
      {"3 2\n2\n1 4\n2\n", "g.graph:3: neighbour 4 is outside 1..3"},
      {"3 2\n2\n1 2\n2\n", "g.graph:3: self loop on vertex 2"},
      {"3 2\n2 2\n1 3\n2\n", "g.graph:2: neighbour 2 listed twice"},
      {"3 2 1\n2 1\n1 1 3\n2 1\n", "g.graph:3: neighbour 3 has no edge weight"},
      {"3 2 1\n2 0\n1 0 3 1\n2 1\n", "g.graph:2: edge weight 0 is not positive"},
      {"3 2 1\n2 1.5\n1 1.5 3 1\n2 1\n", "g.graph:2: edge weight '1.5' is not an integer"},
      {"3 2 10\n-1 2\n1 1 3\n1 2\n", "g.graph:2: negative vertex weight -1"},
      {"3 2 11 2\n1 2 2\n1 1 1 1 3 1\n1 1 2 1\n", "g.graph:2: neighbour 2 has no edge weight"},
      {"3 2 10 3\n1 2\n", "g.graph:2: fewer than 3 vertex weights"},
      // counts and symmetry
      {"3 2\n2\n1 3\n", "g.graph:3: file ends after 2 of 3 vertex lines"},
      {"3 2\n2\n1 3\n2\n1\n", "g.graph:5: more than 3 vertex lines"},
      {"% c\n3 3\n2\n1 3\n2\n", "g.graph:2: header says 3 edges but the vertex lines list 2"},
      {"3 2\n2 3\n1 3\n2\n", "g.graph:2: edge 1-3 has no reverse: vertex 3 (line 4) does not list 1"},
      {"3 2 1\n2 1\n1 1 3 2\n2 5\n", "g.graph:3: edge 2-3 has weight 2 here but 5 on vertex 3's line (line 4)"},
  };
  for (const auto& [text, message] : cases) EXPECT_EQ(error_of(text), message) << text;
}

TEST(MetisGraph, MissingFileIsAnInputError) {
  EXPECT_THROW(read_metis_graph("/nonexistent/rbpart/g.graph"), InputError);
  EXPECT_THROW(read_masses("/nonexistent/rbpart/m.txt", 1), InputError);
}

std::string masses_error(const std::string& text, int count) {
  std::istringstream in(text);
  try {
    parse_masses(in, "m.txt", count);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Masses, OnePerLineWithCommentsAndBlankLines) {
  std::istringstream in("% kg\n10\n\n2.5e2\n  0.125  \n");
  EXPECT_EQ(parse_masses(in, "m.txt", 3), (std::vector<double>{10, 250, 0.125}));
}

TEST(Masses, RejectsBadMassesNamingTheLine) {
  EXPECT_EQ(masses_error("1\nheavy\n", 2), "m.txt:2: mass 'heavy' is not a number");
  EXPECT_EQ(masses_error("1\n0\n", 2), "m.txt:2: mass 0 is not positive and finite");
  EXPECT_EQ(masses_error("-1\n1\n", 2), "m.txt:1: mass -1 is not positive and finite");
  EXPECT_EQ(masses_error("1\nnan\n", 2), "m.txt:2: mass nan is not positive and finite");
  EXPECT_EQ(masses_error("inf\n1\n", 2), "m.txt:1: mass inf is not positive and finite");
  EXPECT_EQ(masses_error("1 2\n", 2), "m.txt:1: more than one mass on the line");
  EXPECT_EQ(masses_error("1\n2\n3\n", 2), "m.txt:3: 3 masses for 2 vertices");
  EXPECT_EQ(masses_error("1\n", 2), "m.txt:1: 1 masses for 2 vertices");
}

TEST(PartFile, OneZeroBasedIdPerLineWrittenAtomically) {
  const Partition p{{0, 2, 1, 0}, 3};
  EXPECT_EQ(part_file_text(p), "0\n2\n1\n0\n");
  test::TempDir dir;
  write_part_file(dir.file("g.part"), p);
  EXPECT_EQ(test::read_text(dir.file("g.part")), "0\n2\n1\n0\n");
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"g.part"}));
}

TEST(MetisGraph, ReadsAFileAndItsMasses) {
  test::TempDir dir;
  std::ofstream(dir.file("g.graph")) << "2 1\n2\n1\n";
  std::ofstream(dir.file("m.txt")) << "3\n4\n";
  const MetisGraph m = read_metis_graph(dir.file("g.graph"));
  EXPECT_EQ(m.graph.edge_count(), 1);
  EXPECT_EQ(read_masses(dir.file("m.txt"), 2), (std::vector<double>{3, 4}));
  try {
    read_metis_graph(dir.file("m.txt"));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), dir.file("m.txt") + ":1: header needs at least n and m");
  }
}

}  // namespace
// Memory follows the file, not its header (issue #26: a 3-line graph claiming 2e9 vertices took
// 7 GB): a header claiming 5e7 vertices, which 32-bit per-vertex arrays would make 400 MB, fails on
// its third line with the peak resident size unchanged.
TEST(MetisGraph, HeaderCountsAllocateNothingBeforeTheLinesExist) {
  const auto peak_kb = [] {
    rusage usage{};
    ::getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss;
  };
  const long before = peak_kb();
  EXPECT_EQ(error_of("50000000 1\n2\n1\n"), "g.graph:3: file ends after 2 of 50000000 vertex lines");
  EXPECT_LT(peak_kb() - before, 64 * 1024);
}

}  // namespace rbpart
