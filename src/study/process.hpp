#pragma once
// Running a helper program (git, the plotting script) without a shell: no quoting, no injection.
#include <string>
#include <vector>

namespace rbpart {

// Runs argv[0] (searched on PATH) with `argv` and waits. With `out` its stdout is captured there;
// with `quiet` its stderr (and stdout, if not captured) goes to /dev/null, else to ours. Returns
// the exit status, or -1 if it could not be started or did not exit normally.
int run_process(const std::vector<std::string>& argv, std::string* out, bool quiet);

}  // namespace rbpart
