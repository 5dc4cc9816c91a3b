#pragma once
// The stages' data of a World's last step, for the CLI, the study, the recording and the tests. Not
// in include/rbpart/: their types are internal, and the public World exposes none of them.
#include <rbpart/world.hpp>

#include <functional>

#include "assembly/rows.hpp"
#include "graph/constraint_graph.hpp"
#include "graph/islands.hpp"
#include "partition/partition.hpp"
#include "scene/bodies.hpp"

namespace rbpart {

const Bodies& world_bodies(const World& world);
// The last step's constraint rows (with their impulses), islands and constraint graph: what the
// partitioners and the viewer are built from.
const Rows& world_rows(const World& world);
const Islands& world_islands(const World& world);
const ConstraintGraph& world_graph(const World& world);
// The last step's sub-systems: part id per graph node. The islands for the monolithic solvers
// without a partitioner; the partitioned and refined parts otherwise.
const Partition& world_partition(const World& world);
// Whether the last step kept the partition of the step before (the same graph: same_partition_input).
bool world_partition_kept(const World& world);

// Called every step just before the solve stage with the step's problem: the rows carrying their
// warm starts, the bodies (world inertia of this step), the islands and the constraint graph.
// `rbpart bench` records problems with it and replays them with every partitioner (src/study/).
using ProblemObserver = std::function<void(const Rows&, const Bodies&, const Islands&, const ConstraintGraph&)>;
void set_problem_observer(World& world, ProblemObserver observer);

}  // namespace rbpart
