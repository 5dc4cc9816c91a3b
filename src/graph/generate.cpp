#include "graph/generate.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace rbpart {

namespace {

// splitmix64: the same stream on every platform and standard library (std::*_distribution is not).
struct Rng {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  int below(int n) { return static_cast<int>(next() % static_cast<std::uint64_t>(n)); }  // [0, n)
  int between(int lo, int hi) { return lo + below(hi - lo + 1); }                          // [lo, hi]
};

using Point = std::array<double, 3>;

GraphEdge contact_edge(int a, int b, int points) { return {a, b, points, 3 * points}; }

// Edges between points closer than r (j > i, `skip(i, j)` false), found through a sorted cell list
// of cell size r so the cost is O(n log n) whatever the points' extent. Each edge gets 1..max_points
// contact points, drawn in a fixed order (deterministic).
template <class Skip>
void connect_near(const std::vector<Point>& p, double r, int max_points, Rng& rng, Skip skip,
                  std::vector<GraphEdge>& edges) {
  const int n = static_cast<int>(p.size());
  auto cell_key = [r](const Point& x, int dx, int dy, int dz) {
    auto c = [r](double v, int d) { return static_cast<std::uint64_t>(std::floor(v / r) + d + (1 << 20)); };
    return (c(x[0], dx) << 42) | (c(x[1], dy) << 21) | c(x[2], dz);
  };
  std::vector<std::pair<std::uint64_t, int>> cells(n);
  for (int i = 0; i < n; ++i) cells[i] = {cell_key(p[i], 0, 0, 0), i};
  std::sort(cells.begin(), cells.end());
  for (int i = 0; i < n; ++i)
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const std::uint64_t key = cell_key(p[i], dx, dy, dz);
          for (auto it = std::lower_bound(cells.begin(), cells.end(), std::make_pair(key, 0));
               it != cells.end() && it->first == key; ++it) {
            const int j = it->second;
            if (j <= i || skip(i, j)) continue;
            const double d2 = (p[i][0] - p[j][0]) * (p[i][0] - p[j][0]) +
                              (p[i][1] - p[j][1]) * (p[i][1] - p[j][1]) +
                              (p[i][2] - p[j][2]) * (p[i][2] - p[j][2]);
            if (d2 < r * r) edges.push_back(contact_edge(i, j, rng.between(1, max_points)));
          }
        }
}

bool never(int, int) { return false; }

}  // namespace

ConstraintGraph make_graph(int nodes, const std::vector<GraphEdge>& edges, std::vector<double> masses) {
  if (nodes < 0) throw std::invalid_argument("make_graph: negative node count");
  if (masses.empty()) masses.assign(nodes, 1.0);
  if (static_cast<int>(masses.size()) != nodes) throw std::invalid_argument("make_graph: one mass per node expected");
  for (double m : masses)
    if (!(m > 0) || !std::isfinite(m)) throw std::invalid_argument("make_graph: masses must be positive and finite");

  // Both directions of every edge, sorted by (from, to), then merged per pair.
  std::vector<GraphEdge> half;
  half.reserve(2 * edges.size());
  for (const GraphEdge& e : edges) {
    if (e.a < 0 || e.a >= nodes || e.b < 0 || e.b >= nodes) throw std::invalid_argument("make_graph: edge end out of range");
    if (e.a == e.b) throw std::invalid_argument("make_graph: self loop");
    if (e.weight < 1 || e.rows < 1) throw std::invalid_argument("make_graph: weight and rows must be at least 1");
    half.push_back(e);
    half.push_back({e.b, e.a, e.weight, e.rows});
  }
  std::sort(half.begin(), half.end(),
            [](const GraphEdge& x, const GraphEdge& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; });

  ConstraintGraph g;
  g.body_of.resize(nodes);
  std::iota(g.body_of.begin(), g.body_of.end(), 0);
  g.node_of = g.body_of;
  g.mass = std::move(masses);
  g.offset.assign(nodes + 1, 0);
  for (std::size_t i = 0; i < half.size(); ++i) {
    if (i > 0 && half[i].a == half[i - 1].a && half[i].b == half[i - 1].b) {
      g.weight.back() += half[i].weight;
      g.rows.back() += half[i].rows;
      continue;
    }
    g.adjacency.push_back(half[i].b);
    g.weight.push_back(half[i].weight);
    g.rows.push_back(half[i].rows);
    ++g.offset[half[i].a + 1];
  }
  std::partial_sum(g.offset.begin(), g.offset.end(), g.offset.begin());
  return g;
}

