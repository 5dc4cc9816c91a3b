// The rbpart CLI as a user runs it: exit statuses, one-line errors, no half-written outputs, and
// export -> load -> simulate reproducing a built-in run exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

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
  // The direct solver is the Newton solver: `newton` is no longer a solver of its own.
  EXPECT_EQ(run("simulate --scene box_stack --solver newton").err,
            "rbpart: error: --solver: newton not in {direct,pgs,substructured}\n");
}

TEST_F(Cli, NumericOptionsNameTheirBound) {
  const std::pair<std::string, std::string> cases[] = {
      {"--steps -3", "--steps: must be at least 0 (got -3)"},
      {"--dt 0", "--dt: must lie in (0, 1] (got 0)"},
      {"--dt 1e300", "--dt: must lie in (0, 1] (got 1e300)"},
      {"--erp 0", "--erp: must lie in (0, 1] (got 0)"},
      {"--erp 1.5", "--erp: must lie in (0, 1] (got 1.5)"},
      {"--max-factorizations 0", "--max-factorizations: must be positive (got 0)"},
      // The direct solver's body-space systems divide by every row's regularisation.
      {"--sigma-floor 0", "--sigma-floor: must be positive (got 0)"},
      {"--slop nan", "--slop: must be a number (got 'nan')"},
      {"--contact-prox -1e-3", "--contact-prox: must be at least 0 (got -1e-3)"},
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
                          "edge_cut", "partition_ms", "refine_ms", "solve_ms", "solver_iterations", "factorizations",
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
  const Result r = run("simulate --scene rock_pile --set rocks=20 --steps 40 --max-factorizations 1 "
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

// Outputs that are not regular files (issue #26): "-" is standard output, a FIFO is written
// through and stays a FIFO, a symlink stays a symlink and its target gets the file.
TEST_F(Cli, OutputsGoThroughStdoutFifosAndSymlinks) {
  const Result dash = run("simulate --scene box_stack --steps 3 -q --stats -");
  ASSERT_EQ(dash.status, 0) << dash.err;
  EXPECT_NE(dash.out.find("step,bodies,"), std::string::npos) << dash.out;
  EXPECT_FALSE(fs::exists("-"));
  EXPECT_FALSE(fs::exists("-.json"));

  const std::string fifo = path("state.fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  fs::create_directory(path("runs"));
  fs::create_symlink("runs/s.csv", path("s.csv"));
  // The read end is held open without blocking, so the writer never waits, and a FIFO that was
  // replaced by a file cannot hang the test: the text waits in the pipe's buffer.
  const int in = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(in, 0);
  const Result r = run("simulate --scene box_stack --steps 3 -q --state " + fifo + " --stats " + path("s.csv"));
  std::string state;
  char buffer[4096];
  for (ssize_t n; (n = ::read(in, buffer, sizeof buffer)) > 0;) state.append(buffer, n);
  ::close(in);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(state.find("\"bodies\""), std::string::npos) << state;
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_TRUE(fs::is_symlink(path("s.csv")));
  EXPECT_NE(read(path("runs/s.csv")).find("step,bodies,"), std::string::npos);
  EXPECT_EQ(std::distance(fs::directory_iterator(path("runs")), fs::directory_iterator()), 1);
}

// A directory given as an output is refused before the run (issue #26): the state file is written
// last, so a late check would have committed the stats first.
TEST_F(Cli, DirectoryAsOutputIsRefusedUpFront) {
  fs::create_directory(path("out"));
  const Result r = run("simulate --scene box_stack --steps 5 --stats " + path("s.csv") + " --state " + path("out"));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(r.err, "rbpart: error: " + path("out") + ": is a directory\n");
  EXPECT_FALSE(fs::exists(path("s.csv")));
  EXPECT_TRUE(fs::is_empty(path("out")));
}

// Values given with --set pass the checks a scene file's values pass, and a bad one gets exit 2
// naming the parameter (issue #26: these ran to exit 0, truncated or clamped, or ended in an
// internal error). rocks=20000 is past the cap that keeps a scene within memory.
TEST_F(Cli, SetValuesAreCheckedNamingTheParameter) {
  const std::pair<const char*, const char*> cases[] = {
      {"rock_pile --set dt=0", "scene rock_pile: parameter 'dt' must be in (0, 1] (got 0)"},
      {"rock_pile --set friction=-0.5", "parameter 'friction' must be in [0, 1000] (got -0.5)"},
      {"rock_pile --set points=3", "parameter 'points' must be a whole number in [4, 100] (got 3)"},
      {"rock_pile --set min_size=0.5 --set max_size=0.2", "parameter 'min_size' (0.5) must not exceed 'max_size' (0.2)"},
      {"box_pile --set boxes=-5", "parameter 'boxes' must be a whole number in [1, 10000] (got -5)"},
      {"rock_pile --set seed=1.5", "parameter 'seed' must be a whole number"},
      {"rock_pile --set rocks=20000", "parameter 'rocks' must be a whole number in [1, 10000] (got 20000)"},
      {"chain_drop --set mass=1e308", "parameter 'mass' must be in [1e-09, 1e+12] (got 1e308)"},
      {"rock_pile --set density=1e-308", "scene rock_pile: body 'rock0': mass"},
      {"pendulum --set radius=1e200", "parameter 'radius' must be in (0, 10000] (got 1e200)"},
  };
  for (const auto& [args, expect] : cases) {
    const Result r = run(std::string("simulate --scene ") + args + " --steps 0 --stats " + path("s.csv"));
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    EXPECT_NE(r.err.find(expect), std::string::npos) << args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
    EXPECT_FALSE(fs::exists(path("s.csv"))) << args;
  }
}

// Finite values a scene file may hold but the dynamics cannot carry (issue #26).
TEST_F(Cli, OutOfRangeSceneFileValues) {
  const std::string ball = R"("shape": {"type": "sphere", "radius": 0.5})";
  expect_rejected(scene_with("{" + ball + R"(, "mass": 1e308})"), "bodies[1]: body 'body1': mass 1e+308 kg is outside");
  expect_rejected(scene_with("{" + ball + R"(, "density": 1e-308})"), "bodies[1]: body 'body1': mass");
  expect_rejected(scene_with(R"({"shape": {"type": "sphere", "radius": 1e200}, "mass": 1})"),
                  "bodies[1]: body 'body1': sphere radius must lie in");
  expect_rejected(R"({"name": "t", "dt": 1e300, "bodies": [)" + std::string(kGround) + "]}",
                  "bad.json: dt: must be at most 1 s (got 1e+300)");
  expect_rejected(scene_with("{" + ball + R"(, "mass": 1, "position": [0, 0, 1]})",
                             R"([{"type": "hinge", "bodies": [1, -1], "anchor": [0, 0, 1], "axis": [1e-200, 0, 0]}])"),
                  "joints[0].axis: is too short or too long to normalise");
}

// Ctrl-C during a long run (issue #26: it left hidden .tmp- files and no output): the run stops
// after the step under way, the statistics of the steps done are kept and marked incomplete, the
// recording and the state are not written (the sidecar says "incomplete"), no temporary file is left, and the exit status is
// 128 + SIGINT.
TEST_F(Cli, InterruptKeepsTheStepsDoneAndLeavesNoTemporaries) {
  const std::string args[] = {RBPART_CLI, "simulate", "--scene", "rock_pile", "--set", "rocks=30", "--steps", "100000",
                              "-q", "--stats", path("s.csv"), "--state", path("s.json"), "--record", path("r.rbrec")};
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  // Some steps in: the stats' temporary file holds data once the first stdio buffer is flushed.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  const auto stats_written = [&] {
    for (const auto& e : fs::directory_iterator(dir_))
      if (e.path().filename().string().rfind(".s.csv.tmp-", 0) == 0 && fs::file_size(e.path()) > 0) return true;
    return false;
  };
  while (!stats_written() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ::kill(child, SIGINT);
  int status = 0;
  pid_t waited = 0;
  while ((waited = ::waitpid(child, &status, WNOHANG)) == 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  if (waited == 0) {
    ::kill(child, SIGKILL);
    ::waitpid(child, &status, 0);
    FAIL() << "simulate did not stop on SIGINT";
  }
  ASSERT_TRUE(WIFEXITED(status)) << status;
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGINT);
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"s.csv", "s.csv.json"}));
  std::ifstream f(path("s.csv"));
  std::string line;
  int data = -1;  // the header
  while (std::getline(f, line)) ++data;
  EXPECT_GT(data, 0);
  const nlohmann::json params = nlohmann::json::parse(read(path("s.csv.json")));
  EXPECT_EQ(params.value("incomplete", ""), "stopped by SIGINT after " + std::to_string(data) + " of 100000 steps");
}
}  // namespace
