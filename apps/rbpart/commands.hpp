#pragma once
// The rbpart CLI: one file per subcommand. Each `add_*` registers its subcommand and returns the
// function that runs it once the command line is parsed.
#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <rbpart/params.hpp>
#include <rbpart/scene.hpp>

namespace rbpart::cli {

using Run = std::function<int()>;

Run add_simulate(CLI::App& app);
Run add_scenes(CLI::App& app);
Run add_partition(CLI::App& app);
Run add_view(CLI::App& app);
Run add_snapshot(CLI::App& app);
Run add_bench(CLI::App& app);

// Checks of numeric options whose errors name the bound: "--steps: must be at least 0 (got -3)".
CLI::Validator at_least(double lo);
CLI::Validator positive();
CLI::Validator open_closed(double lo, double hi);  // lo < x <= hi

// "key=value" strings from --set, split; throws InputError on a missing '='.
std::vector<std::pair<std::string, std::string>> split_assignments(const std::vector<std::string>& sets);

// A built-in scene name (with --set overrides) or a path to a scene file.
SceneDef resolve_scene(const std::string& scene, const std::vector<std::string>& sets);

// --partitioner, --refine, --nmax, --tau-mr, --tau-mix, --debug-checks, shared by `partition` and
// `simulate` (docs/design.md#partition, #refine); defined in partition.cpp.
struct PartitionOptions {
  std::string partitioner = "none", refiner = "none";
  PartitionParams params;
};
void add_partition_options(CLI::App* cmd, PartitionOptions& options, bool partitioner_required);
// The names parsed and the values checked (nmax >= 1, tau_mr > 1, 0 < tau_mix < 1); throws
// InputError naming the option otherwise.
PartitionParams partition_params(const PartitionOptions& options);

}  // namespace rbpart::cli
