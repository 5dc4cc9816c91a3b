// rbpart scenes: list the built-in scenes, or export one as a scene file (docs/design.md#contracts).
#include <cstdio>

#include "apps/rbpart/commands.hpp"
#include "io/scene_json.hpp"
#include "scenes/scenes.hpp"

namespace rbpart::cli {

Run add_scenes(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("scenes", "List the built-in scenes, or export one as JSON");
  struct Options {
    std::string export_name;
    std::vector<std::string> sets;
    bool verbose = false;
  };
  auto o = std::make_shared<Options>();
  cmd->add_option("--export", o->export_name, "Write the scene NAME as a scene file to stdout");
  cmd->add_option("--set", o->sets, "Scene parameter override key=value (repeatable)");
  cmd->add_flag("-v,--verbose", o->verbose, "Also list every scene's parameters and defaults");
  return [o]() {
    if (!o->export_name.empty()) {
      const SceneDef scene = resolve_scene(o->export_name, o->sets);
      std::fputs(scene_to_json(scene).c_str(), stdout);
      std::fputc('\n', stdout);
      return 0;
    }
    std::printf("%-16s %7s %7s %6s  %s\n", "scene", "bodies", "joints", "steps", "description");
    for (const SceneInfo& info : builtin_scenes()) {
      const SceneDef s = make_builtin_scene(info.name);
      int dynamic = 0;
      for (const BodyDef& b : s.bodies) dynamic += !b.is_static;
      std::printf("%-16s %7d %7zu %6d  %s\n", info.name.c_str(), dynamic, s.joints.size(), s.steps,
                  info.description.c_str());
      if (o->verbose)
        for (const SceneParameter& p : info.parameters)
          std::printf("    --set %s=%g  %s\n", p.name.c_str(), p.value, p.help.c_str());
    }
    return 0;
  };
}

}  // namespace rbpart::cli
