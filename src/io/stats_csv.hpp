#pragma once
// Per-step statistics as CSV (docs/design.md#contracts): the run's parameters as "# key=value" comment lines,
// the column header, then one line per step. The file appears only when finish() succeeds.
#include "io/atomic_file.hpp"
#include "io/run_params.hpp"

#include <rbpart/world.hpp>

#include <array>
#include <string>

namespace rbpart {

class StatsCsvWriter {
 public:
  // The columns, in file order; names follow the StepStats / StepProfile fields.
  static constexpr std::array<const char*, 32> kColumns = {
      "step", "bodies", "contacts", "rows", "islands", "parts", "interface_rows", "interface_bodies",
      "edge_cut", "collide_ms", "assemble_ms", "graph_ms", "partition_ms", "refine_ms", "solve_ms",
      "integrate_ms", "total_ms", "solver_iterations", "friction_passes", "factorizations", "fallback",
      "blcp_residual", "max_penetration", "kinetic_energy", "loop_iterations", "factor_ms", "schur_ms",
      "interface_ms", "subsystem_ms", "work_ms", "critical_path_ms", "unsettled"};

  // Throws InputError if `path` cannot be created. Control characters in parameter keys or values
  // become spaces, so that every parameter stays on its one comment line.
  StatsCsvWriter(const std::string& path, const ParamList& params);

  void write(const StepStats& stats);
  // Commits the file; without it (an exception, an abandoned run) nothing is left behind.
  void finish();

 private:
  AtomicFile file_;
  std::string line_;  // reused for every row
};

}  // namespace rbpart
