#include "study/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "io/text_format.hpp"
#include "partition/partition.hpp"

namespace rbpart {

namespace {

const char* solver_name(const StudyConfig& c) { return c.direct() ? "direct" : "substructured"; }

// scene, solver, partitioner, refine, nmax, threads: the key columns of every file.
std::string key_columns(const std::string& scene, const StudyConfig& c) {
  return scene + ',' + solver_name(c) + ',' + partitioner_name(c.partitioner) + ',' + refiner_name(c.refiner) + ',' +
         (c.direct() ? "" : std::to_string(c.nmax)) + ',' + std::to_string(c.threads);
}

// The key columns' names, and steps.csv's columns between them and the measured ones.
constexpr const char* kKeyColumns[] = {"scene", "solver", "partitioner", "refine", "nmax", "threads"};
constexpr const char* kStepColumns[] = {"step", "rows"};

std::string key_header() {
  std::string out;
  for (const char* name : kKeyColumns) out += (out.empty() ? "" : ",") + std::string(name);
  return out;
}

// `name`'s index in `header`; header.size() if it has none.
std::size_t column_of(const std::vector<std::string>& header, const std::string& name) {
  return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
}

// The estimates' column names: est4_ms, est8_ms, est16_ms (with `prefix`: mean_est4_ms, ...).
std::string estimate_columns(const char* prefix) {
  std::string out;
  for (const int cores : kEstimateCores) out += std::string(",") + prefix + "est" + std::to_string(cores) + "_ms";
  return out;
}

std::string summary_columns() {
  return key_header() +
         ",dynamic_bodies,simulated_steps,recorded_steps,mean_solve_ms,median_solve_ms,max_solve_ms,mean_partition_ms,"
         "mean_refine_ms,mean_work_ms,mean_critical_path_ms,mean_parts,mean_interface_rows,mean_interface_bodies,"
         "mean_edge_cut,mean_factorizations,unsettled,solve_vs_mindp,max_lambda_error" +
         estimate_columns("mean_") + ",est" + std::to_string(kEstimateCores[kEstimates - 1]) + "_speedup_vs_direct\n";
}

std::string summary_line(const SceneResult& scene, const ConfigSummary& s) {
  const bool direct = s.config.direct();
  std::string line = key_columns(scene.label, s.config);
  for (const int v : {scene.dynamic_bodies, scene.simulated_steps, static_cast<int>(scene.steps.size())})
    line += ',' + std::to_string(v);
  for (const double v : {s.mean_solve_ms, s.median_solve_ms, s.max_solve_ms, s.mean_partition_ms, s.mean_refine_ms})
    line += ',' + round_trip(v);
  for (const double v : {s.mean_work_ms, s.mean_critical_path_ms}) line += ',' + (direct ? std::string() : round_trip(v));
  for (const double v : {s.mean_parts, s.mean_interface_rows, s.mean_interface_bodies, s.mean_edge_cut})
    line += ',' + round_trip(v);
  line += ',' + round_trip(s.mean_factorizations) + ',' + std::to_string(s.unsettled) + ',' + round_trip(s.solve_vs_mindp) + ',' + round_trip(s.max_lambda_error);
  for (const double v : s.mean_estimate_ms) line += ',' + (direct ? std::string() : round_trip(v));
  line += ',' + (direct ? std::string() : round_trip(s.direct_over_estimate));
  return line + '\n';
}

std::string format(const char* fmt, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, fmt, value);
  return buffer;
}

}  // namespace

std::string percent_change(double ratio) {
  if (!std::isfinite(ratio)) return "—";
  const long pct = std::lround(100 * (ratio - 1));
  if (pct == 0) return "±0 %";
  return (pct < 0 ? "−" : "+") + std::to_string(std::labs(pct)) + " %";
}

double estimated_ms(const StepMeasure& m, int cores) { return std::max(m.critical_path_ms, m.work_ms / cores); }

