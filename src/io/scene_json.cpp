#include "io/scene_json.hpp"

#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/text_format.hpp"
#include "scene/limits.hpp"
#include "scene/mass_properties.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <string_view>
#include <system_error>
#include <vector>

namespace rbpart {

namespace {

using Json = nlohmann::json;

// ---------------------------------------------------------------------------------------------
// Parsing: nlohmann's DOM parser keeps the last of two equal keys silently ({"mass": 1, "mass": 2}
// would load as 2), so the DOM is built here through the SAX interface, which also knows the path
// of the value being read when the parser reports a number too large for a double.

class StrictDomBuilder {
 public:
  StrictDomBuilder(const std::string& text, const std::string& source) : text_(text), source_(source) {}

  Json take() { return std::move(root_); }

  bool null() { return add(Json(nullptr)); }
  bool boolean(bool value) { return add(Json(value)); }
  bool number_integer(Json::number_integer_t value) { return add(Json(value)); }
  bool number_unsigned(Json::number_unsigned_t value) { return add(Json(value)); }
  bool number_float(Json::number_float_t value, const Json::string_t&) { return add(Json(value)); }
  bool string(Json::string_t& value) { return add(Json(std::move(value))); }
  bool binary(Json::binary_t& value) { return add(Json::binary(std::move(value))); }

  bool start_object(std::size_t) { return open(Json::object()); }
  bool start_array(std::size_t) { return open(Json::array()); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }

  bool key(Json::string_t& key) {
    Frame& frame = stack_.back();
    if (frame.node->contains(key)) {
      const std::string object = path(false);
      throw InputError(source_ + ": " + printable(object.empty() ? key : object + "." + key) + ": duplicate key");
    }
    frame.key = std::move(key);
    return true;
  }

  [[noreturn]] bool parse_error(std::size_t position, const std::string& token,
                                const nlohmann::detail::exception& error) {
    // out_of_range.406: a number literal such as 1e999 that overflows to infinity. The parser is
    // then at the literal's last character; point at its first.
    if (error.id == 406) {
      const std::string field = path(true);
      throw InputError(source_ + ": " + (field.empty() ? "" : field + ": ") + "number " + token +
                       " is out of range (not finite), at " +
                       location(position + 1 - std::min(position, token.size())));
    }
    const std::string where = location(position);
    // Keep nlohmann's reason, without its "[json.exception...] parse error at line l, column c: ",
    // as the location computed here is given in front.
    std::string reason = error.what();
    if (const auto pos = reason.find(", column "); pos != std::string::npos) {
      const auto colon = reason.find(": ", pos);
      if (colon != std::string::npos) reason.erase(0, colon + 2);
    }
    std::replace(reason.begin(), reason.end(), '\n', ' ');
    throw InputError(source_ + ": invalid JSON at " + where + ": " + printable(reason));
  }

 private:
  struct Frame {
    Json* node;       // the object or array being filled
    std::string key;  // objects: the key of the member being read
  };

  // Adds a value at the current position and returns it. A pointer to an array element stays
  // valid while it is on the stack: its siblings are appended only after it is closed.
  Json* insert(Json&& value) {
    if (stack_.empty()) {
      root_ = std::move(value);
      return &root_;
    }
    Frame& frame = stack_.back();
    if (frame.node->is_array()) {
      frame.node->push_back(std::move(value));
      return &frame.node->back();
    }
    Json& slot = (*frame.node)[frame.key];
    slot = std::move(value);
    return &slot;
  }
  bool add(Json&& value) {
    insert(std::move(value));
    return true;
  }
  bool open(Json&& container) {
    stack_.push_back({insert(std::move(container)), {}});
    return true;
  }
  bool close() {
    stack_.pop_back();
    return true;
  }

