// `rbpart simulate --initial-state` as a user resumes a run: the steps after a written state give the
// uninterrupted run's final state bit for bit when no contact carries a warm start, the statistics
// go on numbering from the state's step, and a state that is not the scene's is refused with exit
// status 2 and one line naming the problem.
#include <gtest/gtest.h>

#include <string>

#include "support/cli_test.hpp"

namespace rbpart::test {
namespace {

class Restart : public CliTest {
 protected:
  // A brick thrown up, tumbling, in empty space: no contact, no joint.
  std::string brick() const {
    return write("tumble.json", R"({"name": "tumble", "dt": 0.01, "steps": 30,
 "bodies": [{"name": "brick", "shape": {"type": "box", "half_extents": [0.3, 0.2, 0.1]}, "mass": 2,
             "position": [0, 0, 5], "velocity": [1, 0.5, 3], "angular_velocity": [2, 5, 1]}]})");
  }
  // A state file's time and bodies, without the run's parameters.
  static std::string bodies_of(const std::string& state) { return state.substr(0, state.find("\"params\"")); }
  // Runs with a hand-edited state and expects exit 2 with one line naming `problem`.
  void expect_refused(const std::string& scene, const std::string& state, const std::string& problem) {
    const std::string file = write("bad_state.json", state);
    const Result r = run("simulate --scene " + scene + " --initial-state " + file + " --steps 1 -q");
    EXPECT_EQ(r.status, 2) << state << "\n" << r.err;
    EXPECT_NE(r.err.find(problem), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line: " << r.err;
  }
};

TEST_F(Restart, ResumedFreeFlightEndsInTheUninterruptedRunsStateBitForBit) {
  const std::string scene = brick();
  ASSERT_EQ(run("simulate --scene " + scene + " --state " + path("whole.json") + " -q").status, 0);
  ASSERT_EQ(run("simulate --scene " + scene + " --steps 12 --state " + path("first.json") + " -q").status, 0);
  // Without --steps the resumed run does the scene's 30 - 12 steps left.
  const Result r = run("simulate --scene " + scene + " --initial-state " + path("first.json") + " --state " +
                       path("rest.json") + " --stats " + path("rest.csv") + " -q");
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string whole = read(path("whole.json"));
  ASSERT_NE(whole.find("\"time\": 0.3,"), std::string::npos) << whole;
  EXPECT_EQ(bodies_of(read(path("rest.json"))), bodies_of(whole));
  const std::string csv = read(path("rest.csv"));
  const std::size_t line2 = csv.find('\n') + 1;
  EXPECT_EQ(csv.substr(line2, 3), "13,") << csv;
  EXPECT_NE(csv.find("\n30,"), std::string::npos);
  EXPECT_EQ(csv.find("\n31,"), std::string::npos);
  const std::string params = read(path("rest.csv.json"));
  EXPECT_NE(params.find("\"steps\": \"18\""), std::string::npos) << params;
  EXPECT_NE(params.find("\"first_step\": \"13\""), std::string::npos) << params;
}

TEST_F(Restart, AStateThatIsNotTheScenesIsRefused) {
  const std::string scene = brick();
  ASSERT_EQ(run("simulate --scene " + scene + " --steps 5 --state " + path("good.json") + " -q").status, 0);
  const std::string good = read(path("good.json"));
  auto edited = [&good](const std::string& from, const std::string& to) {
    std::string s = good;
    const std::size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? s : s.replace(at, from.size(), to);
  };
  expect_refused(scene, edited("\"brick\"", "\"block\""), "bodies[0].name: is \"block\", but the scene's body 0 is \"brick\"");
  expect_refused(scene, edited("\"orientation\": [", "\"orientation\": [0.5, "), "bodies[0].orientation: expected [w, x, y, z]");
  expect_refused(scene, edited("\"velocity\"", "\"speed\""), "bodies[0].speed: unknown key for a body state");
  expect_refused(scene, R"({"time": 0.05, "bodies": [{"name": "brick", "position": [0, 0, 5],
    "orientation": [1, 0.01, 0, 0], "velocity": [0, 0, 0], "angular_velocity": [0, 0, 0]}]})",
                 "bodies[0].orientation: is not a unit quaternion (norm 1.00004999");
  expect_refused(scene, R"({"time": 0.05, "bodies": [{"name": "brick", "position": [0, null, 5],
    "orientation": [1, 0, 0, 0], "velocity": [0, 0, 0], "angular_velocity": [0, 0, 0]}]})",
                 "bodies[0].position[1]: expected a number (got null)");
  expect_refused(scene, R"({"time": 0.05, "bodies": [{"name": "brick", "position": [0, 1e999, 5],
    "orientation": [1, 0, 0, 0], "velocity": [0, 0, 0], "angular_velocity": [0, 0, 0]}]})",
                 "number 1e999 is out of range (not finite)");
  // Velocities are bounded as in a scene file (limits::kMaxRate): at 1e300 the first step overflowed.
  expect_refused(scene, R"({"time": 0.05, "bodies": [{"name": "brick", "position": [0, 0, 5],
    "orientation": [1, 0, 0, 0], "velocity": [0, 0, 1e300], "angular_velocity": [0, 0, 0]}]})",
                 "bodies[0].velocity[2]: must lie within +-1e+06 m/s (got 1e+300)");
  expect_refused(scene, edited("\"time\": 0.05", "\"time\": -1"), "time: must not be negative");
  expect_refused(scene, R"({"time": 0, "bodies": []})", "bodies: the state has 0 bodies, scene tumble has 1");
  // A state of another scene: the built-in slope's floor and block.
  expect_refused("slope", good, "bodies: the state has 1 bodies, scene slope has 2");
  const Result missing = run("simulate --scene " + scene + " --initial-state " + path("none.json") + " -q");
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("none.json: cannot read"), std::string::npos) << missing.err;
}

TEST_F(Restart, AStaticBodyMustBeWhereTheSceneHasIt) {
  ASSERT_EQ(run("simulate --scene slope --steps 3 --state " + path("slope.json") + " -q").status, 0);
  // The slope (static, body 0) moved to x = 7.
  std::string state = read(path("slope.json"));
  const std::size_t x = state.find("\"position\": [") + 13;
  state.replace(x, state.find(',', x) - x, "7");
  expect_refused("slope", state, "bodies[0]: static body slope is not at the scene's pose");
}

}  // namespace
}  // namespace rbpart::test
