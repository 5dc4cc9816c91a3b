#include "study/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

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

const char* kSummaryColumns =
    "scene,solver,partitioner,refine,nmax,threads,dynamic_bodies,simulated_steps,recorded_steps,mean_solve_ms,"
    "median_solve_ms,max_solve_ms,mean_partition_ms,mean_refine_ms,mean_work_ms,mean_critical_path_ms,mean_parts,mean_interface_rows,"
    "mean_interface_bodies,mean_edge_cut,mean_factorizations,unsettled,solve_vs_mindp,max_lambda_error\n";

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
  return line + '\n';
}

std::string format(const char* fmt, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, fmt, value);
  return buffer;
}

// "−46 %": the change of the mean solve time against MinDP unrefined, as the paper quotes it.
std::string percent_change(double ratio) {
  if (!std::isfinite(ratio)) return "—";
  const long pct = std::lround(100 * (ratio - 1));
  if (pct == 0) return "±0 %";
  return (pct < 0 ? "−" : "+") + std::to_string(std::labs(pct)) + " %";
}

}  // namespace

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
    }
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
  return out;
}

std::string steps_csv_header() {
  return "scene,solver,partitioner,refine,nmax,threads,step,rows,parts,interface_rows,interface_bodies,edge_cut,"
         "factorizations,unsettled,partition_ms,refine_ms,solve_ms,work_ms,critical_path_ms,lambda_error\n";
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
      out += '\n';
    }
  }
  return out;
}

std::string table1_csv(const std::vector<SceneResult>& scenes) {
  std::string out = kSummaryColumns;
  for (const SceneResult& scene : scenes)
    for (const ConfigSummary& s : summarize(scene)) out += summary_line(scene, s);
  return out;
}

std::string scaling_csv(const std::vector<SceneResult>& scaling) {
  std::string out = std::string("rocks,") + kSummaryColumns;
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
    out += " solve mean (ms) | solve median (ms) | solve max (ms) | critical path (ms) | partition (ms) |"
           " refine (ms) | parts | interface rows | factorisations | unsettled | vs MinDP |\n|---|---|---|";
    if (many_nmax) out += "---:|";
    if (many_threads) out += "---:|";
    out += "---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const ConfigSummary& s : summary) {
      const StudyConfig& c = s.config;
      out += std::string("| ") + (c.direct() ? "direct (monolithic)" : "substructured") + " | " +
             (c.direct() ? "—" : partitioner_name(c.partitioner)) + " | " +
             (c.direct() ? "—" : refiner_name(c.refiner)) + " |";
      if (many_nmax) out += " " + (c.direct() ? std::string("—") : std::to_string(c.nmax)) + " |";
      if (many_threads) out += " " + std::to_string(c.threads) + " |";
      out += " " + format("%.3f", s.mean_solve_ms) + " | " + format("%.3f", s.median_solve_ms) + " | " +
             format("%.3f", s.max_solve_ms) + " | " + (c.direct() ? "—" : format("%.3f", s.mean_critical_path_ms)) + " | " +
             (c.direct() ? "—" : format("%.4f", s.mean_partition_ms)) + " | " +
             (c.direct() ? "—" : format("%.4f", s.mean_refine_ms)) + " | " + format("%.1f", s.mean_parts) + " | " +
             (c.direct() ? "—" : format("%.1f", s.mean_interface_rows)) + " | " +
             format("%.2f", s.mean_factorizations) + " | " + std::to_string(s.unsettled) +
             " | " + percent_change(s.solve_vs_mindp) + " |\n";
    }
  }
  return out;
}

}  // namespace rbpart