  // Path of the value being read, e.g. "bodies[3].shape.radius"; with `innermost` false, the path
  // of the innermost open container itself (a key event has not chosen its member yet).
  std::string path(bool innermost) const {
    std::string out;
    const std::size_t depth = innermost ? stack_.size() : stack_.size() - 1;
    for (std::size_t i = 0; i < depth; ++i) {
      const Frame& frame = stack_[i];
      if (frame.node->is_array()) {
        // An enclosing array's member is its last element; the innermost one's is the next.
        const std::size_t index = frame.node->size() - (i + 1 < stack_.size() ? 1 : 0);
        out += "[" + std::to_string(index) + "]";
      } else {
        if (!out.empty()) out += '.';
        out += frame.key;
      }
    }
    return out;
  }

  // "line l, column c" of a 1-based byte position (as nlohmann counts them).
  std::string location(std::size_t position) const {
    const std::size_t offset = std::min(position == 0 ? 0 : position - 1, text_.size());
    const auto line = 1 + std::count(text_.begin(), text_.begin() + offset, '\n');
    const std::size_t newline = offset == 0 ? std::string::npos : text_.rfind('\n', offset - 1);
    const std::size_t column = newline == std::string::npos ? offset + 1 : offset - newline;
    return "line " + std::to_string(line) + ", column " + std::to_string(column);
  }

  const std::string& text_;
  const std::string& source_;
  Json root_;
  std::vector<Frame> stack_;
};

// ---------------------------------------------------------------------------------------------
// Validation: one reader per level of the format, each failing with "<source>: <path>: <problem>".

std::string member(const std::string& path, std::string_view key) {
  return path.empty() ? std::string(key) : path + "." + std::string(key);
}
std::string element(const std::string& path, std::size_t index) {
  return path + "[" + std::to_string(index) + "]";
}

// A value as a message shows it: 2.0, true, string "abc", an array of 2 elements, an object.
std::string describe(const Json& value) {
  switch (value.type()) {
    case Json::value_t::string: {
      std::string text = value.dump(-1, ' ', false, Json::error_handler_t::replace);
      if (text.size() > 40) text = text.substr(0, 36) + "...\"";
      return "string " + text;
    }
    case Json::value_t::array:
      return "an array of " + std::to_string(value.size()) + (value.size() == 1 ? " element" : " elements");
    case Json::value_t::object: return "an object";
    default: return value.dump();
  }
}

std::string got(double value) { return " (got " + round_trip(value) + ")"; }

class SceneReader {
 public:
  explicit SceneReader(const std::string& source) : source_(source) {}

  SceneDef scene(const Json& root) const {
    if (!root.is_object()) fail("", "expected a JSON object at the top level (got " + describe(root) + ")");
    allow_keys(root, "", {"name", "gravity", "dt", "friction", "steps", "bodies", "joints"}, "scene");
    SceneDef scene;
    if (const Json* v = find(root, "name")) scene.name = string(*v, "name");
    if (const Json* v = find(root, "gravity")) scene.gravity = rate(*v, "gravity", "m/s^2");
    if (const Json* v = find(root, "dt")) {
      scene.dt = positive(*v, "dt");
      if (scene.dt > limits::kMaxDt) fail("dt", "must be at most " + round_trip(limits::kMaxDt) + " s" + got(scene.dt));
    }
    if (const Json* v = find(root, "friction")) scene.friction = non_negative(*v, "friction");
    if (const Json* v = find(root, "steps")) {
      const std::int64_t steps = integer(*v, "steps");
      if (steps < 1 || steps > INT_MAX) fail("steps", "must be a positive count (got " + v->dump() + ")");
      scene.steps = static_cast<int>(steps);
    }

    const Json& bodies = array(require(root, "", "bodies"), "bodies");
    scene.bodies.reserve(bodies.size());
    for (std::size_t i = 0; i < bodies.size(); ++i) scene.bodies.push_back(body(bodies[i], i));
    if (const Json* joints = find(root, "joints")) {
      array(*joints, "joints");
      scene.joints.reserve(joints->size());
      for (std::size_t i = 0; i < joints->size(); ++i) scene.joints.push_back(joint((*joints)[i], i, scene));
    }
    return scene;
  }

