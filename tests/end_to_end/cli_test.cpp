// The rbpart CLI as a user runs it: exit statuses, one-line errors, no half-written outputs, and
// export -> load -> simulate reproducing a built-in run exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include "support/cli_test.hpp"

namespace {

namespace fs = std::filesystem;

class Cli : public rbpart::test::CliTest {
 protected:
  // A bad scene file must give exit 2, one line naming `expect`, and leave no outputs behind.
  void expect_rejected(const std::string& text, const std::string& expect) {
    const std::string scene = write("bad.json", text);
    const Result r = run("simulate --scene " + scene + " --steps 2 --stats " + path("s.csv") + " --state " +
                         path("s.json"));
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find(expect), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(path("s.csv")));
    EXPECT_FALSE(fs::exists(path("s.json")));
  }
};

const char* kGround = R"({"name": "g", "static": true, "shape": {"type": "box", "half_extents": [5, 5, 0.5]},
                          "position": [0, 0, -0.5]})";

std::string scene_with(const std::string& body, const std::string& joints = "[]") {
  return std::string(R"({"name": "t", "bodies": [)") + kGround + ", " + body + R"(], "joints": )" + joints + "}";
}

TEST_F(Cli, MalformedJson) { expect_rejected("{\"name\": \"t\", \"bodies\": [", "bad.json"); }

TEST_F(Cli, UnknownShape) {
  expect_rejected(scene_with(R"({"shape": {"type": "torus", "radius": 1}, "mass": 1})"), "bodies[1].shape");
}

TEST_F(Cli, NonPositiveMass) {
  expect_rejected(scene_with(R"({"shape": {"type": "sphere", "radius": 1}, "mass": -1})"), "bodies[1].mass");
}

TEST_F(Cli, NonPositiveRadius) {
  expect_rejected(scene_with(R"({"shape": {"type": "sphere", "radius": 0}, "mass": 1})"), "bodies[1].shape.radius");
}

TEST_F(Cli, NotANumber) {
  expect_rejected(scene_with(R"({"shape": {"type": "sphere", "radius": 1}, "mass": 1, "position": [0, 0, 1e999]})"),
                  "bodies[1].position");
}

TEST_F(Cli, JointNamingMissingBody) {
  expect_rejected(scene_with(R"({"shape": {"type": "sphere", "radius": 1}, "mass": 1})",
                             R"([{"type": "ball", "bodies": [1, 7], "anchor": [0, 0, 1]}])"),
                  "joints[0].bodies");
}

TEST_F(Cli, DegenerateHull) {
  expect_rejected(scene_with(R"({"shape": {"type": "convex", "vertices": [[0,0,0],[1,0,0],[0,1,0],[1,1,0]]},
                                 "mass": 1})"),
                  "bodies[1]: body 'body1': convex vertices are coplanar");
}

TEST_F(Cli, UnknownOptionAndBadValues) {
  for (const std::string args : {"simulate --scene box_stack --bogus", "simulate --scene box_stack --steps -3",
                                 "simulate --scene box_stack --solver magic", "simulate --scene no_such_scene",
                                 "simulate --scene box_stack --set boxes=ten", "simulate --scene box_stack --set nope=1"}) {
    const Result r = run(args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
  }
}

TEST_F(Cli, NumericOptionsNameTheirBound) {
  const std::pair<std::string, std::string> cases[] = {
      {"--steps -3", "--steps: must be at least 0 (got -3)"},
      {"--dt 0", "--dt: must be positive (got 0)"},
      {"--erp 0", "--erp: must lie in (0, 1] (got 0)"},
      {"--erp 1.5", "--erp: must lie in (0, 1] (got 1.5)"},
      {"--coupled-paths 0", "--coupled-paths: must be positive (got 0)"},
      {"--slop nan", "--slop: must be a number (got 'nan')"},
  };
  for (const auto& [args, expect] : cases) {
    const Result r = run("simulate --scene box_stack " + args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    EXPECT_EQ(r.err, "rbpart: error: " + expect + "\n") << args;
  }
  EXPECT_EQ(run("simulate --scene box_stack --steps 1 --erp 1 -q").status, 0);
}

TEST_F(Cli, UnwritableOutputLeavesNothing) {
  const Result r = run("simulate --scene box_stack --steps 2 --stats /nonexistent_dir/s.csv");
  EXPECT_EQ(r.status, 2) << r.err;
}

TEST_F(Cli, ExportedSceneReproducesBuiltinRun) {
  const Result exported = run("scenes --export rock_pile --set rocks=12 --set seed=3");
  ASSERT_EQ(exported.status, 0) << exported.err;
  const std::string file = write("rocks.json", exported.out);
  const Result a = run("simulate --scene rock_pile --set rocks=12 --set seed=3 --steps 60 --state " + path("a.json"));
  const Result b = run("simulate --scene " + file + " --steps 60 --state " + path("b.json"));
  ASSERT_EQ(a.status, 0) << a.err;
  ASSERT_EQ(b.status, 0) << b.err;
  EXPECT_EQ(read(path("a.json")), read(path("b.json")));
  EXPECT_NE(a.out.find("state hash"), std::string::npos);
}

TEST_F(Cli, StatsHaveEveryColumnAndOneLinePerStep) {
  const Result r = run("simulate --scene box_stack --steps 5 --stats " + path("s.csv"));
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream f(path("s.csv"));
  std::string line, header;
  int data = 0;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header.empty()) header = line;
    else ++data;
  }
  EXPECT_EQ(data, 5);
  for (const char* col : {"step", "bodies", "contacts", "rows", "parts", "interface_rows", "interface_bodies",
                          "edge_cut", "partition_ms", "refine_ms", "solve_ms", "solver_iterations", "fallback",
                          "blcp_residual", "max_penetration", "kinetic_energy"})
    EXPECT_NE(header.find(col), std::string::npos) << col;
}

}  // namespace
