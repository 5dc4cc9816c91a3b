#include <fstream>

#include "apps/rbpart/commands.hpp"
#include "core/error.hpp"
#include "io/scene_json.hpp"
#include "scenes/scenes.hpp"

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
  for (const SceneInfo& info : builtin_scenes())
    if (info.name == scene) return make_builtin_scene(scene, split_assignments(sets));
  if (!sets.empty()) throw InputError("--set applies to built-in scenes only, not to the file '" + scene + "'");
  if (!std::ifstream(scene))
    throw InputError("--scene '" + scene + "': neither a built-in scene (rbpart scenes) nor a readable file");
  return load_scene_file(scene);
}

}  // namespace rbpart::cli