ConstraintGraph pile_graph(int nodes, std::uint64_t seed) {
  Rng rng{seed};
  const int nz = std::max(1, static_cast<int>(std::ceil(std::cbrt(nodes / 4.0))));
  const int nxy = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(nodes) / nz))));
  std::vector<Point> p(nodes);
  for (int k = 0; k < nodes; ++k) {
    const int layer = k / (nxy * nxy), in_layer = k % (nxy * nxy);
    const Point site{double(in_layer % nxy), double(in_layer / nxy), double(layer)};
    for (int c = 0; c < 3; ++c) p[k][c] = site[c] + 0.7 * (rng.uniform() - 0.5);
  }
  std::vector<GraphEdge> edges;
  connect_near(p, 1.3, 4, rng, never, edges);
  return make_graph(nodes, edges);
}

ConstraintGraph random_geometric_graph(int nodes, double mean_degree, std::uint64_t seed) {
  Rng rng{seed};
  std::vector<Point> p(nodes);
  for (Point& x : p)
    for (double& c : x) c = rng.uniform();
  // (4/3) pi r^3 n = mean degree, ignoring the cube's boundary.
  const double r = nodes > 0 ? std::cbrt(3.0 * mean_degree / (4.0 * M_PI * nodes)) : 1.0;
  std::vector<GraphEdge> edges;
  connect_near(p, r, 4, rng, never, edges);
  return make_graph(nodes, edges);
}

ConstraintGraph grid_graph(int nx, int ny, int nz) {
  std::vector<GraphEdge> edges;
  auto id = [&](int i, int j, int k) { return i + nx * (j + ny * k); };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        if (i + 1 < nx) edges.push_back({id(i, j, k), id(i + 1, j, k)});
        if (j + 1 < ny) edges.push_back({id(i, j, k), id(i, j + 1, k)});
        if (k + 1 < nz) edges.push_back({id(i, j, k), id(i, j, k + 1)});
      }
  return make_graph(nx * ny * nz, edges);
}

