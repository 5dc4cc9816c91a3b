#pragma once
// The CLI as a user runs it: each test gets a fresh directory for its files, and run() starts the
// built `rbpart` binary (RBPART_CLI) with shell-quoted arguments, capturing stdout and stderr.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace rbpart::test {

class CliTest : public ::testing::Test {
 protected:
  struct Result {
    int status;  // exit status; -1 if the process did not exit normally
    std::string out, err;
  };

  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("rbpart_cli_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name() + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
    return path(name);
  }
  static std::string read(const std::string& file) {
    std::ifstream in(file);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }

  // `prefix` goes before the binary, e.g. "timeout 20 " for a run that must not hang the suite.
  Result run(const std::string& args, const std::string& prefix = "") const {
    const std::string out = path("stdout.txt"), err = path("stderr.txt");
    const int raw = std::system((prefix + RBPART_CLI + " " + args + " >" + out + " 2>" + err).c_str());
    return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, read(out), read(err)};
  }

  std::filesystem::path dir_;
};

}  // namespace rbpart::test
