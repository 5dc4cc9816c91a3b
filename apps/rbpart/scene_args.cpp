#include "apps/rbpart/commands.hpp"
#include "core/error.hpp"

namespace rbpart::cli {

std::vector<std::pair<std::string, std::string>> split_assignments(const std::vector<std::string>& sets) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const std::string& s : sets) {
    const auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0) throw InputError("--set '" + s + "': expected key=value");
    out.emplace_back(s.substr(0, eq), s.substr(eq + 1));
  }
  return out;
}

SceneDef resolve_scene(const std::string& scene, const std::vector<std::string>& sets) {
  return load_scene(scene, split_assignments(sets));
}

}  // namespace rbpart::cli