ConstraintGraph folded_path_graph(int nodes, std::uint64_t seed) {
  Rng rng{seed};
  // A walk on the ground plane (a 2D walk keeps coming back, so the chain folds onto itself); it
  // keeps its direction with probability 0.6 and never steps straight back.
  static constexpr int step[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
  std::vector<Point> p(nodes);
  int dir = 0, x = 0, y = 0;
  std::vector<GraphEdge> edges;
  for (int k = 0; k < nodes; ++k) {
    if (k > 0) {
      if (rng.uniform() >= 0.6) dir = (dir + rng.between(-1, 1) + 4) % 4;
      x += step[dir][0];
      y += step[dir][1];
      edges.push_back({k - 1, k, 1, 3});  // ball joint
    }
    p[k] = {double(x), double(y), 0.0};
  }
  connect_near(p, 1.01, 2, rng, [](int i, int j) { return j - i <= 1; }, edges);
  return make_graph(nodes, edges);
}

ConstraintGraph star_graph(int leaves) {
  std::vector<GraphEdge> edges;
  for (int k = 1; k <= leaves; ++k) edges.push_back({0, k});
  return make_graph(leaves + 1, edges);
}

ConstraintGraph clique_graph(int nodes) {
  std::vector<GraphEdge> edges;
  for (int a = 0; a < nodes; ++a)
    for (int b = a + 1; b < nodes; ++b) edges.push_back({a, b});
  return make_graph(nodes, edges);
}

ConstraintGraph islands_graph(int count, int max_size, std::uint64_t seed) {
  Rng rng{seed};
  std::vector<int> size(count);
  for (int& s : size) s = rng.between(1, max_size);
  const int n = std::accumulate(size.begin(), size.end(), 0);
  // A random permutation (Fisher-Yates) scatters every island's nodes over the index range.
  std::vector<int> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  for (int i = n - 1; i > 0; --i) std::swap(perm[i], perm[rng.below(i + 1)]);
  std::vector<GraphEdge> edges;
  for (int c = 0, start = 0; c < count; start += size[c++]) {
    const int* island = perm.data() + start;
    for (int t = 1; t < size[c]; ++t) edges.push_back(contact_edge(island[t], island[rng.below(t)], rng.between(1, 4)));
    for (int extra = 0; extra < size[c] / 3; ++extra) {
      const int a = rng.below(size[c]), b = rng.below(size[c]);
      if (a != b) edges.push_back(contact_edge(island[a], island[b], rng.between(1, 4)));
    }
  }
  return make_graph(n, edges);
}

std::vector<double> random_masses(int nodes, std::uint64_t seed) {
  Rng rng{seed};
  static constexpr double choice[3] = {10.0, 100.0, 1000.0};
  std::vector<double> m(nodes);
  for (double& x : m) x = choice[rng.below(3)];
  return m;
}

ConstraintGraph with_masses(ConstraintGraph graph, std::vector<double> masses) {
  if (static_cast<int>(masses.size()) != graph.node_count())
    throw std::invalid_argument("with_masses: one mass per node expected");
  graph.mass = std::move(masses);
  return graph;
}

std::vector<GeneratedGraph> graph_suite(int count, std::uint64_t seed) {
  constexpr int families = 11;
  std::vector<GeneratedGraph> out;
  out.reserve(count);
  for (int i = 0; i < count; ++i) {
    Rng rng{seed ^ (0xA24BAED4963EE407ull * (i + 1))};
    const std::uint64_t s = rng.next();
    GeneratedGraph g;
    auto named = [&](std::string name, ConstraintGraph graph) {
      g.name = std::move(name) + " seed " + std::to_string(s);
      g.graph = std::move(graph);
    };
    switch (i % families) {
      case 0: { const int n = rng.between(1, 300); named("pile n=" + std::to_string(n), pile_graph(n, s)); break; }
      case 1: {
        const int n = rng.between(1, 300);
        const double d = 2.0 + 8.0 * rng.uniform();
        named("geometric n=" + std::to_string(n) + " degree " + std::to_string(d), random_geometric_graph(n, d, s));
        break;
      }
      case 2: {
        const int nx = rng.between(1, 15), ny = rng.between(1, 15);
        named("grid " + std::to_string(nx) + "x" + std::to_string(ny), grid_graph(nx, ny));
        break;
      }
      case 3: {
        const int nx = rng.between(1, 6), ny = rng.between(1, 6), nz = rng.between(1, 6);
        named("grid " + std::to_string(nx) + "x" + std::to_string(ny) + "x" + std::to_string(nz),
              grid_graph(nx, ny, nz));
        break;
      }
      case 4: {
        const int n = rng.between(1, 200);
        named("folded path n=" + std::to_string(n), folded_path_graph(n, s));
        break;
      }
      case 5: { const int l = rng.between(0, 60); named("star leaves=" + std::to_string(l), star_graph(l)); break; }
      case 6: { const int n = rng.between(1, 25); named("clique n=" + std::to_string(n), clique_graph(n)); break; }
      case 7: {
        const int c = rng.between(1, 40), m = rng.between(1, 20);
        named("islands count=" + std::to_string(c) + " max=" + std::to_string(m), islands_graph(c, m, s));
        break;
      }
      case 8: { const int n = rng.between(1, 50); named("isolated n=" + std::to_string(n), make_graph(n, {})); break; }
      case 9: named("single node", make_graph(1, {})); break;
      default: named("empty", make_graph(0, {})); break;
    }
    if ((i / families) % 2 == 1) {
      std::vector<double> masses = random_masses(g.graph.node_count(), s + 1);
      g.graph = with_masses(std::move(g.graph), std::move(masses));
      g.name += " masses";
    }
    out.push_back(std::move(g));
  }
  return out;
}

}  // namespace rbpart