std::vector<ConfigSummary> summarize(const SceneResult& scene) {
  const std::size_t n = scene.steps.size();
  std::vector<ConfigSummary> out(scene.configs.size());
  for (std::size_t c = 0; c < scene.configs.size(); ++c) {
    ConfigSummary& s = out[c];
    s.config = scene.configs[c];
    std::vector<double> solve;
    for (const StepMeasure& m : scene.replay.measures[c]) {
      solve.push_back(m.solve_ms);
      s.mean_solve_ms += m.solve_ms;
      s.max_solve_ms = std::max(s.max_solve_ms, m.solve_ms);
      s.mean_partition_ms += m.partition_ms;
      s.mean_refine_ms += m.refine_ms;
      s.mean_work_ms += m.work_ms;
      s.mean_critical_path_ms += m.critical_path_ms;
      s.mean_parts += m.parts;
      s.mean_interface_rows += m.interface_rows;
      s.mean_interface_bodies += m.interface_bodies;
      s.mean_edge_cut += m.edge_cut;
      s.mean_factorizations += m.factorizations;
      s.unsettled += m.unsettled;
      s.max_lambda_error = std::max(s.max_lambda_error, m.lambda_error);
      if (!s.config.direct())
        for (std::size_t k = 0; k < kEstimates; ++k) s.mean_estimate_ms[k] += estimated_ms(m, kEstimateCores[k]);
    }
    for (double& v : s.mean_estimate_ms) v = n > 0 ? v / static_cast<double>(n) : 0.0;
    for (double* v : {&s.mean_solve_ms, &s.mean_partition_ms, &s.mean_refine_ms, &s.mean_work_ms, &s.mean_critical_path_ms,
                      &s.mean_parts, &s.mean_interface_rows, &s.mean_interface_bodies, &s.mean_edge_cut,
                      &s.mean_factorizations})
      *v = n > 0 ? *v / static_cast<double>(n) : 0.0;
    s.median_solve_ms = median(solve);
  }
  // The reference: MinDP unrefined, same threads and n_max (the first n_max for the baseline).
  for (ConfigSummary& s : out) {
    const ConfigSummary* ref = nullptr;
    for (const ConfigSummary& r : out) {
      const StudyConfig& c = r.config;
      if (c.partitioner != PartitionerKind::MinDp || c.refiner != RefinerKind::None || c.threads != s.config.threads)
        continue;
      if (s.config.direct() ? ref == nullptr : c.nmax == s.config.nmax) ref = &r;
    }
    s.solve_vs_mindp = ref && ref->mean_solve_ms > 0 ? s.mean_solve_ms / ref->mean_solve_ms : NAN;
  }
  // The speed-up of the estimate on the most cores: against the direct baseline of the same threads.
  for (ConfigSummary& s : out) {
    if (s.config.direct()) continue;
    const ConfigSummary* direct = nullptr;
    for (const ConfigSummary& r : out)
      if (r.config.direct() && r.config.threads == s.config.threads && !direct) direct = &r;
    const double estimate = s.mean_estimate_ms.back();
    s.direct_over_estimate = direct && estimate > 0 ? direct->mean_solve_ms / estimate : NAN;
  }
  return out;
}

std::string steps_csv_header() {
  std::string out = key_header();
  for (const char* name : kStepColumns) out += std::string(",") + name;
  for (const auto& [name, field] : kStepCounts) out += std::string(",") + name;
  for (const auto& [name, field] : kStepValues) out += std::string(",") + name;
  return out + estimate_columns("") + '\n';
}

std::string steps_csv_rows(const SceneResult& scene) {
  std::string out;
  for (std::size_t c = 0; c < scene.configs.size(); ++c) {
    const std::string key = key_columns(scene.label, scene.configs[c]);
    for (std::size_t s = 0; s < scene.steps.size(); ++s) {
      const StepMeasure& m = scene.replay.measures[c][s];
      out += key + ',' + std::to_string(scene.steps[s]) + ',' + std::to_string(scene.rows[s]);
      for (const auto& [name, field] : kStepCounts) out += ',' + std::to_string(m.*field);
      for (const auto& [name, field] : kStepValues) out += ',' + round_trip(m.*field);
      for (const int cores : kEstimateCores)
        out += ',' + (scene.configs[c].direct() ? std::string() : round_trip(estimated_ms(m, cores)));
      out += '\n';
    }
  }
  return out;
}

std::vector<std::string> steps_csv_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  for (std::size_t comma; (comma = line.find(',', start)) != std::string::npos; start = comma + 1)
    fields.push_back(line.substr(start, comma - start));
  fields.push_back(line.substr(start));
  return fields;
}

std::string missing_steps_csv_column(const std::vector<std::string>& header) {
  std::vector<std::string> needed(std::begin(kKeyColumns), std::end(kKeyColumns));
  needed.insert(needed.end(), std::begin(kStepColumns), std::end(kStepColumns));
  for (const auto& [name, field] : kStepCounts) needed.emplace_back(name);
  for (const auto& [name, field] : kStepValues) needed.emplace_back(name);
  for (const std::string& name : needed)
    if (column_of(header, name) == header.size()) return name;
  return "";
}

