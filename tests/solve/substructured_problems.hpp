#pragma once
// Step problems and partitions for the substructured solver's tests and bench/substructured_bench.cpp:
// the BLCP a World solves in one step, captured with the warm start the World gives it, and a
// breadth-first partition (any assignment of nodes to parts is valid input for the solver).
#include <rbpart/world.hpp>

#include "assembly/assemble.hpp"
#include "assembly/rows.hpp"
#include "graph/constraint_graph.hpp"
#include "graph/islands.hpp"
#include "integrate/integrate.hpp"
#include "partition/partition.hpp"
#include "scene/bodies.hpp"
#include "step/world_internals.hpp"

#include <queue>
#include <unordered_map>

namespace rbpart::testing {

struct StepProblem {
  Rows rows;
  Bodies bodies;
  Islands islands;
  ConstraintGraph graph;
};

// The warm start assembly gives a step's rows from the previous step's solved rows (assemble.cpp):
// impulses and sets by persistent key, a friction row's impulse as the previous friction impulse
// of its contact projected on its new tangent; other rows start at 0, normals at their lower bound.
inline void warm_start_from(const Rows& previous, Rows& rows) {
  std::unordered_map<std::uint64_t, int> index;
  for (std::size_t j = 0; j < previous.size(); ++j) index.emplace(previous.key[j], static_cast<int>(j));
  auto friction_direction = [](const Rows& r, int j) {
    return r.body[j][0] >= 0 ? Vec3(r.jac[j][0].head<3>()) : Vec3(-r.jac[j][1].head<3>());
  };
  for (std::size_t j = 0; j < rows.size(); ++j) {
    rows.lambda[j] = 0;
    rows.state[j] = rows.kind[j] == RowKind::Normal ? RowState::Lower : RowState::Free;
    const auto it = index.find(rows.key[j]);
    if (it != index.end()) rows.state[j] = previous.state[it->second];
    if (rows.kind[j] != RowKind::Friction) {
      if (it != index.end()) rows.lambda[j] = previous.lambda[it->second];
      continue;
    }
    Vec3 impulse = Vec3::Zero();
    const std::uint64_t contact = rows.key[j] / 4;
    for (int k = 1; k <= 2; ++k) {
      const auto e = index.find(contact_row_key(contact, k));
      if (e != index.end()) impulse += previous.lambda[e->second] * friction_direction(previous, e->second);
    }
    rows.lambda[j] = impulse.dot(friction_direction(rows, static_cast<int>(j)));
  }
}

// Advances `world` one step and returns that step's BLCP with the warm start it was solved from.
inline StepProblem capture_step(World& world) {
  const Rows previous = world_rows(world);
  StepProblem p;
  p.bodies = world_bodies(world);
  update_world_inertia(p.bodies);  // as assembly does before it builds the rows
  world.step();
  p.rows = world_rows(world);
  p.islands = world_islands(world);
  p.graph = world_graph(world);
  warm_start_from(previous, p.rows);
  return p;
}

// Breadth-first parts of at most nmax nodes, seeded at the lowest unassigned node (DESIGN.md §5's
// BFS, written here so the solver's tests do not depend on the partitioners').
inline Partition bfs_partition(const ConstraintGraph& g, int nmax) {
  Partition p;
  p.part_of.assign(g.node_count(), -1);
  for (int seed = 0; seed < g.node_count(); ++seed) {
    if (p.part_of[seed] >= 0) continue;
    const int id = p.part_count++;
    std::queue<int> queue;
    queue.push(seed);
    p.part_of[seed] = id;
    int size = 1;
    while (!queue.empty() && size < nmax) {
      const int v = queue.front();
      queue.pop();
      for (int e = g.offset[v]; e < g.offset[v + 1] && size < nmax; ++e)
        if (p.part_of[g.adjacency[e]] < 0) {
          p.part_of[g.adjacency[e]] = id;
          queue.push(g.adjacency[e]);
          ++size;
        }
    }
  }
  return p;
}

}  // namespace rbpart::testing