  // A state file for `scene` (state_json.hpp): every body by name in scene order; a static body
  // keeps the scene's pose (the engine never moves one), so its entry must give that pose and no
  // velocity, or the file belongs to another scene.
  SceneState state(const Json& root, const SceneDef& scene) const {
    if (!root.is_object()) fail("", "expected a JSON object at the top level (got " + describe(root) + ")");
    allow_keys(root, "", {"time", "bodies", "params"}, "state");
    SceneState state;
    state.time = non_negative(require(root, "", "time"), "time");
    const Json& bodies = array(require(root, "", "bodies"), "bodies");
    if (bodies.size() != scene.bodies.size())
      fail("bodies", "the state has " + std::to_string(bodies.size()) + " bodies, scene " + scene.name + " has " +
                         std::to_string(scene.bodies.size()));
    state.bodies.reserve(bodies.size());
    for (std::size_t i = 0; i < bodies.size(); ++i) state.bodies.push_back(body_state(bodies[i], i, scene.bodies[i]));
    return state;
  }

 private:
  BodyState body_state(const Json& value, std::size_t index, const BodyDef& def) const {
    const std::string path = element("bodies", index);
    object(value, path);
    allow_keys(value, path, {"name", "position", "orientation", "velocity", "angular_velocity"}, "body state");
    const std::string name = string(require(value, path, "name"), member(path, "name"));
    if (name != def.name)
      fail(member(path, "name"), "is \"" + name + "\", but the scene's body " + std::to_string(index) + " is \"" +
                                     def.name + "\"");
    BodyState s;
    s.position = vec3(require(value, path, "position"), member(path, "position"));
    const std::string q_path = member(path, "orientation");
    const Json& q = require(value, path, "orientation");
    const double norm = numbers<4>(q, q_path, "[w, x, y, z], an array of 4 numbers").stableNorm();
    if (!(std::abs(norm - 1) <= kUnitTolerance))
      fail(q_path, "is not a unit quaternion (norm " + round_trip(norm) + ")");
    s.orientation = quaternion(q, q_path);
    s.velocity = rate(require(value, path, "velocity"), member(path, "velocity"), "m/s");
    s.angular_velocity = rate(require(value, path, "angular_velocity"), member(path, "angular_velocity"), "rad/s");
    if (def.is_static) {
      const Quat turn = s.orientation * def.orientation.normalized().conjugate();
      if ((s.position - def.position).norm() > kStaticPoseTolerance * (1 + def.position.norm()) ||
          2 * std::asin(std::min(1.0, turn.vec().norm())) > kStaticPoseTolerance)
        fail(path, "static body " + name + " is not at the scene's pose (a static body never moves)");
      if (!s.velocity.isZero(0) || !s.angular_velocity.isZero(0))
        fail(path, "static body " + name + " has a velocity (a static body never moves)");
    }
    return s;
  }

  // A state's quaternion is the engine's, unit to round-off; a hand-written one to a few digits.
  static constexpr double kUnitTolerance = 1e-6;
  // Relative: the pose a state file writes for a static body is the scene's to round-off.
  static constexpr double kStaticPoseTolerance = 1e-9;

