// Scene files and state files in rbpart's formats (docs/formats.md), the bodies' inertia, and the
// vector algebra the engine adapters share.
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "peers.hpp"

namespace peers {
namespace {

using nlohmann::json;

Vec3 vec3(const json& j, const char* key, Vec3 fallback) {
  if (!j.contains(key)) return fallback;
  const auto& a = j.at(key);
  return {a.at(0).get<double>(), a.at(1).get<double>(), a.at(2).get<double>()};
}

// Uniform solid: the volume and the principal moments per unit mass, in the shape frame.
double volume(const Shape& s) {
  switch (s.type) {
    case ShapeType::box: return 8 * s.half_extents[0] * s.half_extents[1] * s.half_extents[2];
    case ShapeType::sphere: return 4.0 / 3.0 * M_PI * std::pow(s.radius, 3);
    case ShapeType::capsule:
      return M_PI * s.radius * s.radius * 2 * s.half_length + 4.0 / 3.0 * M_PI * std::pow(s.radius, 3);
  }
  return 0;
}

Vec3 inertia(const Shape& s, double mass) {
  switch (s.type) {
    case ShapeType::box: {
      const auto& h = s.half_extents;
      return {mass / 3 * (h[1] * h[1] + h[2] * h[2]), mass / 3 * (h[0] * h[0] + h[2] * h[2]),
              mass / 3 * (h[0] * h[0] + h[1] * h[1])};
    }
    case ShapeType::sphere: {
      const double i = 0.4 * mass * s.radius * s.radius;
      return {i, i, i};
    }
    case ShapeType::capsule: {
      // The cylinder and the two hemispheres by volume; each hemisphere's centre of mass lies
      // 3r/8 beyond the cylinder's end.
      const double r = s.radius, l = s.half_length;
      const double cylinder = M_PI * r * r * 2 * l, caps = 4.0 / 3.0 * M_PI * r * r * r;
      const double mc = mass * cylinder / (cylinder + caps), ms = mass - mc;
      const double axial = mc * r * r / 2 + ms * 0.4 * r * r;
      const double across = mc * (r * r / 4 + (2 * l) * (2 * l) / 12) + ms * (0.4 * r * r + l * l + 0.75 * l * r);
      return {across, across, axial};
    }
  }
  return {};
}

Shape shape_of(const json& j, const std::string& where) {
  Shape s;
  const auto type = j.at("type").get<std::string>();
  if (type == "box") {
    s.type = ShapeType::box;
    s.half_extents = vec3(j, "half_extents", {});
  } else if (type == "sphere") {
    s.type = ShapeType::sphere;
    s.radius = j.at("radius").get<double>();
  } else if (type == "capsule") {
    s.type = ShapeType::capsule;
    s.radius = j.at("radius").get<double>();
    s.half_length = j.at("half_length").get<double>();
  } else {
    throw std::runtime_error(where + ": shape type '" + type + "' is not supported by the peers' harness");
  }
  return s;
}

}  // namespace

Scene load_scene(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  const json j = json::parse(in);
  Scene scene;
  scene.name = j.value("name", "");
  scene.gravity = vec3(j, "gravity", scene.gravity);
  scene.dt = j.value("dt", scene.dt);
  scene.steps = j.value("steps", scene.steps);
  const double friction = j.value("friction", 0.5);
  const auto& bodies = j.at("bodies");
  for (size_t i = 0; i < bodies.size(); ++i) {
    const auto& b = bodies[i];
    const std::string where = path + ": bodies[" + std::to_string(i) + "]";
    Body body;
    body.name = b.value("name", "body" + std::to_string(i));
    body.is_static = b.value("static", false);
    body.shape = shape_of(b.at("shape"), where);
    body.position = vec3(b, "position", {});
    if (b.contains("orientation")) {
      const auto& q = b.at("orientation");
      Quat o{q.at(0).get<double>(), q.at(1).get<double>(), q.at(2).get<double>(), q.at(3).get<double>()};
      const double n = std::sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2] + o[3] * o[3]);
      body.orientation = {o[0] / n, o[1] / n, o[2] / n, o[3] / n};
    }
    body.friction = b.value("friction", friction);
    if (!body.is_static) {
      body.mass = b.contains("mass") ? b.at("mass").get<double>()
                                     : b.at("density").get<double>() * volume(body.shape);
      body.inertia = inertia(body.shape, body.mass);
      body.velocity = vec3(b, "velocity", {});
      body.angular_velocity = vec3(b, "angular_velocity", {});
    }
    scene.bodies.push_back(body);
  }
  if (j.contains("joints")) {
    for (size_t i = 0; i < j.at("joints").size(); ++i) {
      const auto& jj = j.at("joints")[i];
      const std::string where = path + ": joints[" + std::to_string(i) + "]";
      if (jj.at("type").get<std::string>() != "ball")
        throw std::runtime_error(where + ": only ball joints are supported by the peers' harness");
      if (jj.value("compliance", 0.0) != 0.0 || jj.value("collide_connected", false))
        throw std::runtime_error(where + ": compliant or colliding joints are not supported");
      Joint joint;
      joint.a = jj.at("bodies").at(0).get<int>();
      joint.b = jj.at("bodies").at(1).get<int>();
      joint.anchor = vec3(jj, "anchor", {});
      scene.joints.push_back(joint);
    }
  }
  return scene;
}

