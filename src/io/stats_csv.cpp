#include "io/stats_csv.hpp"

#include "io/text_format.hpp"

#include <charconv>

namespace rbpart {

namespace {

void append_int(std::string& line, int value) {
  char buffer[16];
  line.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, value).ptr);
  line += ',';
}

// Wall times: six significant digits resolve far below a timer's noise.
void append_ms(std::string& line, double value) {
  char buffer[32];
  line.append(buffer,
              std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 6).ptr);
  line += ',';
}

// Physical quantities: exact, so that two runs' statistics can be compared bit for bit.
void append_exact(std::string& line, double value) {
  line += round_trip(value);
  line += ',';
}

}  // namespace

StatsCsvWriter::StatsCsvWriter(const std::string& path, const ParamList& params)
    : file_(path), params_(params_json(params)) {
  if (classify_output(path).kind == OutputTarget::Replace) sidecar_.emplace(sidecar_path(path));
  std::string header;
  for (std::size_t i = 0; i < kColumns.size(); ++i) {
    header += kColumns[i];
    header += i + 1 < kColumns.size() ? ',' : '\n';
  }
  file_.write(header);
}

void StatsCsvWriter::write(const StepStats& s) {
  line_.clear();
  append_int(line_, s.step);
  append_int(line_, s.bodies);
  append_int(line_, s.contacts);
  append_int(line_, s.rows);
  append_int(line_, s.islands);
  append_int(line_, s.parts);
  append_int(line_, s.interface_rows);
  append_int(line_, s.interface_bodies);
  append_int(line_, s.edge_cut);
  append_ms(line_, s.profile.collide_ms);
  append_ms(line_, s.profile.assemble_ms);
  append_ms(line_, s.profile.graph_ms);
  append_ms(line_, s.profile.partition_ms);
  append_ms(line_, s.profile.refine_ms);
  append_ms(line_, s.profile.solve_ms);
  append_ms(line_, s.profile.integrate_ms);
  append_ms(line_, s.profile.total_ms);
  append_int(line_, s.solver_iterations);
  append_int(line_, s.friction_passes);
  append_int(line_, s.factorizations);
  append_int(line_, s.fallbacks);
  append_exact(line_, s.residual);
  append_exact(line_, s.max_penetration);
  append_exact(line_, s.kinetic_energy);
  append_int(line_, s.loop_iterations);
  for (double ms : {s.factor_ms, s.schur_ms, s.interface_ms, s.subsystem_ms, s.work_ms, s.critical_path_ms})
    append_ms(line_, ms);
  append_int(line_, s.unsettled);
  line_.back() = '\n';
  file_.write(line_);
}

void StatsCsvWriter::finish() {
  file_.commit();
  if (sidecar_) {
    sidecar_->write(pretty_json(params_));
    sidecar_->commit();
  }
}

void StatsCsvWriter::finish_incomplete(const std::string& why) {
  params_["incomplete"] = why;
  finish();
}

}  // namespace rbpart
