// The substructured solver's driver (DESIGN.md §7): per island, the parts of its bodies, then the
// friction outer loop of DESIGN.md §3 around the substructured fixed-bounds solve
// (SubstructuredIsland::solve_fixed) and the coupled friction step on the substructured matrix,
// exactly as solve_direct runs them around its monolithic solve.
#include "solve/substructured.hpp"

#include "core/parallel.hpp"
#include "core/timer.hpp"
#include "solve/blcp.hpp"
#include "solve/direct_island.hpp"
#include "solve/island_parts.hpp"
#include "solve/island_system.hpp"
#include "solve/residual.hpp"
#include "solve/sub_island.hpp"

#include <algorithm>
#include <memory>
#include <numeric>
#include <stdexcept>

namespace rbpart {

namespace {

struct SplitOutcome {
  IslandOutcome island;  // passes, residual, failure; iterations/factorizations of monolithic solves
  SubIslandStats sub;    // phases, loop iterations (split islands)
  int parts = 1, interface_rows = 0, interface_bodies = 0;
  bool fallback = false;
  double monolithic_ms = 0, wall_ms = 0;
};

SplitOutcome solve_split_island(Rows& rows, const Bodies& bodies, const Islands& islands, int island,
                                const std::vector<int>& local_row, const ConstraintGraph& graph,
                                const Partition& partition, const SolverParams& params) {
  const Timer wall;
  SplitOutcome out;
  IslandSystem s;
  s.gather(rows, bodies, islands, island, local_row);
  const std::vector<int> part_of_body = island_parts(s, graph, partition);
  const int parts = *std::max_element(part_of_body.begin(), part_of_body.end()) + 1;
  if (parts < 2 || !(s.sigma.array() > 0).all()) {
    const Timer timer;
    out.island = solve_island(rows, bodies, islands, island, local_row, params);
    out.monolithic_ms = timer.ms();
    out.wall_ms = wall.ms();
    out.sub.critical_ms = out.wall_ms;
    out.sub.other_ms = out.wall_ms - out.monolithic_ms;
    return out;
  }
  out.parts = parts;

  Eigen::VectorXd lambda(s.rows), previous;
  std::vector<RowState> state(s.rows);
  for (int r = 0; r < s.rows; ++r) {
    lambda[r] = rows.lambda[s.global_rows[r]];
    state[r] = rows.state[s.global_rows[r]];
  }
  SubstructuredIsland sub;
  sub.assign(s, part_of_body, out.parts);
  out.interface_rows = sub.interface_rows();
  out.interface_bodies = sub.interface_bodies();

  const BlcpSettings settings = blcp_settings(params);
  // The fallback: a fixed-bounds solve whose iteration does not settle (iteration cap, halving
  // limit) or fails is solved by the monolithic backend from the same warm start (solve_fixed
  // leaves lambda and state as they were), and so is the rest of the step, coupled step included:
  // the earlier passes' work is kept, and a loop that did not settle on one pass's bounds is not
  // tried again on the next.
  std::unique_ptr<BlcpMatrix> direct;
  BlcpWorkspace direct_ws;
  auto on_direct = [&](auto&& fn) {
    const Timer timer;
    if (!direct) direct = make_direct_matrix(s, params);
    const bool solved = fn(*direct);
    out.monolithic_ms += timer.ms();
    return solved;
  };
  CoupledWorkspace coupled;
  Eigen::VectorXd w, du;
  const FrictionPassResult passes = friction_passes(
      s.coupling(), s.diag, lambda, state, s.lo, s.hi, params.friction_passes, params.friction_tolerance, previous,
      [&] {
        if (!out.fallback) {
          if (sub.solve_fixed(s.lo, s.hi, lambda, state, settings, params.substructured_max_iterations,
                              params.substructured_max_halvings))
            return true;
          out.fallback = true;
        }
        return on_direct([&](BlcpMatrix& a) {
          return out.island.count(solve_blcp(a, s.q, s.lo, s.hi, lambda, state, settings, direct_ws));
        });
      },
      [&]() -> const Eigen::VectorXd& {
        apply_a(s, lambda, du, w);
        w += s.q;
        return w;
      },
      [&] {
        if (out.fallback)
          return on_direct([&](BlcpMatrix& a) {
            const bool solved = coupled_friction_step(a, s.q, s.lo, s.hi, s.coupling(), lambda, state, settings, coupled);
            out.island.count(coupled);
            return solved;
          });
        bool solved = false;
        sub.serial(kCoupledPhase, [&] {
          solved = coupled_friction_step(sub, s.q, s.lo, s.hi, s.coupling(), lambda, state, settings, coupled);
        });
        return solved;
      });
  out.island.passes = passes.passes;
  out.island.unsettled = !passes.settled;
  out.island.failed = !passes.solved;  // a BLCP of the monolithic backend failed, as it would in solve_direct
  store_island_solution(s, lambda, state, rows);
  out.island.residual = island_residual(s, lambda, du, w);
  out.wall_ms = wall.ms();
  // The monolithic fallback is serial work.
  out.sub = sub.stats(out.wall_ms - out.monolithic_ms);
  out.sub.critical_ms += out.monolithic_ms;
  return out;
}

}  // namespace

SubstructuredReport solve_substructured(Rows& rows, const Bodies& bodies, const Islands& islands,
                                        const ConstraintGraph& graph, const Partition& partition,
                                        const SolverParams& params) {
  if (static_cast<int>(partition.part_of.size()) != graph.node_count())
    throw std::invalid_argument("solve_substructured: the partition does not cover the graph's nodes");
  const std::vector<int> local_row = local_row_index(rows, islands);
  const std::size_t count = islands.count();
  const std::vector<int> order = largest_islands_first(islands);
  std::vector<SplitOutcome> outcome(count);
  parallel_for_each(count, [&](std::size_t t) {
    const int i = order[t];
    outcome[i] = solve_split_island(rows, bodies, islands, i, local_row, graph, partition, params);
  });

  SubstructuredReport report;
  SolveReport& solve = report.solve;
  for (const SplitOutcome& o : outcome) {
    solve.iterations += o.island.iterations + o.sub.blcp_iterations;
    solve.friction_passes = std::max(solve.friction_passes, o.island.passes);
    solve.factorizations += o.island.factorizations + o.sub.factorizations;
    solve.newton_islands += o.island.newton || o.sub.newton;
    solve.failures += o.island.failed;
    solve.unsettled += o.island.unsettled;
    solve.residual = std::max(solve.residual, o.island.residual);
    report.parts += o.parts;
    report.interface_rows += o.interface_rows;
    report.interface_bodies += o.interface_bodies;
    report.loop_iterations += o.sub.loop_iterations;
    report.fallbacks += o.fallback;
    report.factor_ms += o.sub.phase_ms[kFactorPhase];
    report.schur_ms += o.sub.phase_ms[kSchurPhase];
    report.interface_ms += o.sub.phase_ms[kInterfacePhase];
    report.subsystem_ms += o.sub.phase_ms[kSubsystemPhase];
    report.coupled_ms += o.sub.phase_ms[kCoupledPhase];
    report.monolithic_ms += o.monolithic_ms;
    report.work_ms += o.monolithic_ms + o.sub.other_ms;
    for (double ms : o.sub.phase_ms) report.work_ms += ms;
    report.critical_path_ms = std::max(report.critical_path_ms, o.sub.critical_ms);
  }
  return report;
}

}  // namespace rbpart
