#pragma once
// What a study's numbers were measured on (machine.json): CPU, cores, compiler, build, revision.
#include <string>

namespace rbpart {

struct MachineInfo {
  std::string cpu;            // "model name" of /proc/cpuinfo ("unknown" elsewhere)
  int logical_cpus = 0;       // hardware threads
  int physical_cores = 0;     // distinct (physical id, core id) pairs; 0 if /proc/cpuinfo lacks them
  std::string compiler;       // e.g. "GCC 12.2.0"
  std::string build_type;     // from the compiler's macros: optimised or not, assertions or not
  std::string git_revision;   // of the source tree this binary was built from, read at run time;
                              // "unknown" without git or a repository (a tarball)
  bool git_dirty = false;     // tracked files differ from the revision
  std::string hostname;
};

MachineInfo machine_info();

// The source tree this binary was compiled from (derived from this file's compile-time path).
std::string source_root();

}  // namespace rbpart
