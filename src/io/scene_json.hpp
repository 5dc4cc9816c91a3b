#pragma once
// Scene files (docs/design.md#contracts): JSON, z up, SI units, quaternions [w, x, y, z]. Loading is strict —
// unknown keys, wrong types, duplicate keys, non-finite numbers and physically meaningless values are
// rejected with one line naming the file, the field path and the problem, e.g.   scene.json:
// bodies[3].shape.radius: must be positive (got -0.5) Extensions to the format of docs/design.md#contracts:
// "steps" (the scene's default step count) and a joint's "collide_connected" (whether the joined bodies
// collide; default false).
#include <rbpart/scene.hpp>
#include <rbpart/world.hpp>

#include <string>
#include <vector>

namespace rbpart {

// Reads and validates a scene file; throws InputError prefixed with `path`.
SceneDef load_scene_file(const std::string& path);

// Validates scene text; errors are prefixed with `source_name`. Optional keys take the SceneDef
// defaults (a body's name defaults to "body<i>"); a quaternion is normalised unless it is already
// unit to within 1e-12, so that loading an exported scene reproduces it bit for bit.
SceneDef parse_scene(const std::string& text, const std::string& source_name);

// Every field of the scene as scene-file JSON; parse_scene of the result gives back the same
// SceneDef bit for bit (a body's mass is written instead of its density when both are set, as the
// engine uses the mass then; a friction < 0, "the scene default", is left out).
std::string scene_to_json(const SceneDef& scene);

// A state file (docs/formats.md#state-file, what state_to_json writes) as the state to continue
// `scene` from (World::restart), read as strictly as a scene file: the same body count and names in
// scene order, every field present, unit quaternions (to 1e-6; kept bit for bit when unit to 1e-12,
// else normalised), static bodies at the scene's pose and at rest. "params" is not read. Throws
// InputError prefixed with the file or `source_name`.
struct SceneState {
  double time = 0;                // s, >= 0
  std::vector<BodyState> bodies;  // scene order
};
SceneState parse_state(const std::string& text, const std::string& source_name, const SceneDef& scene);
SceneState load_state_file(const std::string& path, const SceneDef& scene);

// scene_to_json into `path`, atomically.
void write_scene_file(const std::string& path, const SceneDef& scene);

}  // namespace rbpart
