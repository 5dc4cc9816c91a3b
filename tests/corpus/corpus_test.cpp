// The fuzz corpus (this folder): malformed scene files, METIS graphs, mass files and recordings,
// with a few valid controls, each run through the CLI as expected.tsv says. Bad input
// must exit with status 2 and one line naming the problem, and leave no output file (not even a
// temporary); a valid control exits 0 and leaves exactly its outputs. The sanitizer build of CI
// (scripts/test.sh, build-asan) runs these too.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli_test.hpp"

namespace rbpart::test {
namespace {

const std::string kCorpus = std::string(RBPART_SOURCE_DIR) + "/tests/corpus";

// How each command of the manifest runs its file ({file}) into an empty output directory ({out}),
// and the outputs a successful run leaves there.
struct Command {
  std::string name, args;
  std::set<std::string> outputs;
};
const std::vector<Command> kCommands = {
    {"simulate",
     "simulate --scene {file} --steps 2 -q --stats {out}/stats.csv --state {out}/state.json --record {out}/run.rbrec",
     {"stats.csv", "stats.csv.json", "state.json", "run.rbrec"}},
    {"partition", "partition --graph {file} --out {out}/parts.txt --report {out}/report.json",
     {"parts.txt", "report.json"}},
    {"snapshot", "snapshot {file} --out {out}/step.png", {"step.png"}},
};

// One line of expected.tsv: file (relative to tests/corpus), command, exit status, what stderr
// must contain (status 2; "-" for status 0), and the command's further arguments ({corpus}: the
// corpus directory).
struct Case {
  std::string file, command;
  int status = 0;
  std::string message, extra;
  int line = 0;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.file << " (" << c.command << ")"; }

std::vector<Case> read_manifest() {
  std::ifstream in(kCorpus + "/expected.tsv");
  std::vector<Case> cases;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    if (text.empty() || text[0] == '#') continue;
    std::vector<std::string> fields;
    std::stringstream s(text);
    for (std::string field; std::getline(s, field, '\t');) fields.push_back(field);
    Case c;
    c.line = line;
    if (fields.size() >= 4) {
      c.file = fields[0];
      c.command = fields[1];
      c.status = std::atoi(fields[2].c_str());
      c.message = fields[3];
      c.extra = fields.size() > 4 ? fields[4] : "";
    }
    cases.push_back(c);  // a malformed line fails its test (file empty)
  }
  return cases;
}

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

std::set<std::string> files_in(const std::string& dir) {
  std::set<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) names.insert(entry.path().filename().string());
  return names;
}

class Corpus : public CliTest, public ::testing::WithParamInterface<Case> {};

TEST_P(Corpus, ExitsWithTheExpectedStatusAndLeavesNoPartialOutput) {
  const Case& c = GetParam();
  ASSERT_FALSE(c.file.empty()) << "expected.tsv:" << c.line << ": needs file, command, status, message[, arguments]";
  ASSERT_TRUE(std::filesystem::is_regular_file(kCorpus + "/" + c.file)) << c.file;
  const auto command =
      std::find_if(kCommands.begin(), kCommands.end(), [&](const Command& k) { return k.name == c.command; });
  ASSERT_NE(command, kCommands.end()) << "expected.tsv:" << c.line << ": unknown command " << c.command;
  const std::string out = path("out");
  std::filesystem::create_directories(out);
  std::string args = command->args + (c.extra.empty() ? "" : " " + c.extra);
  args = replace_all(args, "{file}", "'" + kCorpus + "/" + c.file + "'");
  args = replace_all(args, "{corpus}", "'" + kCorpus + "'");
  args = replace_all(args, "{out}", "'" + out + "'");

  // A hang is a failure too (the sanitizer build is slower, hence the generous limit).
  const Result r = run(args, "timeout 300 ");
  SCOPED_TRACE("expected.tsv:" + std::to_string(c.line) + ": rbpart " + args);
  EXPECT_EQ(r.status, c.status) << r.err;
  if (c.status == 2) {
    // One line, "rbpart: error: <what>", that names the problem.
    ASSERT_FALSE(r.err.empty());
    EXPECT_EQ(r.err.rfind("rbpart: error: ", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.back(), '\n') << r.err;
    EXPECT_TRUE(std::none_of(r.err.begin(), r.err.end() - 1,
                             [](unsigned char ch) { return ch < 0x20 || ch == 0x7f; }))
        << "a control byte in: " << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << "expected '" << c.message << "' in: " << r.err;
    EXPECT_EQ(files_in(out), std::set<std::string>{}) << "bad input left output behind";
  } else {
    EXPECT_EQ(files_in(out), command->outputs) << "not exactly the outputs (or a temporary left behind)";
  }
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  std::string name = std::to_string(info.index) + "_" + info.param.file + "_" + info.param.command;
  for (char& ch : name)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return name;
}

INSTANTIATE_TEST_SUITE_P(Files, Corpus, ::testing::ValuesIn(read_manifest()), case_name);

}  // namespace
}  // namespace rbpart::test
