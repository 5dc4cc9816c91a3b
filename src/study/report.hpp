#pragma once
// The study's tables: per-step medians (steps.csv), their means per scene and configuration
// (table1.csv, table1.md, scaling.csv). Formats are described in docs/study.md.
#include <array>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "solve/island_chunks.hpp"
#include "study/replay.hpp"

namespace rbpart {

// One scene's replay, with what the tables need to know about the scene.
struct SceneResult {
  std::string label;
  int rocks = 0;              // Rock Pile scaling entries, else 0
  int dynamic_bodies = 0;
  int simulated_steps = 0;
  std::vector<int> steps;     // recorded step numbers
  std::vector<int> rows;      // rows of each recorded step
  std::vector<StudyConfig> configs;
  ReplayResult replay;
  double capture_ms = 0, replay_ms = 0;
  std::string git_revision;   // of the binary that measured it (a resumed study may mix revisions)
};

// The core counts of the estimates (docs/study.md, "Reading the numbers on a small machine").
inline constexpr int kEstimateCores[] = {4, 8, 16};
inline constexpr std::size_t kEstimates = std::size(kEstimateCores);
// The solver splits its independent work in as many chunks as the most cores estimated.
static_assert(kEstimateCores[kEstimates - 1] == kMaxChunks);

// A substructured solve's time on `cores` cores, bounded below by its critical path and by its work
// shared evenly: max(critical_path_ms, work_ms / cores) (DESIGN.md §7). 0 for the direct baseline,
// which reports neither.
double estimated_ms(const StepMeasure& m, int cores);

// Means over a scene's recorded steps of one configuration's per-step medians (and their median
// over the steps: one landing step that takes 100 times the others moves the mean).
struct ConfigSummary {
  StudyConfig config;
  double mean_solve_ms = 0, median_solve_ms = 0, max_solve_ms = 0, mean_partition_ms = 0, mean_refine_ms = 0;
  double mean_work_ms = 0, mean_critical_path_ms = 0;  // substructured only
  // Substructured only: the mean over the steps of each step's estimated_ms on kEstimateCores[k]
  // cores, and the direct baseline's mean solve time (same steps and threads) over the estimate on
  // the most cores: the speed-up those cores would give, were the estimate reached.
  std::array<double, kEstimates> mean_estimate_ms{};
  double direct_over_estimate = 0;
  double mean_parts = 0, mean_interface_rows = 0, mean_interface_bodies = 0, mean_edge_cut = 0;
  double mean_factorizations = 0;
  int unsettled = 0;          // islands, summed over the steps
  double max_lambda_error = 0;
  // mean_solve_ms / that of MinDP unrefined with the same threads (and n_max; the first n_max for
  // the direct baseline), from the same recorded steps and repeats.
  double solve_vs_mindp = 0;
};

std::vector<ConfigSummary> summarize(const SceneResult& scene);

// steps.csv's measured columns after "step,rows", in file order: counts, then times and errors
// (the writer and the reader of bench --resume share them). The estimates est<c>_ms of
// kEstimateCores follow them, derived from work_ms and critical_path_ms (empty for the baseline).
inline constexpr std::pair<const char*, int StepMeasure::*> kStepCounts[] = {
    {"parts", &StepMeasure::parts},
    {"interface_rows", &StepMeasure::interface_rows},
    {"interface_bodies", &StepMeasure::interface_bodies},
    {"edge_cut", &StepMeasure::edge_cut},
    {"factorizations", &StepMeasure::factorizations},
    {"unsettled", &StepMeasure::unsettled}};
inline constexpr std::pair<const char*, double StepMeasure::*> kStepValues[] = {
    {"partition_ms", &StepMeasure::partition_ms},
    {"refine_ms", &StepMeasure::refine_ms},
    {"solve_ms", &StepMeasure::solve_ms},
    {"work_ms", &StepMeasure::work_ms},
    {"critical_path_ms", &StepMeasure::critical_path_ms},
    {"lambda_error", &StepMeasure::lambda_error}};

// "−46 %": the change ratio - 1 in whole percent, as the paper quotes it ("—" if not finite).
std::string percent_change(double ratio);

// CSV with a header line; numbers in round-trip form, so that a reader recomputes the table's
// means and ratios from steps.csv exactly.
std::string steps_csv_header();
std::string steps_csv_rows(const SceneResult& scene);
// steps.csv read back (bench --resume), by column name. A header is readable if it holds the key
// columns, step, rows and every measured column; the estimates are not read but derived again when
// the rows are written, so a steps.csv written before they were added reads too. The first
// column missing from `header`, or "" if it is readable:
std::string missing_steps_csv_column(const std::vector<std::string>& header);
// A line of steps.csv split at its commas (its fields hold no commas or quotes).
std::vector<std::string> steps_csv_fields(const std::string& line);
// The measured columns of one line (`fields`, as many as `header`'s) under a readable header.
StepMeasure read_step_measure(const std::vector<std::string>& header, const std::vector<std::string>& fields);
std::string table1_csv(const std::vector<SceneResult>& scenes);
std::string scaling_csv(const std::vector<SceneResult>& scaling);
// `context` (machine, preset, protocol) is printed above the tables.
std::string table1_markdown(const std::vector<SceneResult>& scenes, const std::string& context);

}  // namespace rbpart
