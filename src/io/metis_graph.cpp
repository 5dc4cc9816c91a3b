#include "io/metis_graph.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <numeric>
#include <utility>

#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/text_format.hpp"

namespace rbpart {

namespace {

// Physical lines with their numbers; every error names "<file>:<line>".
class LineReader {
 public:
  LineReader(std::istream& in, std::string name) : in_(in), name_(std::move(name)) {}

  // The next line, comment lines ('%' first after blanks) skipped; false at the end of the file.
  bool next() {
    while (std::getline(in_, line_)) {
      ++number_;
      if (!line_.empty() && line_.back() == '\r') line_.pop_back();
      split();
      if (tokens_.empty() || tokens_[0][0] != '%') return true;
    }
    return false;
  }
  const std::vector<std::string>& tokens() const { return tokens_; }
  int number() const { return number_; }

  [[noreturn]] void fail(const std::string& what, int line = -1) const {
    throw InputError(name_ + ":" + std::to_string(line < 0 ? std::max(number_, 1) : line) + ": " + what);
  }
  // The whole token as an integer (e.g. "neighbour"), else fail naming it.
  int integer(const std::string& token, const char* what) const {
    int value = 0;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec == std::errc::result_out_of_range) fail(std::string(what) + " '" + printable(token) + "' is out of range");
    if (ec != std::errc() || end != token.data() + token.size())
      fail(std::string(what) + " '" + printable(token) + "' is not an integer");
    return value;
  }
  double real(const std::string& token, const char* what) const {
    double value = 0;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec != std::errc() || end != token.data() + token.size())
      fail(std::string(what) + " '" + printable(token) + "' is not a number");
    return value;
  }

 private:
  void split() {
    tokens_.clear();
    std::size_t i = 0;
    while (i < line_.size()) {
      while (i < line_.size() && (line_[i] == ' ' || line_[i] == '\t')) ++i;
      const std::size_t start = i;
      while (i < line_.size() && line_[i] != ' ' && line_[i] != '\t') ++i;
      if (i > start) tokens_.push_back(line_.substr(start, i - start));
    }
  }

  std::istream& in_;
  std::string name_;
  std::string line_;
  std::vector<std::string> tokens_;
  int number_ = 0;
};

std::ifstream open_input(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open");
  return in;
}

// Sorts every node's neighbours, with their weights, into increasing order (the graph's CSR
// convention).
void sort_neighbours(ConstraintGraph& g) {
  std::vector<std::pair<int, int>> entries;
  for (int v = 0; v + 1 < static_cast<int>(g.offset.size()); ++v) {
    entries.clear();
    for (int k = g.offset[v]; k < g.offset[v + 1]; ++k) entries.emplace_back(g.adjacency[k], g.weight[k]);
    std::sort(entries.begin(), entries.end());
    for (std::size_t i = 0; i < entries.size(); ++i) {
      g.adjacency[g.offset[v] + i] = entries[i].first;
      g.weight[g.offset[v] + i] = entries[i].second;
    }
  }
}

// The first edge, in node then neighbour order, that its other end does not list (reverse = -1) or
// lists with another weight (reverse = that entry); k = -1 when every edge is paired. Neighbours
// sorted, so each reverse is found by binary search.
struct UnpairedEdge {
  int v = -1, k = -1, reverse = -1;
};
UnpairedEdge find_unpaired_edge(const ConstraintGraph& g) {
  for (int v = 0; v + 1 < static_cast<int>(g.offset.size()); ++v)
    for (int k = g.offset[v]; k < g.offset[v + 1]; ++k) {
      const int u = g.adjacency[k];
      const auto first = g.adjacency.begin() + g.offset[u], last = g.adjacency.begin() + g.offset[u + 1];
      const auto it = std::lower_bound(first, last, v);
      if (it == last || *it != v) return {v, k, -1};
      const int reverse = static_cast<int>(it - g.adjacency.begin());
      if (g.weight[reverse] != g.weight[k]) return {v, k, reverse};
    }
  return {};
}

// Node i is body i, of mass 1 unless `masses` says otherwise; an edge's row count is its weight.
void finish_graph(ConstraintGraph& g, int n) {
  g.body_of.resize(n);
  std::iota(g.body_of.begin(), g.body_of.end(), 0);
  g.node_of = g.body_of;
  g.mass.assign(n, 1.0);
  g.rows = g.weight;
}

}  // namespace