  BodyDef body(const Json& value, std::size_t index) const {
    const std::string path = element("bodies", index);
    object(value, path);
    allow_keys(value, path,
               {"name", "static", "shape", "mass", "density", "position", "orientation", "velocity",
                "angular_velocity", "friction"},
               "body");
    BodyDef body;
    body.name = "body" + std::to_string(index);
    if (const Json* v = find(value, "name")) body.name = string(*v, member(path, "name"));
    if (const Json* v = find(value, "static")) body.is_static = boolean(*v, member(path, "static"));
    body.shape = shape(require(value, path, "shape"), member(path, "shape"));

    const Json* mass = find(value, "mass");
    const Json* density = find(value, "density");
    if (mass && density) fail(path, "give \"mass\" or \"density\", not both");
    if (mass) body.mass = positive(*mass, member(path, "mass"));
    if (density) body.density = positive(*density, member(path, "density"));
    if (!mass && !density && !body.is_static) fail(path, "a dynamic body needs \"mass\" or \"density\"");

    if (const Json* v = find(value, "position")) body.position = vec3(*v, member(path, "position"));
    if (const Json* v = find(value, "orientation"))
      body.orientation = quaternion(*v, member(path, "orientation"));
    if (const Json* v = find(value, "velocity")) body.velocity = rate(*v, member(path, "velocity"), "m/s");
    if (const Json* v = find(value, "angular_velocity"))
      body.angular_velocity = rate(*v, member(path, "angular_velocity"), "rad/s");
    if (const Json* v = find(value, "friction")) body.friction = non_negative(*v, member(path, "friction"));

    // What the sizes above cannot show (a flat or too small convex hull) is found where the engine
    // needs it: in the mass properties. A static body needs no mass, only a sound shape.
    BodyDef probe = body;
    if (probe.mass == 0 && probe.density == 0) probe.density = 1;
    try {
      mass_properties(probe);
    } catch (const InputError& error) {
      fail(path, error.what());
    }
    return body;
  }

  Shape shape(const Json& value, const std::string& path) const {
    object(value, path);
    const std::string type_path = member(path, "type");
    const std::string type = string(require(value, path, "type"), type_path);
    Shape shape;
    if (type == "sphere") {
      shape.type = ShapeType::Sphere;
      allow_keys(value, path, {"type", "radius"}, "sphere");
      shape.radius = positive(require(value, path, "radius"), member(path, "radius"));
    } else if (type == "box") {
      shape.type = ShapeType::Box;
      allow_keys(value, path, {"type", "half_extents"}, "box");
      const std::string extents_path = member(path, "half_extents");
      shape.half_extents = vec3(require(value, path, "half_extents"), extents_path);
      for (int k = 0; k < 3; ++k)
        if (!(shape.half_extents[k] > 0))
          fail(element(extents_path, k), "must be positive" + got(shape.half_extents[k]));
    } else if (type == "capsule" || type == "cylinder") {
      shape.type = type == "capsule" ? ShapeType::Capsule : ShapeType::Cylinder;
      allow_keys(value, path, {"type", "radius", "half_length"}, type.c_str());
      shape.radius = positive(require(value, path, "radius"), member(path, "radius"));
      shape.half_length = positive(require(value, path, "half_length"), member(path, "half_length"));
    } else if (type == "convex") {
      shape.type = ShapeType::Convex;
      allow_keys(value, path, {"type", "vertices"}, "convex shape");
      const std::string vertices_path = member(path, "vertices");
      const Json& vertices = array(require(value, path, "vertices"), vertices_path);
      shape.vertices.reserve(vertices.size());
      for (std::size_t i = 0; i < vertices.size(); ++i)
        shape.vertices.push_back(vec3(vertices[i], element(vertices_path, i)));
    } else {
      fail(type_path,
           "unknown shape type \"" + type + "\" (expected sphere, box, capsule, cylinder or convex)");
    }
    return shape;
  }

