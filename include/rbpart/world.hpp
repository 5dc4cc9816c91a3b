#pragma once
// A World advances a scene in time: collide -> assemble -> graph -> (partition -> refine) -> solve
// -> integrate (docs/design.md#step), each stage timed into the step's profile.
#include <rbpart/params.hpp>
#include <rbpart/scene.hpp>

#include <cstdint>
#include <functional>
#include <memory>

namespace rbpart {

struct Bodies;
struct Rows;
struct Islands;
struct ConstraintGraph;
struct Partition;

// Wall time of each stage of one step, named after the stage (ms).
struct StepProfile {
  double collide_ms = 0, assemble_ms = 0, graph_ms = 0, partition_ms = 0, refine_ms = 0, solve_ms = 0,
         integrate_ms = 0, total_ms = 0;
};

// Per-step statistics (docs/design.md#contracts: one CSV line per step).
struct StepStats {
  int step = 0;
  int bodies = 0;            // dynamic bodies
  int contacts = 0;
  int rows = 0;
  int islands = 0;
  int parts = 0;             // sub-systems (= islands for the monolithic solvers)
  int interface_rows = 0;
  int interface_bodies = 0;
  int edge_cut = 0;
  int solver_iterations = 0;
  int friction_passes = 0;
  int factorizations = 0;
  // Islands the solver could not finish within its caps; for the substructured solver also the
  // islands it handed to the monolithic solve after its iteration cap (docs/design.md#substructured).
  int fallbacks = 0;
  // Islands whose friction loop (docs/design.md#contact-problem) ended above its tolerance: approximate
  // impulses.
  int unsettled = 0;
  double residual = 0;       // scaled natural-map residual of the step's BLCP
  double max_penetration = 0;  // m, deepest contact after collision
  double kinetic_energy = 0;   // J, after the step
  StepProfile profile;
  // Substructured solver only (0 otherwise): iterations of docs/design.md#substructured's
  // interface/sub-system loop, and the solve's work per phase summed over threads and islands (ms):
  // factorisations, Schur complement (effective inverse masses, S and q~), interface BLCPs, sub-system BLCPs;
  // all work including set-up, monolithic one-part islands and fallbacks; and the critical path (each
  // parallel section replaced by its slowest part), which bounds the solve time on many cores.
  int loop_iterations = 0;
  double factor_ms = 0, schur_ms = 0, interface_ms = 0, subsystem_ms = 0, work_ms = 0, critical_path_ms = 0;
};

class World {
 public:
  // With a partitioner in `partition_params` every step partitions and refines the constraint graph
  // (docs/design.md#partition, #refine) and reports the partition's quality in its stats.
  World(SceneDef scene, StepParams step_params = {}, SolverParams solver_params = {},
        PartitionParams partition_params = {});
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  // Advances one time step of the scene's dt.
  const StepStats& step();

  double time() const;
  int step_count() const;
  const SceneDef& scene() const;
  const StepParams& step_params() const;
  const SolverParams& solver_params() const;
  const PartitionParams& partition_params() const;
  const Bodies& bodies() const;
  // The last step's constraint rows (with their impulses), islands and constraint graph: what the
  // partitioners and the viewer are built from.
  const Rows& rows() const;
  const Islands& islands() const;
  const ConstraintGraph& graph() const;
  // The last step's sub-systems: part id per graph node. The islands for the monolithic solvers
  // without a partitioner; the partitioned and refined parts otherwise.
  const Partition& partition() const;
  // FNV-1a over the bit patterns of every body's state: equal hashes = identical runs.
  std::uint64_t state_hash() const;

  // Called every step just before the solve stage with the step's problem: the rows carrying their
  // warm starts, the bodies (world inertia of this step), the islands and the constraint graph.
  // `rbpart bench` records problems with it and replays them with every partitioner (src/study/).
  using ProblemObserver = std::function<void(const Rows&, const Bodies&, const Islands&, const ConstraintGraph&)>;
  void set_problem_observer(ProblemObserver observer);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rbpart
