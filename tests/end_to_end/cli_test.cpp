// The rbpart CLI as a user runs it: exit statuses, one-line errors, no half-written outputs, and
// export -> load -> simulate reproducing a built-in run exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

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
    EXPECT_FALSE(fs::exists(path("s.csv.json")));
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

TEST_F(Cli, StatsHaveTheHeaderOnLineOneEveryColumnAndOneLinePerStep) {
  const Result r = run("simulate --scene box_stack --steps 5 --stats " + path("s.csv"));
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream f(path("s.csv"));
  std::string header, line;
  std::getline(f, header);
  EXPECT_EQ(header.rfind("step,bodies,", 0), 0u) << header;
  int data = 0;
  while (std::getline(f, line)) {
    EXPECT_FALSE(line.empty() || line[0] == '#') << line;
    ++data;
  }
  EXPECT_EQ(data, 5);
  for (const char* col : {"step", "bodies", "contacts", "rows", "parts", "interface_rows", "interface_bodies",
                          "edge_cut", "partition_ms", "refine_ms", "solve_ms", "solver_iterations", "fallback",
                          "blcp_residual", "max_penetration", "kinetic_energy", "unsettled"})
    EXPECT_NE(header.find(col), std::string::npos) << col;
}

// What a user's script does: Python's csv.DictReader on the stats, json on their sidecar.
TEST_F(Cli, StatsReadByPythonsCsvDictReaderWithTheParametersInTheSidecar) {
  if (std::system("python3 -c '' 2>/dev/null") != 0) GTEST_SKIP() << "no python3";
  const Result r = run("simulate --scene box_stack --steps 5 --erp 0.25 --stats " + path("s.csv"));
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string script = write("read.py", R"(import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1], newline="")))
assert [int(row["step"]) for row in rows] == [1, 2, 3, 4, 5], rows
assert all(float(row["kinetic_energy"]) >= 0 and float(row["solve_ms"]) >= 0 for row in rows)
params = json.load(open(sys.argv[1] + ".json"))
assert params["scene"] == "box_stack" and params["steps"] == "5" and float(params["erp"]) == 0.25, params
print("read", len(rows), "rows")
)");
  const std::string out = path("python.txt");
  const int status = std::system(("python3 " + script + " " + path("s.csv") + " >" + out + " 2>&1").c_str());
  EXPECT_EQ(status, 0) << read(out);
  EXPECT_EQ(read(out), "read 5 rows\n");
}

// The summary names the run's total time, its slowest step and its unsettled steps, as the stats say
// (one factorisation per island and step leaves most of a landing pile's steps unsettled).
TEST_F(Cli, SummaryNamesTotalSlowestStepAndUnsettledSteps) {
  const Result r = run("simulate --scene rock_pile --set rocks=20 --steps 40 --solver newton --max-factorizations 1 "
                       "--stats " + path("s.csv"));
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream f(path("s.csv"));
  std::string line;
  std::getline(f, line);
  std::vector<std::string> columns;
  std::stringstream h(line);
  for (std::string c; std::getline(h, c, ',');) columns.push_back(c);
  const auto column = [&](const char* name) {
    return std::find(columns.begin(), columns.end(), name) - columns.begin();
  };
  const auto total_col = column("total_ms"), unsettled_col = column("unsettled");
  int step = 0, slowest = 0, unsettled = 0, last_unsettled = 0;
  double slowest_ms = -1;
  while (std::getline(f, line)) {
    ++step;
    std::vector<std::string> v;
    std::stringstream l(line);
    for (std::string c; std::getline(l, c, ',');) v.push_back(c);
    if (std::stod(v[total_col]) > slowest_ms) slowest_ms = std::stod(v[total_col]), slowest = step;
    if (std::stoi(v[unsettled_col]) > 0) ++unsettled, last_unsettled = step;
  }
  ASSERT_EQ(step, 40);
  std::smatch m;
  const std::regex first_line(R"(\ntotal [0-9.e+-]+ s \(solve [0-9.e+-]+ s\); median step .*; slowest step ([0-9]+): )");
  ASSERT_TRUE(std::regex_search(r.out, m, first_line)) << r.out;
  EXPECT_EQ(std::stoi(m[1]), slowest) << r.out;
  const std::string expected =
      unsettled == 0 ? std::string("unsettled steps: none\n")
                     : "unsettled steps: " + std::to_string(unsettled) + " of 40, the last at step " +
                           std::to_string(last_unsettled) + "\n";
  EXPECT_NE(r.out.find(expected), std::string::npos) << r.out;
}

}  // namespace