MetisGraph parse_metis_graph(std::istream& in, const std::string& name) {
  LineReader r(in, name);
  // Header: n m [fmt [ncon]]; blank lines before it are tolerated.
  do {
    if (!r.next()) r.fail("no header line (n m [fmt [ncon]])");
  } while (r.tokens().empty());
  const int header_line = r.number();
  const auto& h = r.tokens();
  if (h.size() > 4) r.fail("header has more than 4 fields (n m [fmt [ncon]])");
  if (h.size() < 2) r.fail("header needs at least n and m");
  const int n = r.integer(h[0], "vertex count"), m = r.integer(h[1], "edge count");
  if (n < 0 || m < 0) r.fail("negative vertex or edge count");
  if (n == 0) r.fail("empty graph (no vertices)");
  int fmt = 0;
  if (h.size() >= 3) {
    fmt = r.integer(h[2], "fmt");
    if (fmt >= 100 && fmt <= 111 && fmt % 10 <= 1 && fmt / 10 % 10 <= 1) r.fail("vertex sizes (fmt 1xx) are not supported");
    if (fmt != 0 && fmt != 1 && fmt != 10 && fmt != 11) r.fail("fmt " + h[2] + " is not one of 0, 1, 10, 11");
  }
  const bool edge_weights = fmt % 10 == 1, has_vertex_weights = fmt / 10 == 1;
  int ncon = has_vertex_weights ? 1 : 0;
  if (h.size() == 4) {
    if (!has_vertex_weights) r.fail("ncon given but fmt has no vertex weights");
    ncon = r.integer(h[3], "ncon");
    if (ncon < 1) r.fail("ncon must be at least 1");
  }

  MetisGraph out;
  out.ncon = ncon;
  ConstraintGraph& g = out.graph;
  g.offset.assign(1, 0);
  // Nothing is sized by the header's n or m: a 3-line file may claim 2e9 vertices (issue #26), so
  // memory grows only with the lines actually read, and the counts are checked against them.
  std::vector<int> line_of, neighbours;
  for (int v = 0; v < n; ++v) {
    if (!r.next()) r.fail("file ends after " + std::to_string(v) + " of " + std::to_string(n) + " vertex lines");
    line_of.push_back(r.number());
    const auto& t = r.tokens();
    if (static_cast<int>(t.size()) < ncon) r.fail("fewer than " + std::to_string(ncon) + " vertex weights");
    for (int c = 0; c < ncon; ++c) {
      const int w = r.integer(t[c], "vertex weight");
      if (w < 0) r.fail("negative vertex weight " + t[c]);
      out.vertex_weights.push_back(w);
    }
    const std::size_t step = edge_weights ? 2 : 1;
    if ((t.size() - ncon) % step != 0) r.fail("neighbour " + printable(t.back()) + " has no edge weight");
    for (std::size_t k = ncon; k < t.size(); k += step) {
      const int u = r.integer(t[k], "neighbour");
      if (u < 1 || u > n) r.fail("neighbour " + t[k] + " is outside 1.." + std::to_string(n));
      if (u - 1 == v) r.fail("self loop on vertex " + std::to_string(v + 1));
      const int w = edge_weights ? r.integer(t[k + 1], "edge weight") : 1;
      if (w < 1) r.fail("edge weight " + t[k + 1] + " is not positive");
      g.adjacency.push_back(u - 1);
      g.weight.push_back(w);
    }
    neighbours.assign(g.adjacency.begin() + g.offset.back(), g.adjacency.end());
    std::sort(neighbours.begin(), neighbours.end());
    const auto twice = std::adjacent_find(neighbours.begin(), neighbours.end());
    if (twice != neighbours.end()) r.fail("neighbour " + std::to_string(*twice + 1) + " listed twice");
    g.offset.push_back(static_cast<int>(g.adjacency.size()));
  }
  while (r.next())
    if (!r.tokens().empty()) r.fail("more than " + std::to_string(n) + " vertex lines");

  sort_neighbours(g);
  if (const UnpairedEdge e = find_unpaired_edge(g); e.k >= 0) {
    const int v = e.v, u = g.adjacency[e.k];
    const std::string edge = "edge " + std::to_string(v + 1) + "-" + std::to_string(u + 1);
    if (e.reverse < 0)
      r.fail(edge + " has no reverse: vertex " + std::to_string(u + 1) + " (line " + std::to_string(line_of[u]) +
                 ") does not list " + std::to_string(v + 1),
             line_of[v]);
    r.fail(edge + " has weight " + std::to_string(g.weight[e.k]) + " here but " + std::to_string(g.weight[e.reverse]) +
               " on vertex " + std::to_string(u + 1) + "'s line (line " + std::to_string(line_of[u]) + ")",
           line_of[v]);
  }
  if (g.edge_count() != m)
    r.fail("header says " + std::to_string(m) + " edges but the vertex lines list " + std::to_string(g.edge_count()),
           header_line);

  finish_graph(g, n);
  return out;
}

