#include "study/machine.hpp"

#include <unistd.h>

#include <fstream>
#include <set>
#include <thread>
#include <utility>

#include "study/process.hpp"

namespace rbpart {

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n"), e = s.find_last_not_of(" \t\r\n");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

std::string compiler() {
#if defined(__clang__)
  return std::string("Clang ") + __clang_version__;
#elif defined(__GNUC__)
  return std::string("GCC ") + __VERSION__;
#else
  return "unknown";
#endif
}

// CMake passes the build type only as flags, so it is read back from the macros they set.
std::string build_type() {
#if defined(__OPTIMIZE__) && defined(NDEBUG)
  return "optimised, assertions off (Release)";
#elif defined(__OPTIMIZE__)
  return "optimised, assertions on";
#else
  return "unoptimised (Debug)";
#endif
}

}  // namespace

std::string source_root() {
  // This file is <root>/src/study/machine.cpp.
  std::string path = __FILE__;
  for (int up = 0; up < 3; ++up) {
    const auto slash = path.find_last_of('/');
    if (slash == std::string::npos) return ".";
    path.resize(slash);
  }
  return path.empty() ? "/" : path;
}

MachineInfo machine_info() {
  MachineInfo m;
  m.cpu = "unknown";
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::set<std::pair<std::string, std::string>> cores;
  std::string line, physical_id;
  int processors = 0;
  while (std::getline(cpuinfo, line)) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    const std::string key = trim(line.substr(0, colon)), value = trim(line.substr(colon + 1));
    if (key == "processor") ++processors;
    else if (key == "model name" && m.cpu == "unknown") m.cpu = value;
    else if (key == "physical id") physical_id = value;
    else if (key == "core id") cores.emplace(physical_id, value);
  }
  m.logical_cpus = processors > 0 ? processors : static_cast<int>(std::thread::hardware_concurrency());
  m.physical_cores = static_cast<int>(cores.size());
  m.compiler = compiler();
  m.build_type = build_type();

  const std::string root = source_root();
  std::string revision;
  if (run_process({"git", "-C", root, "rev-parse", "HEAD"}, &revision, true) == 0 && !trim(revision).empty()) {
    m.git_revision = trim(revision);
    // `git diff` reads the index without refreshing it (unlike `git status`): no writes to .git.
    m.git_dirty = run_process({"git", "-C", root, "diff", "--quiet", "HEAD", "--"}, nullptr, true) == 1;
  } else {
    m.git_revision = "unknown";
  }
  char host[256] = {};
  m.hostname = ::gethostname(host, sizeof host - 1) == 0 ? host : "unknown";
  return m;
}

}  // namespace rbpart
