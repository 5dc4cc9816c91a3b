#include "study/figures.hpp"

#include <cstdlib>

#include "study/machine.hpp"
#include "study/process.hpp"

namespace rbpart {

std::string find_plot_python() {
  for (const char* python : {"/usr/bin/python3", "python3"})
    if (run_process({python, "-c", "import matplotlib"}, nullptr, true) == 0) return python;
  return "";
}

std::string plot_script_path() {
  const char* env = std::getenv("RBPART_PLOT_SCRIPT");
  return env && *env ? env : source_root() + "/scripts/plot_study.py";
}

int draw_figures(const std::string& python, const std::string& dir) {
  return run_process({python, plot_script_path(), dir}, nullptr, false);
}

}  // namespace rbpart
