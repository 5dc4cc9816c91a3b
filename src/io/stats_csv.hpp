#pragma once
// Per-step statistics as plain CSV (docs/design.md#contracts, docs/formats.md#stats-csv): one header
// line, then one line per step, readable by any CSV reader. The run's parameters go to a JSON
// sidecar beside it, `<path>.json`, with "incomplete" for a run stopped early; a CSV written
// through (standard output, a FIFO) has none. Both files appear only when finish() or
// finish_incomplete() succeeds.
#include "io/atomic_file.hpp"
#include "io/run_params.hpp"

#include <rbpart/world.hpp>

#include <array>
#include <optional>
#include <string>

namespace rbpart {

class StatsCsvWriter {
 public:
  // The columns, in file order; names follow the StepStats / StepProfile fields.
  static constexpr std::array<const char*, 28> kColumns = {
      "step", "bodies", "contacts", "rows", "islands", "parts", "interface_rows", "interface_bodies",
      "edge_cut", "collide_ms", "assemble_ms", "graph_ms", "partition_ms", "refine_ms", "solve_ms",
      "integrate_ms", "project_ms", "total_ms", "solver_iterations", "factorizations", "blcp_residual",
      "max_penetration", "kinetic_energy", "factor_ms", "work_ms", "critical_path_ms", "unsettled",
      "island_factorizations"};

  // A step's value of every column, in kColumns order (as numbers, before the file's formatting),
  // and what each column holds: counts, wall times (the "_ms" columns) or physical quantities.
  static std::array<double, kColumns.size()> values(const StepStats& stats);
  enum class ColumnKind { Count, Ms, Exact };
  static ColumnKind column_kind(std::size_t column);

  // The parameters' file beside a stats CSV: "run.csv" -> "run.csv.json".
  static std::string sidecar_path(const std::string& csv_path) { return csv_path + ".json"; }

  // Throws InputError if `path` or its sidecar cannot be created.
  StatsCsvWriter(const std::string& path, const ParamList& params);

  void write(const StepStats& stats);
  // Commits both files; without it (an exception, an abandoned run) nothing is left behind.
  void finish();
  // Commits the steps written so far, the sidecar saying "incomplete": <why>: a run stopped early
  // (Ctrl-C) keeps what it measured, and no reader takes it for a whole run.
  void finish_incomplete(const std::string& why);

 private:
  AtomicFile file_;
  std::optional<AtomicFile> sidecar_;  // for a CSV that is a regular file
  nlohmann::ordered_json params_;  // the sidecar's content, written when the run ends
  std::string line_;  // reused for every row
};

}  // namespace rbpart