StepMeasure read_step_measure(const std::vector<std::string>& header, const std::vector<std::string>& fields) {
  StepMeasure m;
  for (const auto& [name, field] : kStepCounts) m.*field = std::atoi(fields.at(column_of(header, name)).c_str());
  for (const auto& [name, field] : kStepValues)
    m.*field = std::strtod(fields.at(column_of(header, name)).c_str(), nullptr);
  return m;
}

std::string table1_csv(const std::vector<SceneResult>& scenes) {
  std::string out = summary_columns();
  for (const SceneResult& scene : scenes)
    for (const ConfigSummary& s : summarize(scene)) out += summary_line(scene, s);
  return out;
}

std::string scaling_csv(const std::vector<SceneResult>& scaling) {
  std::string out = "rocks," + summary_columns();
  for (const SceneResult& scene : scaling)
    for (const ConfigSummary& s : summarize(scene)) out += std::to_string(scene.rocks) + ',' + summary_line(scene, s);
  return out;
}

std::string table1_markdown(const std::vector<SceneResult>& scenes, const std::string& context) {
  std::string out = "# Table 1: substructured solve time per partitioner and refinement\n\n" + context + "\n";
  for (const SceneResult& scene : scenes) {
    const std::vector<ConfigSummary> summary = summarize(scene);
    // n_max and threads get columns only when the study varies them.
    bool many_nmax = false, many_threads = false;
    for (const ConfigSummary& s : summary) {
      many_nmax |= !s.config.direct() && s.config.nmax != summary.back().config.nmax;
      many_threads |= s.config.threads != summary.front().config.threads;
    }
    out += "\n## " + scene.label + "\n\n" + std::to_string(scene.dynamic_bodies) + " dynamic bodies; " +
           std::to_string(scene.steps.size()) + " of " + std::to_string(scene.simulated_steps) +
           " steps replayed; n_max " + (many_nmax ? "varies" : std::to_string(summary.back().config.nmax)) +
           ", threads " + (many_threads ? "vary" : std::to_string(summary.front().config.threads)) + ".\n\n";
    out += "| solver | partitioner | refine |";
    if (many_nmax) out += " n_max |";
    if (many_threads) out += " threads |";
    out += " solve mean (ms) | solve median (ms) | solve max (ms) | critical path (ms) |";
    for (const int cores : kEstimateCores) out += " est. " + std::to_string(cores) + " cores (ms) |";
    out += " partition (ms) | refine (ms) | parts | interface rows | factorisations | unsettled | vs MinDP |"
           " speed-up, " + std::to_string(kEstimateCores[kEstimates - 1]) + " cores |\n|---|---|---|";
    if (many_nmax) out += "---:|";
    if (many_threads) out += "---:|";
    out += "---:|---:|---:|---:|";
    for (std::size_t k = 0; k < kEstimates; ++k) out += "---:|";
    out += "---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const ConfigSummary& s : summary) {
      const StudyConfig& c = s.config;
      out += std::string("| ") + (c.direct() ? "direct (monolithic)" : "substructured") + " | " +
             (c.direct() ? "—" : partitioner_name(c.partitioner)) + " | " +
             (c.direct() ? "—" : refiner_name(c.refiner)) + " |";
      if (many_nmax) out += " " + (c.direct() ? std::string("—") : std::to_string(c.nmax)) + " |";
      if (many_threads) out += " " + std::to_string(c.threads) + " |";
      out += " " + format("%.3f", s.mean_solve_ms) + " | " + format("%.3f", s.median_solve_ms) + " | " +
             format("%.3f", s.max_solve_ms) + " | " + (c.direct() ? "—" : format("%.3f", s.mean_critical_path_ms)) + " | ";
      for (const double v : s.mean_estimate_ms) out += (c.direct() ? "—" : format("%.3f", v)) + " | ";
      out += (c.direct() ? "—" : format("%.4f", s.mean_partition_ms)) + " | " +
             (c.direct() ? "—" : format("%.4f", s.mean_refine_ms)) + " | " + format("%.1f", s.mean_parts) + " | " +
             (c.direct() ? "—" : format("%.1f", s.mean_interface_rows)) + " | " +
             format("%.2f", s.mean_factorizations) + " | " + std::to_string(s.unsettled) +
             " | " + percent_change(s.solve_vs_mindp) + " | " +
             (c.direct() || !std::isfinite(s.direct_over_estimate) ? "—" : format("%.2f×", s.direct_over_estimate)) +
             " |\n";
    }
  }
  return out;
}

}  // namespace rbpart
