#include "io/stats_csv.hpp"

#include "io/text_format.hpp"

#include <charconv>
#include <string_view>

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

std::array<double, StatsCsvWriter::kColumns.size()> StatsCsvWriter::values(const StepStats& s) {
  const PartitionStats& q = s.partition;
  const StepProfile& p = s.profile;
  const SolveStats& v = s.solve;
  return {double(s.step), double(s.bodies), double(s.contacts), double(s.rows), double(s.islands), double(q.parts),
          double(q.interface_rows), double(q.interface_bodies), double(q.edge_cut), p.collide_ms, p.assemble_ms,
          p.graph_ms, p.partition_ms, p.refine_ms, p.solve_ms, p.integrate_ms, p.project_ms, p.total_ms,
          double(v.iterations), double(v.factorizations), v.residual, s.max_penetration, s.kinetic_energy,
          v.factor_ms, v.work_ms, v.critical_path_ms, double(v.unsettled), double(v.island_factorizations)};
}

StatsCsvWriter::ColumnKind StatsCsvWriter::column_kind(std::size_t column) {
  const std::string_view name = kColumns[column];
  if (name.size() > 3 && name.substr(name.size() - 3) == "_ms") return ColumnKind::Ms;
  if (name == "blcp_residual" || name == "max_penetration" || name == "kinetic_energy") return ColumnKind::Exact;
  return ColumnKind::Count;
}

void StatsCsvWriter::write(const StepStats& s) {
  line_.clear();
  const auto v = values(s);
  for (std::size_t i = 0; i < v.size(); ++i) {
    switch (column_kind(i)) {
      case ColumnKind::Count: append_int(line_, static_cast<int>(v[i])); break;
      case ColumnKind::Ms: append_ms(line_, v[i]); break;
      case ColumnKind::Exact: append_exact(line_, v[i]); break;
    }
  }
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
