// `rbpart bench` as a user runs it: bad options exit 2 with one line and write nothing; a tiny
// study writes its tables and removes an earlier study's figures.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "support/cli_test.hpp"

namespace {

namespace fs = std::filesystem;

using BenchCli = rbpart::test::CliTest;

TEST_F(BenchCli, BadOptionsExitTwoWithOneLineAndWriteNothing) {
  const std::string out = (dir_ / "study").string();
  const std::pair<const char*, const char*> cases[] = {
      {"--preset nope", "preset"},
      {"--partitioners mindp,nope", "partitioner"},
      {"--partitioners none", "--partitioners"},
      {"--refine kl,sideways", "refiner"},
      {"--nmax 0", "--nmax"},
      {"--threads 0", "--threads"},
      {"--repeats 0", "--repeats"},
      {"--repeats two", "--repeats"},
      {"--steps 0", "--steps"},
      {"--every 0", "--every"},
      {"--steps 3 --every 5", "--every"},
      {"--scaling 0", "--scaling"},
      {"--scenes no_such_scene", "no_such_scene"},
      {"--scenes rock_pile:rocks", "rock_pile:rocks"},
      {"--scenes rock_pile:bogus=1", "bogus"},
      {"--no-such-option", "no-such-option"},
  };
  for (const auto& [args, expect] : cases) {
    SCOPED_TRACE(args);
    const Result r = run("bench " + std::string(args) + " --out " + out);
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find(expect), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
  const Result missing_out = run("bench --preset quick");
  EXPECT_EQ(missing_out.status, 2) << missing_out.err;
  EXPECT_NE(missing_out.err.find("--out"), std::string::npos) << missing_out.err;
}

TEST_F(BenchCli, TinyStudyWritesItsTables) {
  const fs::path out = dir_ / "study";
  fs::create_directories(out);
  std::ofstream(out / "fig4.png") << "an earlier study's figure";
  const Result r = run("bench --scenes chain_drop:links=8 --partitioners mix --refine fm --nmax 3 --threads 1 "
                       "--repeats 1 --steps 4 --no-scaling --no-plots --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* name : {"table1.csv", "table1.md", "steps.csv", "scaling.csv", "machine.json"})
    EXPECT_TRUE(fs::exists(out / name)) << name;
  EXPECT_FALSE(fs::exists(out / "fig4.png"));  // it would not match the new tables
  // Header, the direct baseline, MinDP unrefined (the reference, always measured) and MIX+FM.
  std::ifstream table(out / "table1.csv");
  std::string line;
  int lines = 0;
  bool mix_fm = false;
  while (std::getline(table, line)) {
    ++lines;
    mix_fm |= line.find(",substructured,mix,fm,3,1,") != std::string::npos;
  }
  EXPECT_EQ(lines, 4);
  EXPECT_TRUE(mix_fm);
}

TEST_F(BenchCli, NoReferenceLeavesMinDpOut) {
  const fs::path out = dir_ / "study";
  const Result r = run("bench --scenes chain_drop:links=8 --partitioners mix --refine fm --nmax 3 --threads 1 "
                       "--repeats 1 --steps 4 --no-scaling --no-reference --no-plots --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  // Header, the direct baseline and MIX+FM: no MinDP, and no change against it.
  std::ifstream table(out / "table1.csv");
  std::string line;
  int lines = 0;
  while (std::getline(table, line)) {
    ++lines;
    EXPECT_EQ(line.find(",mindp,"), std::string::npos) << line;
    if (line.find(",substructured,mix,fm,3,1,") != std::string::npos) EXPECT_NE(line.find(",nan,"), std::string::npos) << line;
  }
  EXPECT_EQ(lines, 3);
  std::ifstream machine(out / "machine.json");
  const std::string json((std::istreambuf_iterator<char>(machine)), std::istreambuf_iterator<char>());
  EXPECT_NE(json.find("\"mindp_reference\": false"), std::string::npos);
}

}  // namespace
