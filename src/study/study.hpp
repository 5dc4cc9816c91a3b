#pragma once
// The partitioning study (issue #6): the paper's Table 1 and Figures 3-5 from one command,
// `rbpart bench`. Each scene's trajectory is recorded once with the direct solver
// (study/capture.hpp) and every configuration — partitioner x refiner x n_max x threads, plus the
// direct baseline — solves the same recorded problems (study/replay.hpp). docs/study.md explains
// the measurements and the outputs.
#include <rbpart/params.hpp>
#include <rbpart/scene.hpp>

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "study/replay.hpp"

namespace rbpart {

// A scene of the study: a built-in scene with parameter overrides, or a scene file.
struct StudyScene {
  std::string label;   // its name in the outputs: the text it was parsed from
  std::string source;  // built-in scene name or scene file path
  std::vector<std::pair<std::string, std::string>> overrides;
  int rocks = 0;       // entries of the Rock Pile scaling (Figure 4): the rock count
};

// "name[:key=value[:key=value...]]" (a built-in scene, `rbpart scenes`) or a scene file path.
// Throws InputError on a malformed override; unknown scenes and keys are caught by make_study_scene.
StudyScene parse_study_scene(const std::string& text);
SceneDef make_study_scene(const StudyScene& scene);

struct StudySpec {
  std::string preset;
  std::vector<StudyScene> scenes;   // Table 1, Figures 3 and 5
  // Figure 4: rock_pile with these rock counts (empty: no scaling study) and these other overrides.
  std::vector<int> scaling_rocks;
  std::vector<std::pair<std::string, std::string>> scaling_overrides;
  int steps = 0;   // steps simulated per scene; 0: each scene's own count
  int every = 1;   // record (and replay) steps every, 2 every, ...
  std::vector<PartitionerKind> partitioners;
  std::vector<RefinerKind> refiners;
  std::vector<int> nmax;
  std::vector<int> threads;
  int repeats = 3;
  // Unrefined MinDP, the reference of the "vs MinDP" column and of the claims, is measured even when
  // not listed; false leaves it out (a sweep of other partitioners, where it would cost the most:
  // 1.9 s a solve against 0.08 s for METIS on the Large Rock Pile at n_max 300).
  bool mindp_reference = true;
  StepParams step_params;
  SolverParams solver_params;
  PartitionParams partition_params;  // tau_mr, tau_mix, debug_checks
};

// n_max of the presets. The substructured solve's cost per step is roughly a dense factorisation
// per part (O(n_max^3) each) plus the interface problem, which grows as parts shrink; docs/study.md
// gives the measurements this value was chosen from.
constexpr int kStudyNmax = 32;
constexpr int kQuickNmax = 8;  // the quick preset's small scenes (study_preset)

// The presets: "paper" (docs/design.md#scenes scenes, 500 steps, Rock Pile scaling 50-800 rocks, three
// repeats) and "quick" (the same grid on small scenes and short runs, for CI). InputError otherwise.
StudySpec study_preset(const std::string& name);

// Throws InputError naming the first bad field (no scene, empty lists, values out of range).
void validate_study(const StudySpec& spec);

// The study's columns: per thread count the direct baseline, then every partitioner except METIS
// with every refiner, then METIS (a reference) unrefined; per n_max. MinDP unrefined, the
// reference of the relative column, is added when the lists leave it out.
std::vector<StudyConfig> study_configs(const StudySpec& spec);

// Runs the study and writes table1.csv, table1.md, steps.csv, scaling.csv and machine.json into
// `out_dir` (created if missing; InputError if it cannot be written). Every file is rewritten,
// atomically, after each scene, so an interrupted run leaves the scenes finished so far; with
// `resume`, the scenes an earlier run of the same study (same protocol: machine.json's "study" but
// its scene lists, and parameters; InputError otherwise) finished there are kept, not measured
// again, and each scene's revision is recorded. Progress bars on stderr when it is a terminal; one
// summary line per scene on `log` (null: silent).
void run_study(const StudySpec& spec, const std::string& out_dir, std::FILE* log, bool resume = false);

}  // namespace rbpart
