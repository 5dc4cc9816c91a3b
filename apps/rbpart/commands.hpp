#pragma once
// The rbpart CLI: one file per subcommand. Each `add_*` registers its subcommand and returns the
// function that runs it once the command line is parsed.
#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <rbpart/scene.hpp>

namespace rbpart::cli {

using Run = std::function<int()>;

Run add_simulate(CLI::App& app);
Run add_scenes(CLI::App& app);

// "key=value" strings from --set, split; throws InputError on a missing '='.
std::vector<std::pair<std::string, std::string>> split_assignments(const std::vector<std::string>& sets);

// A built-in scene name (with --set overrides) or a path to a scene file.
SceneDef resolve_scene(const std::string& scene, const std::vector<std::string>& sets);

}  // namespace rbpart::cli
