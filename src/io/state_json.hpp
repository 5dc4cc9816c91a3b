#pragma once
// Final (or any) state as JSON (docs/design.md#contracts), so that two runs can be compared:
//   {"time": t, "bodies": [{"name", "position", "orientation" [w,x,y,z], "velocity",
//    "angular_velocity"}, ...], "params": {...}}
// in scene body order. Numbers round-trip exactly; "position" is that of the shape frame, the one a
// scene file gives, not the centre of mass.
#include "io/run_params.hpp"

#include <rbpart/scene.hpp>

#include <string>

namespace rbpart {

struct Bodies;

std::string state_to_json(const SceneDef& scene, const Bodies& bodies, double time,
                          const ParamList& params = {});

// state_to_json into `path`, atomically. "params" (the run's parameters, e.g. run_parameters())
// is written when not empty.
void write_state_json(const std::string& path, const SceneDef& scene, const Bodies& bodies, double time,
                      const ParamList& params = {});

}  // namespace rbpart
