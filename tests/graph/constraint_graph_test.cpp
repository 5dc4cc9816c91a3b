// The constraint graph against hand-counted examples and structural properties on random rows.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <utility>

#include "assembly/assemble.hpp"
#include "graph/constraint_graph.hpp"
#include "graph/islands.hpp"

namespace rbpart {
namespace {

Bodies make_bodies(const std::vector<bool>& is_static) {
  Bodies b;
  for (std::size_t i = 0; i < is_static.size(); ++i) {
    b.is_static.push_back(is_static[i]);
    b.mass.push_back(is_static[i] ? 0.0 : 1.0 + i);
  }
  b.x.resize(is_static.size());
  return b;
}

// A contact point between a and b: one normal row and two friction rows.
void add_contact(Rows& rows, int a, int b, std::uint64_t id) {
  const int n = rows.add(RowKind::Normal, a, b, contact_row_key(id, 0));
  for (int k = 1; k <= 2; ++k) rows.normal_of[rows.add(RowKind::Friction, a, b, contact_row_key(id, k))] = n;
}

void add_ball_joint(Rows& rows, int a, int b, int joint) {
  for (int k = 0; k < 3; ++k) rows.add(RowKind::Joint, a, b, joint_row_key(joint, k));
}

TEST(ConstraintGraph, HandCountedWeightsRowsAndDegrees) {
  // Bodies 0 (static), 1, 2, 3 dynamic, 4 dynamic and isolated.
  const Bodies bodies = make_bodies({true, false, false, false, false});
  Rows rows;
  for (int p = 0; p < 4; ++p) add_contact(rows, 1, 2, p);  // a face: 4 points
  add_ball_joint(rows, 3, 2, 0);                           // one joint, 3 rows
  add_contact(rows, 3, 0, 10);                             // with a static body: no edge
  add_contact(rows, 3, -1, 11);
  ConstraintGraph g;
  build_constraint_graph(rows, bodies, g);
  ASSERT_EQ(g.node_count(), 4);
  EXPECT_EQ(g.node_of[0], -1);
  EXPECT_EQ(g.body_of, (std::vector<int>{1, 2, 3, 4}));
  EXPECT_EQ(g.edge_count(), 2);
  // Node 0 = body 1: one edge to node 1 (body 2) of weight 4 and 12 rows.
  EXPECT_EQ(g.offset, (std::vector<int>{0, 1, 3, 4, 4}));
  EXPECT_EQ(g.adjacency, (std::vector<int>{1, 0, 2, 1}));
  EXPECT_EQ(g.weight, (std::vector<int>{4, 4, 1, 1}));
  EXPECT_EQ(g.rows, (std::vector<int>{12, 12, 3, 3}));
  EXPECT_EQ(g.degree(0), 4);
  EXPECT_EQ(g.degree(1), 5);
  EXPECT_EQ(g.degree(2), 1);
  EXPECT_EQ(g.degree(3), 0);
  EXPECT_DOUBLE_EQ(g.mass[2], 4.0);
}

TEST(ConstraintGraph, RandomRowsGiveASymmetricGraphConsistentWithIslands) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + static_cast<int>(rng() % 30);
    std::vector<bool> is_static(n);
    for (int i = 0; i < n; ++i) is_static[i] = rng() % 5 == 0;
    const Bodies bodies = make_bodies(is_static);
    Rows rows;
    const int constraints = static_cast<int>(rng() % 60);
    int expected_weight = 0;
    std::map<std::pair<int, int>, std::pair<int, int>> pair_count;  // (body, body) -> (constraints, rows)
    for (int c = 0; c < constraints; ++c) {
      const int a = static_cast<int>(rng() % n), b = static_cast<int>(rng() % (n + 1)) - 1;
      if (b == a || is_static[a]) continue;
      const int bb = b >= 0 && is_static[b] ? -1 : b;
      if (rng() % 3 == 0) add_ball_joint(rows, a, bb, c);
      else add_contact(rows, a, bb, c);
      expected_weight += bb >= 0;
      if (bb >= 0) {
        for (const auto& key : {std::make_pair(a, bb), std::make_pair(bb, a)}) {
          ++pair_count[key].first;
          pair_count[key].second += 3;
        }
      }
    }
    ConstraintGraph g;
    build_constraint_graph(rows, bodies, g);
    int total_weight = 0;
    for (int i = 0; i < g.node_count(); ++i) {
      total_weight += g.degree(i);
      for (int e = g.offset[i]; e < g.offset[i + 1]; ++e) {
        const int j = g.adjacency[e];
        EXPECT_NE(i, j);
        if (e > g.offset[i]) EXPECT_LT(g.adjacency[e - 1], j);
        // The reverse edge exists with the same weight and rows.
        const auto first = g.adjacency.begin() + g.offset[j], last = g.adjacency.begin() + g.offset[j + 1];
        const auto it = std::lower_bound(first, last, i);
        ASSERT_TRUE(it != last && *it == i);
        EXPECT_EQ(g.weight[it - g.adjacency.begin()], g.weight[e]);
        EXPECT_EQ(g.rows[it - g.adjacency.begin()], g.rows[e]);
      }
    }
    EXPECT_EQ(total_weight, 2 * expected_weight);
    // Every pair's edge, counted by hand.
    std::size_t edges = 0;
    for (int i = 0; i < g.node_count(); ++i)
      for (int e = g.offset[i]; e < g.offset[i + 1]; ++e, ++edges) {
        const auto it = pair_count.find({g.body_of[i], g.body_of[g.adjacency[e]]});
        ASSERT_TRUE(it != pair_count.end());
        EXPECT_EQ(g.weight[e], it->second.first);
        EXPECT_EQ(g.rows[e], it->second.second);
      }
    EXPECT_EQ(edges, pair_count.size());
    // Edges never join two islands.
    Islands islands;
    build_islands(rows, n, islands);
    std::vector<int> island_of(n, -1);
    for (std::size_t k = 0; k < islands.count(); ++k)
      for (int e = islands.body_offset[k]; e < islands.body_offset[k + 1]; ++e) island_of[islands.bodies[e]] = k;
    for (int i = 0; i < g.node_count(); ++i)
      for (int e = g.offset[i]; e < g.offset[i + 1]; ++e)
        EXPECT_EQ(island_of[g.body_of[i]], island_of[g.body_of[g.adjacency[e]]]);
  }
}

}  // namespace
}  // namespace rbpart
