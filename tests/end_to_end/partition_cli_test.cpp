// `rbpart partition` and the partition options of `rbpart simulate` as a user runs them: part files,
// the JSON report, exit status 2 with one line naming the problem, nothing half written.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "support/cli_test.hpp"

namespace {

namespace fs = std::filesystem;

// Two 4-cliques {1..4} and {5..8} (edge weight 2) bridged by 4-5 (weight 3), METIS fmt 1.
const char* kTwoCliques =
    "% two cliques\n"
    "8 13 1\n"
    "2 2 3 2 4 2\n"
    "1 2 3 2 4 2\n"
    "1 2 2 2 4 2\n"
    "1 2 2 2 3 2 5 3\n"
    "4 3 6 2 7 2 8 2\n"
    "5 2 7 2 8 2\n"
    "5 2 6 2 8 2\n"
    "5 2 6 2 7 2\n";

class PartitionCli : public rbpart::test::CliTest {
 protected:
  void SetUp() override {
    CliTest::SetUp();
    graph_ = write("g.graph", kTwoCliques);
  }
  // Runs `rbpart <args>`; stdout and stderr land in out_ and err_.
  int rbpart(const std::string& args) {
    const Result r = run(args);
    out_ = r.out;
    err_ = r.err;
    return r.status;
  }
  // Exit 2, one stderr line containing `words`, no --out file.
  void expect_rejected(const std::string& args, const std::string& words) {
    EXPECT_EQ(rbpart(args + " --out " + path("p.part")), 2) << args << "\n" << err_;
    EXPECT_NE(err_.find(words), std::string::npos) << args << "\n" << err_;
    EXPECT_EQ(std::count(err_.begin(), err_.end(), '\n'), 1) << err_;
    EXPECT_FALSE(fs::exists(path("p.part")));
  }