  JointDef joint(const Json& value, std::size_t index, const SceneDef& scene) const {
    const std::string path = element("joints", index);
    object(value, path);
    allow_keys(value, path, {"type", "bodies", "anchor", "axis", "compliance", "collide_connected"}, "joint");
    JointDef joint;
    const std::string type_path = member(path, "type");
    const std::string type = string(require(value, path, "type"), type_path);
    if (type == "ball") {
      joint.type = JointType::Ball;
    } else if (type == "hinge") {
      joint.type = JointType::Hinge;
    } else if (type == "fixed") {
      joint.type = JointType::Fixed;
    } else {
      fail(type_path, "unknown joint type \"" + type + "\" (expected ball, hinge or fixed)");
    }

    // Bodies: [i, j], i a scene body, j a scene body or -1 for the world.
    const std::string bodies_path = member(path, "bodies");
    const Json& bodies = require(value, path, "bodies");
    if (!bodies.is_array() || bodies.size() != 2)
      fail(bodies_path, "expected [i, j], two body indices (got " + describe(bodies) + ")");
    const auto body_index = [&](std::size_t slot) {
      const std::string slot_path = element(bodies_path, slot);
      const std::int64_t body = integer(bodies[slot], slot_path);
      if (body < -1 || body >= static_cast<std::int64_t>(scene.bodies.size()))
        fail(slot_path, "no body " + std::to_string(body) + " (the scene has " +
                            std::to_string(scene.bodies.size()) +
                            (scene.bodies.size() == 1 ? " body" : " bodies") + "; -1 is the world)");
      return static_cast<int>(body);
    };
    joint.body_a = body_index(0);
    joint.body_b = body_index(1);
    if (joint.body_a == -1)
      fail(element(bodies_path, 0), "must be a body (-1, the world, may only be second)");
    const auto is_static = [&](int body) { return scene.bodies[body].is_static; };
    const std::string a = std::to_string(joint.body_a), b = std::to_string(joint.body_b);
    if (joint.body_a == joint.body_b) fail(bodies_path, "joins body " + a + " to itself");
    if (joint.body_b == -1 && is_static(joint.body_a))
      fail(bodies_path, "joins static body " + a + " to the world");
    if (joint.body_b != -1 && is_static(joint.body_a) && is_static(joint.body_b))
      fail(bodies_path, "joins two static bodies (" + a + " and " + b + ")");

    joint.anchor = vec3(require(value, path, "anchor"), member(path, "anchor"));
    const std::string axis_path = member(path, "axis");
    if (joint.type == JointType::Hinge) {
      // Kept as given (the engine normalises it), so that an exported scene loads back unchanged.
      joint.axis = vec3(require(value, path, "axis"), axis_path);
      // The engine normalises it: its squared norm must be a normal number (1e-200 squared is 0).
      const double norm2 = joint.axis.squaredNorm();
      if (!(norm2 >= std::numeric_limits<double>::min() && std::isfinite(norm2)))
        fail(axis_path, joint.axis.isZero(0) ? "must not be zero"
                                             : "is too short or too long to normalise (squared norm " +
                                                   round_trip(norm2) + ")");
    } else if (find(value, "axis")) {
      fail(axis_path, "only a hinge has an axis");
    }
    if (const Json* v = find(value, "compliance"))
      joint.compliance = non_negative(*v, member(path, "compliance"));
    if (const Json* v = find(value, "collide_connected"))
      joint.collide_connected = boolean(*v, member(path, "collide_connected"));
    return joint;
  }

  // --- primitives ------------------------------------------------------------------------------

  // Keys and strings of the file may hold any byte ("\u0000" too): printable() keeps the message whole.
  [[noreturn]] void fail(const std::string& path, const std::string& problem) const {
    throw InputError(source_ + ": " + printable((path.empty() ? "" : path + ": ") + problem));
  }

  // Strict keys: a typo ("raduis") must not silently fall back to a default.
  void allow_keys(const Json& object, const std::string& path, std::initializer_list<const char*> keys,
                  const char* what) const {
    for (auto it = object.begin(); it != object.end(); ++it) {
      if (std::find_if(keys.begin(), keys.end(), [&](const char* k) { return it.key() == k; }) != keys.end())
        continue;
      std::string allowed;
      for (const char* k : keys) allowed += (allowed.empty() ? "" : ", ") + std::string(k);
      fail(member(path, it.key()), std::string("unknown key for a ") + what + " (allowed: " + allowed + ")");
    }
  }

  static const Json* find(const Json& object, const char* key) {
    const auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
  }
  const Json& require(const Json& object, const std::string& path, const char* key) const {
    const Json* value = find(object, key);
    if (!value) fail(member(path, key), "required key is missing");
    return *value;
  }

