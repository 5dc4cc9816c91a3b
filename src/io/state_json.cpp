#include "io/state_json.hpp"

#include "io/atomic_file.hpp"
#include "io/text_format.hpp"
#include "scene/bodies.hpp"

#include <stdexcept>

namespace rbpart {

namespace {

using Json = nlohmann::ordered_json;

Json vec3_json(const Vec3& v) { return Json::array({v.x(), v.y(), v.z()}); }

}  // namespace

std::string state_to_json(const SceneDef& scene, const Bodies& bodies, double time, const ParamList& params) {
  if (bodies.size() != static_cast<int>(scene.bodies.size()))
    throw std::logic_error("state_to_json: the bodies do not belong to the scene");
  Json out = Json::object();
  out["time"] = time;
  Json list = Json::array();
  for (int i = 0; i < bodies.size(); ++i) {
    const Quat& q = bodies.q[i];
    // A non-finite state (a diverged run) is written as null: JSON has no NaN or infinity.
    list.push_back(Json{{"name", scene.bodies[i].name},
                        {"position", vec3_json(bodies.frame_position(i))},
                        {"orientation", Json::array({q.w(), q.x(), q.y(), q.z()})},
                        {"velocity", vec3_json(bodies.v[i])},
                        {"angular_velocity", vec3_json(bodies.w[i])}});
  }
  out["bodies"] = std::move(list);
  if (!params.empty()) out["params"] = params_json(params);
  return pretty_json(out);
}

void write_state_json(const std::string& path, const SceneDef& scene, const Bodies& bodies, double time,
                      const ParamList& params) {
  write_file_atomically(path, state_to_json(scene, bodies, time, params));
}

}  // namespace rbpart
