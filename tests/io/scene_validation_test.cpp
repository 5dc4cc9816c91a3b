// Scene file validation: each kind of bad input gets one line naming the file, the field path (with
// the body or joint index) and the problem (docs/design.md#contracts).
#include "core/error.hpp"
#include "io/scene_json.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <regex>

namespace rbpart {
namespace {

using Json = nlohmann::json;

// Valid: every shape type, static and dynamic bodies, every joint type.
Json base() {
  return Json::parse(R"({
    "name": "base",
    "bodies": [
      {"name": "ground", "static": true, "shape": {"type": "box", "half_extents": [5, 5, 0.5]},
       "position": [0, 0, -0.5]},
      {"name": "ball", "shape": {"type": "sphere", "radius": 0.5}, "mass": 1, "position": [0, 0, 1]},
      {"name": "link", "shape": {"type": "capsule", "radius": 0.1, "half_length": 0.3}, "density": 1000},
      {"name": "post", "static": true, "shape": {"type": "cylinder", "radius": 0.2, "half_length": 1}},
      {"name": "rock", "shape": {"type": "convex",
                                 "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]},
       "density": 2500}
    ],
    "joints": [
      {"type": "ball", "bodies": [1, 2], "anchor": [0, 0, 0.5]},
      {"type": "hinge", "bodies": [2, -1], "anchor": [0, 0, 0], "axis": [0, 0, 1]},
      {"type": "fixed", "bodies": [4, 3], "anchor": [0, 0, 0]}
    ]
  })");
}

// The InputError message for `text`, checked to be one line.
std::string error_of_text(const std::string& text) {
  try {
    parse_scene(text, "scene.json");
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    return message;
  }
  return "(no error)";
}
std::string error_of(const Json& scene) { return error_of_text(scene.dump(2)); }

Json with(const std::string& pointer, Json value) {
  Json scene = base();
  scene[Json::json_pointer(pointer)] = std::move(value);
  return scene;
}
Json without(const std::string& pointer) {
  Json scene = base();
  const Json::json_pointer p(pointer);
  scene[p.parent_pointer()].erase(p.back());
  return scene;
}

TEST(SceneValidation, BaseSceneAndDuplicateNamesLoad) {
  EXPECT_EQ(error_of(base()), "(no error)");
  EXPECT_EQ(error_of(with("/bodies/2/name", "ball")), "(no error)");
  // A static body may be the first of a joint with a dynamic one.
  EXPECT_EQ(error_of(with("/joints/2/bodies", {3, 4})), "(no error)");
}

// Our line and column, computed from the parser's byte offset, must be those nlohmann's own lexer
// reports in its exception text (an independent count).
TEST(SceneValidation, MalformedJsonNamesLineAndColumn) {
  const std::vector<std::string> texts = {
      "{\n  \"dt\": 0.01,\n  \"bodies\": [,]\n}",  // a stray comma
      "{\"bodies\": []",                           // end of input
      "{\"bodies\": []}\n\n  x",                   // trailing text
      "",                                          // empty
      "{\"bodies\": [], \"dt\": .5}",              // not a JSON number
  };
  const std::regex ours("^scene\\.json: invalid JSON at (line \\d+, column \\d+): .+");
  const std::regex theirs("parse error at (line \\d+, column \\d+)");
  for (const std::string& text : texts) {
    const std::string message = error_of_text(text);
    std::smatch our_match;
    ASSERT_TRUE(std::regex_match(message, our_match, ours)) << message;
    std::string reference;
    try {
      const Json accepted = Json::parse(text);
      ADD_FAILURE() << "nlohmann accepts " << accepted.dump();
    } catch (const Json::parse_error& error) {
      std::smatch their_match;
      const std::string what = error.what();
      ASSERT_TRUE(std::regex_search(what, their_match, theirs)) << what;
      reference = their_match[1];
    }
    EXPECT_EQ(our_match[1], reference) << text;
  }
  // Where the offending character is a newline, nlohmann counts it as column 0 of the next line; we
  // name the line it ends, where an editor shows the unterminated string.
  EXPECT_EQ(error_of_text("{\n\"bodies\": [],\n\"name\": \"a\nb\"}")
                .rfind("scene.json: invalid JSON at line 3, column 11: syntax error while parsing value - "
                       "invalid string: control character U+000A",
                       0),
            0u);
  EXPECT_EQ(error_of_text(texts[0]),
            "scene.json: invalid JSON at line 3, column 14: syntax error while parsing value - "
            "unexpected ','; expected '[', '{', or a literal");
}

TEST(SceneValidation, WrongTypes) {
  EXPECT_EQ(error_of_text("[]"),
            "scene.json: expected a JSON object at the top level (got an array of 0 elements)");
  EXPECT_EQ(error_of(with("/dt", "0.01")), "scene.json: dt: expected a number (got string \"0.01\")");
  EXPECT_EQ(error_of(with("/bodies", Json::object())),
            "scene.json: bodies: expected an array (got an object)");
  EXPECT_EQ(error_of(with("/bodies/2", Json::array())),
            "scene.json: bodies[2]: expected an object (got an array of 0 elements)");
  EXPECT_EQ(error_of(with("/bodies/0/name", 5)), "scene.json: bodies[0].name: expected a string (got 5)");
  EXPECT_EQ(error_of(with("/bodies/1/static", 1)),
            "scene.json: bodies[1].static: expected true or false (got 1)");
  EXPECT_EQ(error_of(with("/bodies/1/shape/radius", nullptr)),
            "scene.json: bodies[1].shape.radius: expected a number (got null)");
  EXPECT_EQ(error_of(with("/bodies/1/shape", "sphere")),
            "scene.json: bodies[1].shape: expected an object (got string \"sphere\")");
  EXPECT_EQ(error_of(with("/bodies/1/position/1", "a")),
            "scene.json: bodies[1].position[1]: expected a number (got string \"a\")");
  EXPECT_EQ(error_of(with("/joints/0/bodies/1", 2.0)),
            "scene.json: joints[0].bodies[1]: expected an integer (got 2.0)");
  EXPECT_EQ(error_of(with("/joints/1/collide_connected", "yes")),
            "scene.json: joints[1].collide_connected: expected true or false (got string \"yes\")");
  EXPECT_EQ(error_of(with("/steps", 2.5)), "scene.json: steps: expected an integer (got 2.5)");
}

TEST(SceneValidation, ArraysOfTheWrongLength) {
  EXPECT_EQ(error_of(with("/bodies/2/position", {1, 2})),
            "scene.json: bodies[2].position: expected [x, y, z], an array of 3 numbers (got an array of 2 "
            "elements)");
  EXPECT_EQ(error_of(with("/gravity", 9.81)),
            "scene.json: gravity: expected [x, y, z], an array of 3 numbers (got 9.81)");
  EXPECT_EQ(error_of(with("/bodies/1/orientation", {1, 0, 0})),
            "scene.json: bodies[1].orientation: expected [w, x, y, z], an array of 4 numbers (got an array "
            "of 3 elements)");
  EXPECT_EQ(error_of(with("/bodies/4/shape/vertices/2", {0, 1})),
            "scene.json: bodies[4].shape.vertices[2]: expected [x, y, z], an array of 3 numbers (got an "
            "array of 2 elements)");
  EXPECT_EQ(error_of(with("/joints/0/bodies", {1})),
            "scene.json: joints[0].bodies: expected [i, j], two body indices (got an array of 1 element)");
  EXPECT_EQ(error_of(with("/bodies/0/shape/half_extents", {1, 2, 3, 4})),
            "scene.json: bodies[0].shape.half_extents: expected [x, y, z], an array of 3 numbers (got an "
            "array of 4 elements)");
}

TEST(SceneValidation, UnknownShapeAndJointTypes) {
  EXPECT_EQ(error_of(with("/bodies/1/shape/type", "spher")),
            "scene.json: bodies[1].shape.type: unknown shape type \"spher\" (expected sphere, box, capsule, "
            "cylinder or convex)");
  EXPECT_EQ(error_of(with("/joints/2/type", "weld")),
            "scene.json: joints[2].type: unknown joint type \"weld\" (expected ball, hinge or fixed)");
}

TEST(SceneValidation, UnknownKeysCatchTypos) {
  EXPECT_EQ(error_of(with("/gravty", {0, 0, -1})),
            "scene.json: gravty: unknown key for a scene (allowed: name, gravity, dt, friction, steps, "
            "bodies, joints)");
  EXPECT_EQ(error_of(with("/bodies/1/masss", 2))
                .rfind("scene.json: bodies[1].masss: unknown key for a body (allowed: name, ", 0),
            0u);
  Json typo = base();
  typo["bodies"][1]["shape"] = {{"type", "sphere"}, {"raduis", 0.5}};
  EXPECT_EQ(error_of(typo),
            "scene.json: bodies[1].shape.raduis: unknown key for a sphere (allowed: type, radius)");
  EXPECT_EQ(error_of(with("/bodies/2/shape/half_extents", {1, 1, 1})),
            "scene.json: bodies[2].shape.half_extents: unknown key for a capsule (allowed: type, radius, "
            "half_length)");
  EXPECT_EQ(error_of(with("/joints/0/anchr", {0, 0, 0})),
            "scene.json: joints[0].anchr: unknown key for a joint (allowed: type, bodies, anchor, axis, "
            "compliance, collide_connected)");
}

TEST(SceneValidation, DuplicateKeys) {
  std::string text = base().dump(2);
  const std::string once = "\"mass\": 1";  // only bodies[1] has a mass
  ASSERT_EQ(text.find(once), text.rfind(once));
  text.replace(text.find(once), once.size(), "\"mass\": 1, \"mass\": 2");
  EXPECT_EQ(error_of_text(text), "scene.json: bodies[1].mass: duplicate key");
  EXPECT_EQ(error_of_text(R"({"dt": 0.1, "bodies": [], "dt": 0.2})"), "scene.json: dt: duplicate key");
}

TEST(SceneValidation, MissingRequiredKeys) {
  EXPECT_EQ(error_of(without("/bodies")), "scene.json: bodies: required key is missing");
  EXPECT_EQ(error_of(without("/bodies/1/shape")), "scene.json: bodies[1].shape: required key is missing");
  EXPECT_EQ(error_of(without("/bodies/1/shape/type")),
            "scene.json: bodies[1].shape.type: required key is missing");
  EXPECT_EQ(error_of(without("/bodies/3/shape/half_length")),
            "scene.json: bodies[3].shape.half_length: required key is missing");
  EXPECT_EQ(error_of(without("/joints/0/anchor")), "scene.json: joints[0].anchor: required key is missing");
  EXPECT_EQ(error_of(without("/joints/2/bodies")), "scene.json: joints[2].bodies: required key is missing");
}

TEST(SceneValidation, NonPositiveSizesAndMasses) {
  EXPECT_EQ(error_of(with("/bodies/3/shape/radius", -0.5)),
            "scene.json: bodies[3].shape.radius: must be positive (got -0.5)");
  EXPECT_EQ(error_of(with("/bodies/1/shape/radius", 0)),
            "scene.json: bodies[1].shape.radius: must be positive (got 0)");
  EXPECT_EQ(error_of(with("/bodies/2/shape/half_length", 0)),
            "scene.json: bodies[2].shape.half_length: must be positive (got 0)");
  EXPECT_EQ(error_of(with("/bodies/0/shape/half_extents/1", -0.0)),
            "scene.json: bodies[0].shape.half_extents[1]: must be positive (got -0)");
  EXPECT_EQ(error_of(with("/bodies/1/mass", 0)), "scene.json: bodies[1].mass: must be positive (got 0)");
  EXPECT_EQ(error_of(with("/bodies/1/mass", -2)), "scene.json: bodies[1].mass: must be positive (got -2)");
  EXPECT_EQ(error_of(with("/bodies/4/density", -1e-3)),
            "scene.json: bodies[4].density: must be positive (got -0.001)");
}

TEST(SceneValidation, MassOrDensity) {
  EXPECT_EQ(error_of(without("/bodies/1/mass")),
            "scene.json: bodies[1]: a dynamic body needs \"mass\" or \"density\"");
  EXPECT_EQ(error_of(with("/bodies/1/density", 7800)),
            "scene.json: bodies[1]: give \"mass\" or \"density\", not both");
}

// 1e999 overflows to infinity: rejected by the parser, at the field and where it stands in the text.
TEST(SceneValidation, NonFiniteNumbers) {
  const auto error_with_literal = [](const std::string& pointer, const std::string& literal,
                                     std::string* location) {
    std::string text = with(pointer, 123.25).dump(2);
    const std::size_t at = text.find("123.25");
    text.replace(at, 6, literal);
    const std::size_t line_start = text.rfind('\n', at) + 1;
    *location = "line " + std::to_string(1 + std::count(text.begin(), text.begin() + at, '\n')) +
                ", column " + std::to_string(at - line_start + 1);
    return error_of_text(text);
  };
  std::string where;
  std::string message = error_with_literal("/bodies/1/velocity", "1e999", &where);
  EXPECT_EQ(message,
            "scene.json: bodies[1].velocity: number 1e999 is out of range (not finite), at " + where);
  message = error_with_literal("/bodies/1/angular_velocity/2", "-1e999", &where);
  EXPECT_EQ(message.rfind("scene.json: bodies[1].angular_velocity[2]: number -1e999 is out of range", 0), 0u)
      << message;
  message = error_with_literal("/dt", "1E+400", &where);
  EXPECT_EQ(message, "scene.json: dt: number 1E+400 is out of range (not finite), at " + where);
  message = error_with_literal("/bodies/4/shape/vertices/3/0", "2e308", &where);
  EXPECT_EQ(message.rfind("scene.json: bodies[4].shape.vertices[3][0]: number 2e308 is out of range", 0), 0u)
      << message;
}

TEST(SceneValidation, ZeroQuaternion) {
  EXPECT_EQ(error_of(with("/bodies/1/orientation", {0, 0, 0, 0})),
            "scene.json: bodies[1].orientation: must not be zero (a rotation is a unit quaternion)");
}

TEST(SceneValidation, JointBodies) {
  EXPECT_EQ(error_of(with("/joints/0/bodies", {1, 7})),
            "scene.json: joints[0].bodies[1]: no body 7 (the scene has 5 bodies; -1 is the world)");
  EXPECT_EQ(error_of(with("/joints/0/bodies", {-2, 1})),
            "scene.json: joints[0].bodies[0]: no body -2 (the scene has 5 bodies; -1 is the world)");
  EXPECT_EQ(error_of(with("/joints/0/bodies", {-1, 1})),
            "scene.json: joints[0].bodies[0]: must be a body (-1, the world, may only be second)");
  EXPECT_EQ(error_of(with("/joints/1/bodies", {2, 2})),
            "scene.json: joints[1].bodies: joins body 2 to itself");
  EXPECT_EQ(error_of(with("/joints/2/bodies", {0, 3})),
            "scene.json: joints[2].bodies: joins two static bodies (0 and 3)");
  EXPECT_EQ(error_of(with("/joints/1/bodies", {3, -1})),
            "scene.json: joints[1].bodies: joins static body 3 to the world");
  EXPECT_EQ(error_of(with("/joints/0/bodies", {1, 4294967296.0 * 2})),
            "scene.json: joints[0].bodies[1]: expected an integer (got 8589934592.0)");
  EXPECT_EQ(error_of(with("/joints/0/bodies", {1, 8589934592})),
            "scene.json: joints[0].bodies[1]: out of range (got 8589934592)");
}

TEST(SceneValidation, HingeAxis) {
  EXPECT_EQ(error_of(with("/joints/1/axis", {0, 0, 0})), "scene.json: joints[1].axis: must not be zero");
  EXPECT_EQ(error_of(without("/joints/1/axis")), "scene.json: joints[1].axis: required key is missing");
  EXPECT_EQ(error_of(with("/joints/0/axis", {1, 0, 0})),
            "scene.json: joints[0].axis: only a hinge has an axis");
}

TEST(SceneValidation, NegativeComplianceAndFriction) {
  EXPECT_EQ(error_of(with("/joints/0/compliance", -1e-6)),
            "scene.json: joints[0].compliance: must not be negative (got -1e-06)");
  EXPECT_EQ(error_of(with("/friction", -0.1)), "scene.json: friction: must not be negative (got -0.1)");
  EXPECT_EQ(error_of(with("/bodies/1/friction", -0.5)),
            "scene.json: bodies[1].friction: must not be negative (got -0.5)");
  EXPECT_EQ(error_of(with("/bodies/1/friction", 0)), "(no error)");
}

TEST(SceneValidation, TimeStepAndSteps) {
  EXPECT_EQ(error_of(with("/dt", 0)), "scene.json: dt: must be positive (got 0)");
  EXPECT_EQ(error_of(with("/dt", -0.01)), "scene.json: dt: must be positive (got -0.01)");
  EXPECT_EQ(error_of(with("/steps", 0)), "scene.json: steps: must be a positive count (got 0)");
  EXPECT_EQ(error_of(with("/steps", -3)), "scene.json: steps: must be a positive count (got -3)");
}

// The hull check belongs to mass_properties; its message comes prefixed with the body's path.
TEST(SceneValidation, DegenerateConvexHull) {
  const std::string prefix = "scene.json: bodies[4]: ";
  const Json coplanar = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.2, 0}};
  std::string message = error_of(with("/bodies/4/shape/vertices", coplanar));
  EXPECT_EQ(message.rfind(prefix, 0), 0u) << message;
  EXPECT_GT(message.size(), prefix.size()) << message;
  message = error_of(with("/bodies/4/shape/vertices", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
  EXPECT_EQ(message.rfind(prefix, 0), 0u) << message;
  message = error_of(with("/bodies/4/shape/vertices", Json::array()));
  EXPECT_EQ(message.rfind(prefix, 0), 0u) << message;
}

}  // namespace
}  // namespace rbpart