ConstraintGraph graph_from_arrays(const std::vector<int>& xadj, const std::vector<int>& adjncy,
                                  const std::vector<int>& adjwgt, const std::vector<double>& masses) {
  const auto fail = [](const std::string& what) { throw InputError(what); };
  const auto str = [](auto x) { return std::to_string(x); };
  if (xadj.size() < 2) fail("xadj needs n + 1 entries for n >= 1 nodes (got " + str(xadj.size()) + ")");
  const int n = static_cast<int>(xadj.size()) - 1;
  if (xadj[0] != 0) fail("xadj[0] must be 0 (got " + str(xadj[0]) + ")");
  for (int v = 0; v < n; ++v)
    if (xadj[v + 1] < xadj[v]) fail("xadj decreases at xadj[" + str(v + 1) + "] = " + str(xadj[v + 1]));
  if (static_cast<std::size_t>(xadj[n]) != adjncy.size())
    fail("xadj[n] = " + str(xadj[n]) + " but adjncy has " + str(adjncy.size()) + " entries");
  if (!adjwgt.empty() && adjwgt.size() != adjncy.size())
    fail(str(adjwgt.size()) + " edge weights for " + str(adjncy.size()) + " adjncy entries");
  if (!masses.empty() && masses.size() != static_cast<std::size_t>(n))
    fail(str(masses.size()) + " masses for " + str(n) + " nodes");
  for (std::size_t i = 0; i < masses.size(); ++i)
    if (!std::isfinite(masses[i]) || masses[i] <= 0) fail("masses[" + str(i) + "] is not positive and finite");

  ConstraintGraph g;
  g.offset = xadj;
  g.adjacency = adjncy;
  g.weight = adjwgt.empty() ? std::vector<int>(adjncy.size(), 1) : adjwgt;
  for (int v = 0; v < n; ++v)
    for (int k = xadj[v]; k < xadj[v + 1]; ++k) {
      const std::string entry = "adjncy[" + str(k) + "] = " + str(adjncy[k]);
      if (adjncy[k] < 0 || adjncy[k] >= n) fail(entry + " is outside 0.." + str(n - 1));
      if (adjncy[k] == v) fail(entry + " is a self loop on node " + str(v));
      if (g.weight[k] < 1) fail("edge weight " + str(g.weight[k]) + " of " + entry + " is not positive");
    }
  sort_neighbours(g);
  for (int v = 0; v < n; ++v) {
    const auto first = g.adjacency.begin() + g.offset[v], last = g.adjacency.begin() + g.offset[v + 1];
    const auto twice = std::adjacent_find(first, last);
    if (twice != last) fail("node " + str(v) + " lists node " + str(*twice) + " twice");
  }
  if (const UnpairedEdge e = find_unpaired_edge(g); e.k >= 0) {
    const std::string edge = "edge " + str(e.v) + "-" + str(g.adjacency[e.k]);
    if (e.reverse < 0) fail(edge + " has no reverse: node " + str(g.adjacency[e.k]) + " does not list " + str(e.v));
    fail(edge + " has weight " + str(g.weight[e.k]) + " but its reverse " + str(g.weight[e.reverse]));
  }
  finish_graph(g, n);
  if (!masses.empty()) g.mass = masses;
  return g;
}

MetisGraph read_metis_graph(const std::string& path) {
  std::ifstream in = open_input(path);
  return parse_metis_graph(in, path);
}

std::vector<double> parse_masses(std::istream& in, const std::string& name, int count) {
  LineReader r(in, name);
  std::vector<double> masses;
  while (r.next()) {
    const auto& t = r.tokens();
    if (t.empty()) continue;
    if (t.size() > 1) r.fail("more than one mass on the line");
    const double m = r.real(t[0], "mass");
    if (!std::isfinite(m) || m <= 0) r.fail("mass " + t[0] + " is not positive and finite");
    masses.push_back(m);
  }
  if (static_cast<int>(masses.size()) != count)
    r.fail(std::to_string(masses.size()) + " masses for " + std::to_string(count) + " vertices");
  return masses;
}

std::vector<double> read_masses(const std::string& path, int count) {
  std::ifstream in = open_input(path);
  return parse_masses(in, path, count);
}

std::string part_file_text(const Partition& partition) {
  std::string text;
  text.reserve(partition.part_of.size() * 4);
  char buffer[16];
  for (int p : partition.part_of) {
    text.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, p).ptr);
    text += '\n';
  }
  return text;
}

void write_part_file(const std::string& path, const Partition& partition) {
  write_file_atomically(path, part_file_text(partition));
}

}  // namespace rbpart
