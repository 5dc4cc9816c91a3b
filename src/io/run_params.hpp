#pragma once
// The parameters of a run as named text, reported in every output (stats header, state file) so a
// run can be reproduced from its outputs alone (docs/design.md#dynamics: "reported in outputs").
#include <rbpart/params.hpp>

#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

namespace rbpart {

using ParamList = std::vector<std::pair<std::string, std::string>>;

// Every field of StepParams and SolverParams, named as in params.hpp (the solver kind as
// "solver"), doubles in round-trip form: {"erp", "0.2"}, ..., {"solver", "direct"}, ...
ParamList run_parameters(const StepParams& step, const SolverParams& solver);
// The same followed by every field of PartitionParams ("partitioner" and "refiner" by their CLI
// names): {"partitioner", "mix"}, {"refiner", "fm"}, {"nmax", "32"}, ...
ParamList run_parameters(const StepParams& step, const SolverParams& solver, const PartitionParams& partition);

// The parameters as one JSON object of strings, in order: {"erp": "0.2", ...}. The stats sidecar,
// the state file and the recording report them so.
nlohmann::ordered_json params_json(const ParamList& params);

}  // namespace rbpart