  const Json& object(const Json& value, const std::string& path) const {
    if (!value.is_object()) fail(path, "expected an object (got " + describe(value) + ")");
    return value;
  }
  const Json& array(const Json& value, const std::string& path) const {
    if (!value.is_array()) fail(path, "expected an array (got " + describe(value) + ")");
    return value;
  }
  std::string string(const Json& value, const std::string& path) const {
    if (!value.is_string()) fail(path, "expected a string (got " + describe(value) + ")");
    return value.get<std::string>();
  }
  bool boolean(const Json& value, const std::string& path) const {
    if (!value.is_boolean()) fail(path, "expected true or false (got " + describe(value) + ")");
    return value.get<bool>();
  }
  // Finite by construction: the parser rejects literals that overflow (StrictDomBuilder).
  double number(const Json& value, const std::string& path) const {
    if (!value.is_number()) fail(path, "expected a number (got " + describe(value) + ")");
    return value.get<double>();
  }
  double positive(const Json& value, const std::string& path) const {
    const double x = number(value, path);
    if (!(x > 0)) fail(path, "must be positive" + got(x));
    return x;
  }
  double non_negative(const Json& value, const std::string& path) const {
    const double x = number(value, path);
    if (x < 0) fail(path, "must not be negative" + got(x));
    return x;
  }
  std::int64_t integer(const Json& value, const std::string& path) const {
    if (!value.is_number_integer()) fail(path, "expected an integer (got " + describe(value) + ")");
    if (value.is_number_unsigned() && value.get<std::uint64_t>() > INT_MAX)
      fail(path, "out of range (got " + value.dump() + ")");
    return value.get<std::int64_t>();
  }
  template <int N>
  Eigen::Matrix<double, N, 1> numbers(const Json& value, const std::string& path, const char* what) const {
    if (!value.is_array() || value.size() != N)
      fail(path, std::string("expected ") + what + " (got " + describe(value) + ")");
    Eigen::Matrix<double, N, 1> out;
    for (int k = 0; k < N; ++k) out[k] = number(value[k], element(path, k));
    return out;
  }
  Vec3 vec3(const Json& value, const std::string& path) const {
    return numbers<3>(value, path, "[x, y, z], an array of 3 numbers");
  }
  // A vector of rates (gravity, velocities) whose components lie within limits::kMaxRate.
  Vec3 rate(const Json& value, const std::string& path, const char* unit) const {
    const Vec3 v = vec3(value, path);
    for (int k = 0; k < 3; ++k)
      if (std::abs(v[k]) > limits::kMaxRate)
        fail(element(path, k), "must lie within +-" + round_trip(limits::kMaxRate) + " " + unit + got(v[k]));
    return v;
  }
  // [w, x, y, z], normalised. One that is already unit to 1e-12 is kept bit for bit: renormalising
  // a unit quaternion can change its last bits, and an exported scene must load back unchanged.
  Quat quaternion(const Json& value, const std::string& path) const {
    const Eigen::Vector4d wxyz = numbers<4>(value, path, "[w, x, y, z], an array of 4 numbers");
    const double norm = wxyz.stableNorm();
    if (norm == 0) fail(path, "must not be zero (a rotation is a unit quaternion)");
    const Eigen::Vector4d unit = std::abs(norm - 1) <= 1e-12 ? wxyz : Eigen::Vector4d(wxyz / norm);
    return Quat(unit[0], unit[1], unit[2], unit[3]);
  }

