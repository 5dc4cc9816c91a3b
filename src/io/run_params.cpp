#include "io/run_params.hpp"

#include "io/text_format.hpp"
#include "partition/partition.hpp"

namespace rbpart {

namespace {

const char* solver_name(SolverKind kind) {
  switch (kind) {
    case SolverKind::Direct: return "direct";
    case SolverKind::Pgs: return "pgs";
    case SolverKind::Substructured: return "substructured";
  }
  return "unknown";
}

}  // namespace

ParamList run_parameters(const StepParams& step, const SolverParams& solver) {
  const auto real = [](double value) { return round_trip(value); };
  const auto integer = [](int value) { return std::to_string(value); };
  return {
      {"erp", real(step.erp)},
      {"slop", real(step.slop)},
      {"sigma_floor", real(step.sigma_floor)},
      {"contact_prox", real(step.contact_prox)},
      {"sliding_velocity_eps", real(step.sliding_velocity_eps)},
      {"contact_margin", real(step.contact_margin)},
      {"joint_projection_iterations", integer(step.joint_projection_iterations)},
      {"joint_tolerance", real(step.joint_tolerance)},
      {"projection_depth", real(step.projection_depth)},
      {"projection_turn", real(step.projection_turn)},
      {"solver", solver_name(solver.kind)},
      {"max_factorizations", integer(solver.max_factorizations)},
      {"pgs_iterations", integer(solver.pgs_iterations)},
      {"pgs_tolerance", real(solver.pgs_tolerance)},
      {"threads", integer(solver.threads)},
  };
}

ParamList run_parameters(const StepParams& step, const SolverParams& solver, const PartitionParams& partition) {
  ParamList params = run_parameters(step, solver);
  params.insert(params.end(), {{"partitioner", partitioner_name(partition.partitioner)},
                               {"refiner", refiner_name(partition.refiner)},
                               {"nmax", std::to_string(partition.nmax)},
                               {"tau_mr", round_trip(partition.tau_mr)},
                               {"tau_mix", round_trip(partition.tau_mix)},
                               {"debug_checks", partition.debug_checks ? "1" : "0"}});
  return params;
}

nlohmann::ordered_json params_json(const ParamList& params) {
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  for (const auto& [key, value] : params) out[key] = value;
  return out;
}

}  // namespace rbpart
