#pragma once
// Figures 3-5 of the study, drawn by scripts/plot_study.py with matplotlib from the tables in a
// study's output directory (docs/study.md).
#include <string>

namespace rbpart {

// A Python that imports matplotlib: the system's /usr/bin/python3 (Debian's python3-matplotlib)
// first, then python3 on PATH; "" if neither does.
std::string find_plot_python();

// scripts/plot_study.py: $RBPART_PLOT_SCRIPT if set, else in the source tree of this binary.
std::string plot_script_path();

// Runs the script on `dir` (fig3, fig4, fig5 as PNG and SVG next to the tables); returns its exit
// status (-1 if it could not be started).
int draw_figures(const std::string& python, const std::string& dir);

}  // namespace rbpart