  const std::string& source_;
};

// ---------------------------------------------------------------------------------------------
// Export.

using OrderedJson = nlohmann::ordered_json;

OrderedJson vec3_json(const Vec3& v) { return OrderedJson::array({v.x(), v.y(), v.z()}); }

OrderedJson shape_json(const Shape& shape) {
  OrderedJson out = OrderedJson::object();
  switch (shape.type) {
    case ShapeType::Sphere:
      out["type"] = "sphere";
      out["radius"] = shape.radius;
      break;
    case ShapeType::Box:
      out["type"] = "box";
      out["half_extents"] = vec3_json(shape.half_extents);
      break;
    case ShapeType::Capsule:
    case ShapeType::Cylinder:
      out["type"] = shape.type == ShapeType::Capsule ? "capsule" : "cylinder";
      out["radius"] = shape.radius;
      out["half_length"] = shape.half_length;
      break;
    case ShapeType::Convex: {
      out["type"] = "convex";
      OrderedJson vertices = OrderedJson::array();
      for (const Vec3& v : shape.vertices) vertices.push_back(vec3_json(v));
      out["vertices"] = std::move(vertices);
      break;
    }
  }
  return out;
}

const char* joint_type_name(JointType type) {
  switch (type) {
    case JointType::Ball: return "ball";
    case JointType::Hinge: return "hinge";
    case JointType::Fixed: return "fixed";
  }
  return "unknown";
}

}  // namespace

namespace {

Json parse_strictly(const std::string& text, const std::string& source_name) {
  StrictDomBuilder builder(text, source_name);
  Json::sax_parse(text, &builder);
  return builder.take();
}

std::string read_input(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file) throw InputError(path + ": cannot read: " + std::generic_category().message(errno));
  std::string text;
  char buffer[1 << 16];
  std::size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, file)) > 0) text.append(buffer, n);
  const int err = std::ferror(file) ? errno : 0;
  std::fclose(file);
  if (err) throw InputError(path + ": cannot read: " + std::generic_category().message(err));
  return text;
}

}  // namespace

SceneDef parse_scene(const std::string& text, const std::string& source_name) {
  return SceneReader(source_name).scene(parse_strictly(text, source_name));
}

SceneDef load_scene_file(const std::string& path) { return parse_scene(read_input(path), path); }

SceneState parse_state(const std::string& text, const std::string& source_name, const SceneDef& scene) {
  return SceneReader(source_name).state(parse_strictly(text, source_name), scene);
}

SceneState load_state_file(const std::string& path, const SceneDef& scene) {
  return parse_state(read_input(path), path, scene);
}

std::string scene_to_json(const SceneDef& scene) {
  OrderedJson out = OrderedJson::object();
  out["name"] = scene.name;
  out["gravity"] = vec3_json(scene.gravity);
  out["dt"] = scene.dt;
  out["friction"] = scene.friction;
  out["steps"] = scene.steps;
  OrderedJson bodies = OrderedJson::array();
  for (const BodyDef& body : scene.bodies) {
    OrderedJson b = OrderedJson::object();
    b["name"] = body.name;
    b["static"] = body.is_static;
    b["shape"] = shape_json(body.shape);
    if (body.mass > 0) {
      b["mass"] = body.mass;
    } else if (body.density > 0) {
      b["density"] = body.density;
    }
    b["position"] = vec3_json(body.position);
    const Quat& q = body.orientation;
    b["orientation"] = OrderedJson::array({q.w(), q.x(), q.y(), q.z()});
    b["velocity"] = vec3_json(body.velocity);
    b["angular_velocity"] = vec3_json(body.angular_velocity);
    if (body.friction >= 0) b["friction"] = body.friction;
    bodies.push_back(std::move(b));
  }
  out["bodies"] = std::move(bodies);
  OrderedJson joints = OrderedJson::array();
  for (const JointDef& joint : scene.joints) {
    OrderedJson j = OrderedJson::object();
    j["type"] = joint_type_name(joint.type);
    j["bodies"] = OrderedJson::array({joint.body_a, joint.body_b});
    j["anchor"] = vec3_json(joint.anchor);
    if (joint.type == JointType::Hinge) j["axis"] = vec3_json(joint.axis);
    j["compliance"] = joint.compliance;
    j["collide_connected"] = joint.collide_connected;
    joints.push_back(std::move(j));
  }
  out["joints"] = std::move(joints);
  return pretty_json(out);
}

void write_scene_file(const std::string& path, const SceneDef& scene) {
  write_file_atomically(path, scene_to_json(scene));
}

}  // namespace rbpart