double pair_friction(const Body& a, const Body& b) { return std::sqrt(a.friction * b.friction); }

void write_state(const std::string& path, const Scene& scene, const std::vector<BodyState>& state,
                 double time) {
  json bodies = json::array();
  for (size_t i = 0; i < state.size(); ++i) {
    const auto& s = state[i];
    bodies.push_back({{"name", scene.bodies[i].name},
                      {"position", s.position},
                      {"orientation", s.orientation},
                      {"velocity", s.velocity},
                      {"angular_velocity", s.angular_velocity}});
  }
  std::ofstream out(path);
  out << std::setprecision(17) << json{{"time", time}, {"bodies", bodies}}.dump() << "\n";
  if (!out) throw std::runtime_error(path + ": cannot write");
}

std::vector<BodyState> read_state(const std::string& path, const Scene& scene) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  const json j = json::parse(in);
  const auto& bodies = j.at("bodies");
  if (bodies.size() != scene.bodies.size())
    throw std::runtime_error(path + ": the state has another number of bodies than the scene");
  std::vector<BodyState> state;
  for (const auto& b : bodies) {
    BodyState s;
    s.position = vec3(b, "position", {});
    const auto& q = b.at("orientation");
    s.orientation = {q.at(0).get<double>(), q.at(1).get<double>(), q.at(2).get<double>(), q.at(3).get<double>()};
    s.velocity = vec3(b, "velocity", {});
    s.angular_velocity = vec3(b, "angular_velocity", {});
    state.push_back(s);
  }
  return state;
}

Mat3 rotation(const Quat& q) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  return {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
           {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
           {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
}

Vec3 mul(const Mat3& m, const Vec3& v) { return {dot(m[0], v), dot(m[1], v), dot(m[2], v)}; }

Vec3 mul_transposed(const Mat3& m, const Vec3& v) {
  return add(add(scale(m[0], v[0]), scale(m[1], v[1])), scale(m[2], v[2]));
}

Quat conjugate_times(const Quat& a, const Quat& b) {
  const double w = a[0], x = -a[1], y = -a[2], z = -a[3];
  return {w * b[0] - x * b[1] - y * b[2] - z * b[3], w * b[1] + x * b[0] + y * b[3] - z * b[2],
          w * b[2] - x * b[3] + y * b[0] + z * b[1], w * b[3] + x * b[2] - y * b[1] + z * b[0]};
}

Vec3 world_inertia_times(const Mat3& r, const Vec3& diag, const Vec3& v) {
  Vec3 local = mul_transposed(r, v);
  for (int k = 0; k < 3; ++k) local[k] *= diag[k];
  return mul(r, local);
}

Vec3 world_inverse_inertia_times(const Mat3& r, const Vec3& diag, const Vec3& v) {
  return world_inertia_times(r, {1 / diag[0], 1 / diag[1], 1 / diag[2]}, v);
}

double bounding_radius(const Shape& s) {
  switch (s.type) {
    case ShapeType::box: return std::sqrt(dot(s.half_extents, s.half_extents));
    case ShapeType::sphere: return s.radius;
    case ShapeType::capsule: return s.radius + s.half_length;
  }
  return 0;
}

std::string json_number(double value) {
  if (std::isinf(value)) return value > 0 ? "\"inf\"" : "\"-inf\"";
  std::ostringstream o;
  o << std::setprecision(17) << value;
  return o.str();
}

}  // namespace peers
