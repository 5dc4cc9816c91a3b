#include "study/replay.hpp"

#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "core/timer.hpp"
#include "partition/partition.hpp"
#include "solve/newton_substructured.hpp"
#include "solve/solve.hpp"

namespace rbpart {

namespace {

enum Phase { kPartition, kRefine, kSolve, kWork, kCriticalPath, kPhases };
using Sample = std::array<double, kPhases>;

double lambda_error(const std::vector<double>& lambda, const std::vector<double>& live) {
  double diff = 0, scale = 0;
  for (std::size_t j = 0; j < live.size(); ++j) {
    diff = std::max(diff, std::abs(lambda[j] - live[j]));
    scale = std::max(scale, std::abs(live[j]));
  }
  return scale > 0 ? diff / scale : diff;
}

// Sub-systems holding at least one row, so that bodies in free flight (graph nodes without rows,
// parts of their own) count for neither the direct baseline's islands nor the partitions.
int parts_with_rows(const StepProblem& p, const Partition& partition, std::vector<char>& seen) {
  seen.assign(partition.part_count, 0);
  int parts = 0;
  for (int body : p.islands.bodies) {
    char& s = seen[partition.part_of[p.graph.node_of[body]]];
    parts += !s;
    s = 1;
  }
  return parts;
}

class Runner {
 public:
  Runner(const SolverParams& solver, const PartitionParams& partition, std::size_t configs)
      : direct_(solver), sub_(solver), base_(partition), kept_(configs) {
    direct_.kind = SolverKind::Direct;
    sub_.kind = SolverKind::Substructured;
  }

  // One solve of `p` by configuration `index`, `c`; the counts are filled in only when `measure` is
  // set (first repeat).
  Sample run(const StepProblem& p, std::size_t index, const StudyConfig& c, bool measure, StepMeasure& m,
             int& mismatches) {
    Sample sample{};
    rows_ = p.rows;  // untimed: every solve starts from the recorded warm start
    SolveStats report;
    if (c.direct()) {
      direct_.threads = c.threads;
      {
        const Timer t;
        report = solve_newton_direct(rows_, p.bodies, p.islands, direct_);
        sample[kSolve] = t.ms();
      }
      if (!measure) return sample;
      m.parts = static_cast<int>(p.islands.count());
      // The fairness check: the replayed baseline must be the live solve, bit for bit.
      if (rows_.lambda.size() != p.live_lambda.size() ||
          (!rows_.lambda.empty() &&
           std::memcmp(rows_.lambda.data(), p.live_lambda.data(), rows_.lambda.size() * sizeof(double)) != 0))
        ++mismatches;
    } else {
      PartitionParams params = base_;
      params.partitioner = c.partitioner;
      params.refiner = c.refiner;
      params.nmax = c.nmax;
      sub_.threads = c.threads;
      // The parts of the step before are kept, as the World keeps them, when its graph is this
      // step's: a step made before this one, and seen the same up to the step before.
      Kept& k = kept_[index];
      bool kept = false;
      {
        const Timer t;
        kept = k.made < p.step && k.same_through >= p.step - 1 && same_partition_input(p.graph, k.graph);
        if (!kept) partition_graph(p.graph, params, k.partition);
        sample[kPartition] = t.ms();
      }
      if (kept) {
        k.same_through = p.step;
      } else {
        { const Timer t; refine_partition(p.graph, params, k.partition); sample[kRefine] = t.ms(); }
        const Timer t;
        k.graph = p.graph;
        k.made = k.same_through = p.step;
        sample[kPartition] += t.ms();
      }
      const Partition& partition = k.partition;
      NewtonSubstructuredReport sub;
      {
        const Timer t;
        sub = solve_newton_substructured(rows_, p.bodies, p.islands, p.graph, partition, sub_);
        sample[kSolve] = t.ms();
      }
      sample[kWork] = sub.solve.work_ms;
      sample[kCriticalPath] = sub.solve.critical_path_ms;
      if (!measure) return sample;
      report = sub.solve;
      const PartitionQuality q = measure_partition(p.graph, partition);
      m.parts = parts_with_rows(p, partition, seen_);
      m.interface_rows = q.interface_rows;
      m.interface_bodies = q.interface_bodies;
      m.edge_cut = q.edge_cut;
    }
    m.factorizations = report.factorizations;
    m.unsettled = report.unsettled;
    m.lambda_error = lambda_error(rows_.lambda, p.live_lambda);
    return sample;
  }

 private:
  SolverParams direct_, sub_;
  // A configuration's parts, the graph they were made of, the step whose graph that was, and the
  // last step whose graph was seen to be the same.
  struct Kept {
    Partition partition;
    ConstraintGraph graph;
    int made = -1, same_through = -1;
  };
  PartitionParams base_;
  std::vector<Kept> kept_;
  Rows rows_;
  std::vector<char> seen_;
};

}  // namespace

double median(std::vector<double>& v) {
  if (v.empty()) return 0;
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  if (v.size() % 2) return v[mid];
  return 0.5 * (v[mid] + *std::max_element(v.begin(), v.begin() + mid));
}

ReplayResult replay_trajectory(const Trajectory& trajectory, const std::vector<StudyConfig>& configs, int repeats,
                               const SolverParams& solver_params, const PartitionParams& partition_params,
                               const std::function<void()>& on_run) {
  const std::size_t steps = trajectory.steps.size();
  ReplayResult result;
  result.measures.assign(configs.size(), std::vector<StepMeasure>(steps));
  Runner runner(solver_params, partition_params, configs.size());

  std::vector<int> thread_counts;
  for (const StudyConfig& c : configs)
    if (std::find(thread_counts.begin(), thread_counts.end(), c.threads) == thread_counts.end())
      thread_counts.push_back(c.threads);

  std::vector<std::size_t> group;                      // the configurations of one thread count
  std::vector<std::vector<Sample>> samples;            // [config in group][repeat]
  std::vector<double> values(repeats);
  for (int threads : thread_counts) {
    // One limit for all the group's steps: changing it between solves would make the first solve
    // after each change pay for the worker arena's reconfiguration.
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    group.clear();
    for (std::size_t c = 0; c < configs.size(); ++c)
      if (configs[c].threads == threads) group.push_back(c);
    samples.assign(group.size(), std::vector<Sample>(repeats));
    for (std::size_t s = 0; s < steps; ++s) {
      const StepProblem& problem = trajectory.steps[s];
      for (int r = 0; r < repeats; ++r)
        for (std::size_t k = 0; k < group.size(); ++k) {
          const std::size_t g = (k + static_cast<std::size_t>(r)) % group.size();
          const std::size_t c = group[g];
          samples[g][r] = runner.run(problem, c, configs[c], r == 0, result.measures[c][s], result.direct_mismatches);
          if (on_run) on_run();
        }
      for (std::size_t g = 0; g < group.size(); ++g) {
        StepMeasure& m = result.measures[group[g]][s];
        double* const fields[kPhases] = {&m.partition_ms, &m.refine_ms, &m.solve_ms, &m.work_ms, &m.critical_path_ms};
        for (int phase = 0; phase < kPhases; ++phase) {
          for (int r = 0; r < repeats; ++r) values[r] = samples[g][r][phase];
          *fields[phase] = median(values);
        }
      }
    }
  }
  return result;
}

}  // namespace rbpart