  std::string graph_, out_, err_;
};

TEST_F(PartitionCli, WritesPartsAndTheQualityReport) {
  ASSERT_EQ(rbpart("partition --graph " + graph_ + " --partitioner bfs --nmax 4 --out " + path("p.part") +
                   " --report " + path("r.json")),
            0)
      << err_;
  EXPECT_EQ(read(path("p.part")), "0\n0\n0\n0\n1\n1\n1\n1\n");
  EXPECT_EQ(out_, "");
  EXPECT_EQ(err_, "");
  const std::string report = read(path("r.json"));
  EXPECT_EQ(std::count(report.begin(), report.end(), '\n'), 1);
  const nlohmann::json j = nlohmann::json::parse(report);
  EXPECT_EQ(j["partitioner"], "bfs");
  EXPECT_EQ(j["refiner"], "none");
  EXPECT_EQ(j["nmax"], 4);
  EXPECT_EQ(j["nodes"], 8);
  EXPECT_EQ(j["edges"], 13);
  EXPECT_EQ(j["parts"], 2);
  EXPECT_EQ(j["min_bodies"], 4);
  EXPECT_EQ(j["max_bodies"], 4);
  EXPECT_EQ(j["mean_bodies"], 4.0);
  EXPECT_EQ(j["edge_cut"], 3);        // the bridge's weight
  EXPECT_EQ(j["interface_rows"], 3);  // rows = weights for a file's edges
  EXPECT_EQ(j["interface_bodies"], 2);
  EXPECT_GE(j["partition_ms"].get<double>(), 0.0);
  EXPECT_GE(j["refine_ms"].get<double>(), 0.0);
}

TEST_F(PartitionCli, StdoutAndStderrWithoutOutputFiles) {
  ASSERT_EQ(rbpart("partition --graph " + graph_ + " --partitioner metis --refine fm --nmax 4"), 0) << err_;
  EXPECT_EQ(out_, "0\n0\n0\n0\n1\n1\n1\n1\n");
  EXPECT_EQ(std::count(err_.begin(), err_.end(), '\n'), 1);
  const nlohmann::json j = nlohmann::json::parse(err_);
  EXPECT_EQ(j["partitioner"], "metis");
  EXPECT_EQ(j["refiner"], "fm");
  EXPECT_EQ(j["edge_cut"], 3);
}

TEST_F(PartitionCli, EveryPartitionerAndRefinerGivesAValidPartFile) {
  for (const char* partitioner : {"bfs", "mindp", "maxdp", "mr", "mix", "metis"})
    for (const char* refiner : {"none", "kl", "fm", "fm-rollback"}) {
      const std::string args = std::string("partition --graph ") + graph_ + " --partitioner " + partitioner +
                               " --refine " + refiner + " --nmax 3 --debug-checks";
      ASSERT_EQ(rbpart(args), 0) << args << "\n" << err_;
      std::istringstream lines(out_);
      int count = 0, id = 0, parts = nlohmann::json::parse(err_)["parts"];
      while (lines >> id) {
        EXPECT_GE(id, 0);
        EXPECT_LT(id, parts);
        ++count;
      }
      EXPECT_EQ(count, 8) << args;
    }
}

TEST_F(PartitionCli, MassesDriveMr) {
  // A path of 8 (weights 1), masses 1 x4 then 100 x4; nmax 7. BFS: the first 7, then 1. MR (tau 10):
  // the light half, then the heavy half.
  const std::string path8 = write("p.graph", "8 7\n2\n1 3\n2 4\n3 5\n4 6\n5 7\n6 8\n7\n");
  const std::string masses = write("m.txt", "1\n1\n1\n1\n100\n100\n100\n100\n");
  ASSERT_EQ(rbpart("partition --graph " + path8 + " --masses " + masses + " --partitioner bfs --nmax 7"), 0) << err_;
  EXPECT_EQ(out_, "0\n0\n0\n0\n0\n0\n0\n1\n");
  ASSERT_EQ(rbpart("partition --graph " + path8 + " --masses " + masses + " --partitioner mr --nmax 7"), 0) << err_;
  EXPECT_EQ(out_, "0\n0\n0\n0\n1\n1\n1\n1\n");
  ASSERT_EQ(rbpart("partition --graph " + path8 + " --partitioner mr --nmax 7"), 0) << err_;
  EXPECT_EQ(out_, "0\n0\n0\n0\n0\n0\n0\n1\n");  // default masses 1
}

// --parts K, as METIS users ask: the cap of K balanced parts, ceil(n / K), reported beside the parts made.
TEST_F(PartitionCli, PartsKSetsTheCapOfKBalancedParts) {
  ASSERT_EQ(rbpart("partition --graph " + graph_ + " --partitioner metis --parts 2 --report " + path("r.json")), 0)
      << err_;
  EXPECT_EQ(out_, "0\n0\n0\n0\n1\n1\n1\n1\n");  // the two cliques, cut at the bridge
  nlohmann::json j = nlohmann::json::parse(read(path("r.json")));
  EXPECT_EQ(j["requested_parts"], 2);
  EXPECT_EQ(j["nmax"], 4);
  EXPECT_EQ(j["parts"], 2);
  ASSERT_EQ(rbpart("partition --graph " + graph_ + " --partitioner bfs --parts 3 --report " + path("r.json")), 0)
      << err_;
  j = nlohmann::json::parse(read(path("r.json")));
  EXPECT_EQ(j["nmax"], 3);  // ceil(8 / 3)
  EXPECT_LE(j["max_bodies"].get<int>(), 3);
  EXPECT_GE(j["parts"].get<int>(), 3);
  // Without --parts the report has no requested_parts.
  ASSERT_EQ(rbpart("partition --graph " + graph_ + " --partitioner bfs --nmax 4 --report " + path("r.json")), 0);
  EXPECT_FALSE(nlohmann::json::parse(read(path("r.json"))).contains("requested_parts"));
}

TEST_F(PartitionCli, BadOptionsExitTwo) {
  const std::string g = "partition --graph " + graph_;
  expect_rejected(g + " --partitioner bfs --nmax 0", "--nmax must be at least 1");
  expect_rejected(g + " --partitioner mr --nmax 4 --tau-mr 1", "--tau-mr must be greater than 1");
  expect_rejected(g + " --partitioner mix --nmax 4 --tau-mix 0", "--tau-mix must lie in (0, 1)");
  expect_rejected(g + " --partitioner mix --nmax 4 --tau-mix 1", "--tau-mix must lie in (0, 1)");
  expect_rejected(g + " --partitioner kway --nmax 4", "unknown partitioner 'kway' (choose one of none, bfs");
  expect_rejected(g + " --partitioner none --nmax 4", "--partitioner none makes no partition");
  expect_rejected(g + " --partitioner bfs --refine sa --nmax 4", "unknown refiner 'sa'");
  expect_rejected(g + " --nmax 4", "--partitioner is required");
  expect_rejected(g + " --partitioner bfs --nmax four", "--nmax");
  expect_rejected(g + " --partitioner bfs --parts 0", "--parts: must be at least 1");
  expect_rejected(g + " --partitioner bfs --parts 2 --nmax 4", "excludes");
  expect_rejected("partition --partitioner bfs", "--graph is required");
}

TEST_F(PartitionCli, BadFilesExitTwoNamingTheLine) {
  const std::string bad = write("bad.graph", "3 2\n2 3\n1 3\n2\n");
  expect_rejected("partition --partitioner bfs --graph " + bad, bad + ":2: edge 1-3 has no reverse");
  const std::string self = write("self.graph", "2 1\n2\n2\n");
  expect_rejected("partition --partitioner bfs --graph " + self, self + ":3: self loop on vertex 2");
  const std::string word = write("word.graph", "2 1\n2\none\n");
  expect_rejected("partition --partitioner bfs --graph " + word, word + ":3: neighbour 'one' is not an integer");
  const std::string empty = write("empty.graph", "0 0\n");
  expect_rejected("partition --partitioner bfs --graph " + empty, empty + ":1: empty graph");
  const std::string masses = write("m.txt", "1\n1\n1\n1\n1\n0\n1\n1\n");
  expect_rejected("partition --partitioner mr --graph " + graph_ + " --masses " + masses,
                  masses + ":6: mass 0 is not positive");
  expect_rejected("partition --partitioner bfs --graph " + path("missing.graph"), "missing.graph: cannot open");
}

// A star whose three edges weigh 2^31 - 1 each: parts {1, 2}, {3}, {4} cut two of them, a sum that
// 32-bit arithmetic reported as -2 (issue #26); the refiner's tracked cut must agree (debug checks).
TEST_F(PartitionCli, CutOfMaximalEdgeWeightsIsExact) {
  const std::string star = write("star.graph", "4 3 1\n2 2147483647 3 2147483647 4 2147483647\n1 2147483647\n"
                                               "1 2147483647\n1 2147483647\n");
  ASSERT_EQ(rbpart("partition --graph " + star + " --partitioner bfs --nmax 2 --refine fm --debug-checks --out " +
                   path("p.part") + " --report " + path("r.json")),
            0)
      << err_;
  const nlohmann::json j = nlohmann::json::parse(read(path("r.json")));
  EXPECT_EQ(j["parts"], 3);
  EXPECT_EQ(j["edge_cut"].get<std::int64_t>(), 2 * std::int64_t{2147483647});
  EXPECT_EQ(j["interface_rows"].get<std::int64_t>(), 2 * std::int64_t{2147483647});
}

// Outputs that are not regular files are written where they are (issue #26): "-" is standard
// output, a symlink keeps pointing at its target, which gets the parts; a directory is refused
// before the work.
TEST_F(PartitionCli, OutputsThroughDashSymlinksAndNotDirectories) {
  ASSERT_EQ(rbpart("partition --graph " + graph_ + " --partitioner bfs --nmax 4 --out - --report " + path("r.json")), 0)
      << err_;
  EXPECT_EQ(out_, "0\n0\n0\n0\n1\n1\n1\n1\n");
  EXPECT_FALSE(fs::exists("-"));
  fs::create_directory(path("kept"));
  fs::create_symlink("kept/parts.txt", path("link"));
  ASSERT_EQ(rbpart("partition --graph " + graph_ + " --partitioner bfs --nmax 4 --out " + path("link")), 0) << err_;
  EXPECT_TRUE(fs::is_symlink(path("link")));
  EXPECT_EQ(read(path("kept/parts.txt")), "0\n0\n0\n0\n1\n1\n1\n1\n");
  expect_rejected("partition --graph " + graph_ + " --partitioner bfs --report " + path("kept"),
                  path("kept") + ": is a directory");
}

TEST_F(PartitionCli, ReportAndOutNotLeftHalfWrittenOnBadInput) {
  const std::string bad = write("bad.graph", "3 3\n2\n1 3\n2\n");
  EXPECT_EQ(rbpart("partition --partitioner bfs --graph " + bad + " --out " + path("p.part") + " --report " +
                   path("r.json")),
            2);
  EXPECT_FALSE(fs::exists(path("p.part")));
  EXPECT_FALSE(fs::exists(path("r.json")));
}

// The simulate stage: stats carry the partition's columns and the run parameters name it.
TEST_F(PartitionCli, SimulateReportsThePartitionPerStep) {
  ASSERT_EQ(rbpart("simulate --scene rock_pile --set rocks=40 --steps 90 --solver pgs --partitioner mix --refine none "
                   "--nmax 8 --quiet --stats " + path("s.csv")),
            0)
      << err_;
  const nlohmann::json params = nlohmann::json::parse(read(path("s.csv.json")));
  for (const auto& [key, value] : {std::pair<const char*, const char*>{"partitioner", "mix"},
                                   {"refiner", "none"}, {"nmax", "8"}, {"tau_mix", "0.5"}})
    EXPECT_EQ(params.value(key, ""), value) << key;
  std::istringstream csv(read(path("s.csv")));
  std::string line, header;
  std::getline(csv, header);
  std::vector<std::string> columns;
  std::stringstream h(header);
  for (std::string c; std::getline(h, c, ',');) columns.push_back(c);
  auto column = [&](const std::string& name) {
    const auto it = std::find(columns.begin(), columns.end(), name);
    EXPECT_NE(it, columns.end()) << name;
    return it - columns.begin();
  };
  const auto parts = column("parts"), rows = column("interface_rows"), bodies = column("interface_bodies"),
             cut = column("edge_cut"), ms = column("partition_ms"), islands = column("islands");
  int lines = 0, with_cut = 0, with_time = 0, more_parts_than_islands = 0;
  while (std::getline(csv, line)) {
    std::vector<double> v;
    std::stringstream l(line);
    for (std::string c; std::getline(l, c, ',');) v.push_back(std::stod(c));
    ++lines;
    with_cut += v[cut] > 0 && v[rows] > 0 && v[bodies] > 0;
    with_time += v[ms] > 0;
    more_parts_than_islands += v[parts] > v[islands];
  }
  EXPECT_EQ(lines, 90);
  EXPECT_GT(with_cut, 0);
  EXPECT_GT(with_time, 0);
  EXPECT_GT(more_parts_than_islands, 0);
}

TEST_F(PartitionCli, SimulateRejectsBadPartitionOptions) {
  const std::string s = "simulate --scene rock_pile --set rocks=4 --steps 2 --quiet --stats " + path("s.csv");
  for (const auto& [args, words] : std::vector<std::pair<std::string, std::string>>{
           {" --partitioner mix --nmax 0", "--nmax must be at least 1"},
           {" --partitioner mix --tau-mix 1.5", "--tau-mix must lie in (0, 1)"},
           {" --partitioner mr --tau-mr 0.5", "--tau-mr must be greater than 1"},
           {" --partitioner foo", "unknown partitioner 'foo'"},
           {" --partitioner bfs --refine bar", "unknown refiner 'bar'"}}) {
    EXPECT_EQ(rbpart(s + args), 2) << args;
    EXPECT_NE(err_.find(words), std::string::npos) << err_;
    EXPECT_FALSE(fs::exists(path("s.csv")));
  }
}

}  // namespace
