#include "study/study.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "core/timer.hpp"
#include "io/atomic_file.hpp"
#include "io/run_params.hpp"
#include "io/scene_json.hpp"
#include "io/text_format.hpp"
#include "partition/partition.hpp"
#include "scenes/scenes.hpp"
#include "study/capture.hpp"
#include "study/claims.hpp"
#include "study/machine.hpp"
#include "study/report.hpp"

namespace rbpart {

namespace {

const SceneInfo* builtin(const std::string& name) {
  for (const SceneInfo& info : builtin_scenes())
    if (info.name == name) return &info;
  return nullptr;
}

// Two entries with equal keys are the same simulation: a built-in scene with every parameter's
// effective value, or a file. The scaling study reuses a Table 1 scene of equal key.
std::string scene_key(const StudyScene& s) {
  const SceneInfo* info = builtin(s.source);
  if (!info) return "file:" + s.source;
  std::map<std::string, std::string> values;
  for (const SceneParameter& p : info->parameters) values[p.name] = round_trip(p.value);
  for (const auto& [key, text] : s.overrides) values[key] = round_trip(std::strtod(text.c_str(), nullptr));
  std::string out = s.source;
  for (const auto& [key, value] : values) out += ';' + key + '=' + value;
  return out;
}

StudyScene scaling_scene(const StudySpec& spec, int rocks) {
  std::string text = "rock_pile:rocks=" + std::to_string(rocks);
  for (const auto& [key, value] : spec.scaling_overrides) text += ':' + key + '=' + value;
  StudyScene scene = parse_study_scene(text);
  scene.rocks = rocks;
  return scene;
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buffer;
}

// The protocol of a study (machine.json "study"): what was measured and how.
nlohmann::ordered_json study_json(const StudySpec& spec) {
  nlohmann::ordered_json study;
  nlohmann::ordered_json labels = nlohmann::ordered_json::array();
  for (const StudyScene& s : spec.scenes) labels.push_back(s.label);
  study["scenes"] = labels;
  study["scaling_rocks"] = spec.scaling_rocks;
  study["steps"] = spec.steps > 0 ? nlohmann::ordered_json(spec.steps) : nlohmann::ordered_json("scene default");
  study["every"] = spec.every;
  study["repeats"] = spec.repeats;
  study["mindp_reference"] = spec.mindp_reference;
  nlohmann::ordered_json partitioners = nlohmann::ordered_json::array(), refiners = nlohmann::ordered_json::array();
  for (const PartitionerKind p : spec.partitioners) partitioners.push_back(partitioner_name(p));
  for (const RefinerKind r : spec.refiners) refiners.push_back(refiner_name(r));
  study["partitioners"] = partitioners;
  study["refiners"] = refiners;
  study["nmax"] = spec.nmax;
  study["threads"] = spec.threads;
  return study;
}

// The simulation and solver parameters of a study (machine.json "parameters").
nlohmann::ordered_json parameters_json(const StudySpec& spec) {
  nlohmann::ordered_json params;
  for (const auto& [key, value] : run_parameters(spec.step_params, spec.solver_params))
    if (key != "solver" && key != "threads") params[key] = value;
  params["tau_mr"] = round_trip(spec.partition_params.tau_mr);
  params["tau_mix"] = round_trip(spec.partition_params.tau_mix);
  return params;
}

// The scenes an earlier run of this study finished in `dir` (machine.json lists them; steps.csv
// holds every configuration's per-step medians, in round-trip form), keyed by label. Nothing if
// `dir` holds no study. InputError if it holds a study with another protocol (any field of
// machine.json's "study" but its scene lists, or a parameter), whose scenes would not compare.
std::map<std::string, SceneResult> finished_scenes(const StudySpec& spec, const std::vector<StudyConfig>& configs,
                                                const std::filesystem::path& dir, std::string& started) {
  std::map<std::string, SceneResult> out;
  std::ifstream machine_file(dir / "machine.json");
  if (!machine_file) return out;
  const std::string where = "--resume: " + (dir / "machine.json").string();
  nlohmann::ordered_json machine;
  try {
    machine = nlohmann::ordered_json::parse(machine_file);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where + ": not a study's machine.json (" + e.what() + ")");
  }
  const nlohmann::ordered_json now = study_json(spec), params = parameters_json(spec);
  const nlohmann::ordered_json* was = machine.contains("study") ? &machine["study"] : nullptr;
  for (const auto& [key, value] : now.items()) {
    if (key == "scenes" || key == "scaling_rocks") continue;
    if (!was || !was->contains(key) || (*was)[key] != value)
      throw InputError(where + " is a study with another " + key + " (" +
                       (was && was->contains(key) ? (*was)[key].dump() : "none") + "; this run: " + value.dump() + ")");
  }
  if (!machine.contains("parameters") || machine["parameters"] != params)
    throw InputError(where + " is a study with other simulation or solver parameters");
  if (machine.contains("started") && machine["started"].is_string()) started = machine["started"];

  // steps.csv rows by scene label, in file order; columns by name.
  std::string line;
  std::ifstream steps_file(dir / "steps.csv");
  std::getline(steps_file, line);
  const std::vector<std::string> header = steps_csv_fields(line);
  if (const std::string missing = missing_steps_csv_column(header); !missing.empty())
    throw InputError("--resume: " + (dir / "steps.csv").string() + ": not a study's steps.csv (no column " +
                     missing + ")");
  std::map<std::string, std::vector<std::vector<std::string>>> rows;
  while (std::getline(steps_file, line)) {
    std::vector<std::string> fields = steps_csv_fields(line);
    if (fields.size() == header.size()) rows[fields[0]].push_back(std::move(fields));
  }
  const auto column = [&header](const char* name) {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const std::size_t solver = column("solver"), partitioner = column("partitioner"), refine = column("refine"),
                    nmax = column("nmax"), threads = column("threads");
  const auto integer = [&](const std::vector<std::string>& v, const char* name) {
    return std::atoi(v[column(name)].c_str());
  };
  try {
    for (const nlohmann::ordered_json& entry : machine.value("scenes", nlohmann::ordered_json::array())) {
      const std::string label = entry.value("label", "");
      const auto found = rows.find(label);
      if (found == rows.end() || found->second.size() % configs.size() != 0) continue;
      const std::size_t steps = found->second.size() / configs.size();
      SceneResult r;
      r.label = label;
      r.configs = configs;
      r.dynamic_bodies = entry.value("dynamic_bodies", 0);
      r.simulated_steps = entry.value("simulated_steps", 0);
      r.capture_ms = 1000 * entry.value("capture_s", 0.0);
      r.replay_ms = 1000 * entry.value("replay_s", 0.0);
      r.git_revision = entry.value("git_revision", "unknown");
      r.replay.direct_mismatches = entry.value("direct_mismatches", 0);
      r.replay.measures.assign(configs.size(), {});
      bool complete = true;
      for (std::size_t c = 0; c < configs.size() && complete; ++c) {
        const StudyConfig& config = configs[c];
        for (std::size_t k = 0; k < steps && complete; ++k) {
          const std::vector<std::string>& v = found->second[c * steps + k];
          complete = v[solver] == (config.direct() ? "direct" : "substructured") &&
                     v[partitioner] == partitioner_name(config.partitioner) &&
                     v[refine] == refiner_name(config.refiner) &&
                     v[nmax] == (config.direct() ? "" : std::to_string(config.nmax)) &&
                     v[threads] == std::to_string(config.threads);
          if (c == 0) {
            r.steps.push_back(integer(v, "step"));
            r.rows.push_back(integer(v, "rows"));
          }
          complete = complete && r.steps[k] == integer(v, "step");
          r.replay.measures[c].push_back(read_step_measure(header, v));
        }
      }
      if (complete) out.emplace(label, std::move(r));  // else not this study's configurations: measured again
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where + ": " + e.what());
  }
  return out;
}

struct Run {
  StudyScene scene;
  std::vector<int> scaling_rocks;  // scaling points this run also provides (a reused Table 1 scene)
  bool table1 = false;
};

class StudyWriter {
 public:
  StudyWriter(const StudySpec& spec, std::string dir, const std::vector<StudyConfig>& configs, MachineInfo machine,
              std::string started)
      : spec_(spec), dir_(std::move(dir)), machine_(std::move(machine)), started_(std::move(started)) {
    for (const StudyConfig& c : configs)
      if (std::find(threads_.begin(), threads_.end(), c.threads) == threads_.end()) threads_.push_back(c.threads);
  }

  void add(const SceneResult& result, const Run& run) {
    if (run.table1) table1_.push_back(result);
    for (const int rocks : run.scaling_rocks) {
      scaling_.push_back(result);
      scaling_.back().rocks = rocks;
    }
    std::stable_sort(scaling_.begin(), scaling_.end(),
                     [](const SceneResult& a, const SceneResult& b) { return a.rocks < b.rocks; });
    steps_ += steps_csv_rows(result);
    nlohmann::ordered_json scene;
    scene["label"] = result.label;
    scene["dynamic_bodies"] = result.dynamic_bodies;
    scene["simulated_steps"] = result.simulated_steps;
    scene["recorded_steps"] = result.steps.size();
    scene["capture_s"] = std::round(result.capture_ms) / 1000;
    scene["replay_s"] = std::round(result.replay_ms) / 1000;
    scene["git_revision"] = result.git_revision;
    scene["direct_mismatches"] = result.replay.direct_mismatches;
    scenes_.push_back(scene);
    revisions_.insert(result.git_revision);
    for (const StudyConfig& c : result.configs) direct_replays_ += c.direct() ? static_cast<int>(result.steps.size()) : 0;
    direct_mismatches_ += result.replay.direct_mismatches;
  }

  int direct_mismatches() const { return direct_mismatches_; }
  // This binary's revision, as a scene measured now records it.
  std::string revision() const { return machine_.git_revision + (machine_.git_dirty ? " (modified)" : ""); }

  // Every output, each atomically: the whole study so far.
  void write(bool complete) const {
    write_file_atomically(path("machine.json"), pretty_json(machine_json(complete)));
    write_file_atomically(path("table1.csv"), table1_csv(table1_));
    write_file_atomically(path("table1.md"), table1_markdown(table1_, context()));
    write_file_atomically(path("steps.csv"), steps_);
    write_file_atomically(path("scaling.csv"), scaling_csv(scaling_));
    write_file_atomically(path("claims.md"), claims_markdown(check_claims(table1_, scaling_), claims_context()));
  }

 private:
  std::string path(const char* name) const { return (std::filesystem::path(dir_) / name).string(); }

  // The machine, the build and the revisions the scenes were measured at.
  std::string machine_context() const {
    std::string threads;
    for (const int t : threads_) threads += (threads.empty() ? "" : ", ") + std::to_string(t);
    return "Preset `" + spec_.preset + "` on " + machine_.cpu + " (" + std::to_string(machine_.logical_cpus) +
           " hardware threads), " + machine_.compiler + ", " + machine_.build_type + ", git " + revision() +
           (revisions_.size() > 1 || (revisions_.size() == 1 && *revisions_.begin() != revision())
                ? " (scenes resumed from other revisions: machine.json gives each scene's)"
                : "") +
           ". Solver threads: " + threads + ".";
  }

  std::string context() const {
    const std::string most = std::to_string(kEstimateCores[kEstimates - 1]);
    return machine_context() +
           "\n\nEvery configuration solved the same recorded step problems (the direct solver's "
           "trajectory); times are the mean over the recorded steps of each step's median over " +
           std::to_string(spec_.repeats) + (spec_.repeats == 1 ? " run" : " runs") +
           ". *vs MinDP*: change of the mean solve time against MinDP without refinement, same steps and "
           "repeats. Parts count sub-systems with at least one row (islands for the direct solver). "
           "*est. c cores*: the mean over the steps of max(critical path, work / c), a lower bound of the "
           "substructured solve on c cores; *speed-up, " + most + " cores*: the direct solve's mean time "
           "(measured, same threads) over the " + most + "-core estimate.\n";
  }

  std::string claims_context() const {
    return machine_context() +
           "\n\nEach claim is judged on the mean solve times (as the paper quotes them) of the scenes of "
           "its kind in this run, at " + std::to_string(spec_.threads.front()) + " solver thread" +
           (spec_.threads.front() == 1 ? "" : "s") + " and n_max " + std::to_string(spec_.nmax.front()) +
           ", by the rules of docs/study.md (\"The paper's claims\"): a relative change is *reproduced* "
           "with the paper's sign and within a factor of " + round_trip(kClaimFactor) + " of its size, "
           "*contradicted* with the opposite sign, and changes under " +
           std::to_string(std::lround(100 * kClaimNoise)) +
           " % count as none; a claimed winner is *contradicted* when another configuration is more than " +
           std::to_string(std::lround(100 * kClaimMargin)) + " % faster. A scene of another size than the paper's (the "
           "`quick` preset's) still counts: its body count is given.\n";
  }

  nlohmann::ordered_json machine_json(bool complete) const {
    nlohmann::ordered_json j;
    j["preset"] = spec_.preset;
    j["complete"] = complete;
    j["started"] = started_;
    j["written"] = utc_now();
    j["cpu"] = machine_.cpu;
    j["logical_cpus"] = machine_.logical_cpus;
    j["physical_cores"] = machine_.physical_cores;
    j["threads"] = threads_;
    j["hostname"] = machine_.hostname;
    j["compiler"] = machine_.compiler;
    j["build_type"] = machine_.build_type;
    j["git_revision"] = machine_.git_revision;
    j["git_dirty"] = machine_.git_dirty;
    j["study"] = study_json(spec_);
    j["parameters"] = parameters_json(spec_);
    j["replay_check"] = {{"direct_replays", direct_replays_},
                         {"bit_identical_to_live_run", direct_replays_ - direct_mismatches_}};
    j["scenes"] = scenes_;
    return j;
  }

  const StudySpec& spec_;
  std::string dir_;
  MachineInfo machine_;
  std::set<std::string> revisions_;  // of the scenes added
  std::string started_;
  std::vector<int> threads_;
  std::vector<SceneResult> table1_, scaling_;
  std::string steps_ = steps_csv_header();
  std::vector<nlohmann::ordered_json> scenes_;
  int direct_replays_ = 0, direct_mismatches_ = 0;
};

void log_scene(std::FILE* log, const SceneResult& r, std::size_t repeats) {
  if (!log) return;
  const std::vector<ConfigSummary> summary = summarize(r);
  const ConfigSummary* best = nullptr;
  const ConfigSummary* direct = nullptr;
  for (const ConfigSummary& s : summary) {
    if (s.config.direct()) {
      if (!direct) direct = &s;
    } else if (!best || s.mean_solve_ms < best->mean_solve_ms) {
      best = &s;
    }
  }
  std::fprintf(log, "bench: %s: %d bodies, %zu of %d steps replayed, %zu configurations x %zu repeats (capture %.1f s, replay %.1f s)",
               r.label.c_str(), r.dynamic_bodies, r.steps.size(), r.simulated_steps, r.configs.size(), repeats,
               r.capture_ms / 1000, r.replay_ms / 1000);
  if (best && direct)
    std::fprintf(log, "; fastest %s+%s %.3f ms (%+.0f %% vs MinDP), direct %.3f ms", partitioner_name(best->config.partitioner),
                 refiner_name(best->config.refiner), best->mean_solve_ms, 100 * (best->solve_vs_mindp - 1),
                 direct->mean_solve_ms);
  std::fprintf(log, "\n");
  std::fflush(log);
}

}  // namespace

StudyScene parse_study_scene(const std::string& text) {
  if (text.empty()) throw InputError("--scenes: empty scene name");
  StudyScene scene;
  scene.label = text;
  if (!builtin(text) && std::filesystem::is_regular_file(text)) {
    scene.source = text;
    return scene;
  }
  std::size_t start = 0, colon = text.find(':');
  scene.source = text.substr(0, colon);
  while (colon != std::string::npos) {
    start = colon + 1;
    colon = text.find(':', start);
    const std::string item = text.substr(start, colon == std::string::npos ? std::string::npos : colon - start);
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError("scene '" + text + "': expected name:key=value[:key=value...], got '" + item + "'");
    scene.overrides.emplace_back(item.substr(0, eq), item.substr(eq + 1));
  }
  return scene;
}

SceneDef make_study_scene(const StudyScene& scene) {
  if (builtin(scene.source)) return make_builtin_scene(scene.source, scene.overrides);
  if (!scene.overrides.empty() || !std::ifstream(scene.source))
    throw InputError("scene '" + scene.label + "': neither a built-in scene (rbpart scenes) nor a readable file");
  return load_scene_file(scene.source);
}

StudySpec study_preset(const std::string& name) {
  StudySpec spec;
  spec.preset = name;
  spec.partitioners = {PartitionerKind::Bfs, PartitionerKind::MinDp, PartitionerKind::MaxDp, PartitionerKind::Mr,
                       PartitionerKind::Mix, PartitionerKind::Metis};
  spec.refiners = {RefinerKind::None, RefinerKind::Kl, RefinerKind::Fm};
  spec.nmax = {kStudyNmax};
  spec.threads = {std::max(1, static_cast<int>(std::thread::hardware_concurrency()))};
  spec.repeats = 3;
  if (name == "paper") {
    for (const char* s : {"chain_drop", "log_tower", "rock_pile", "large_rock_pile"})
      spec.scenes.push_back(parse_study_scene(s));
    spec.scaling_rocks = {50, 100, 200, 400, 800};
  } else if (name == "quick") {
    // Small versions of the four scenes over 40 steps (the chain released just above its bar, the
    // piles in four layers, so that contacts form at once), every other step replayed. Their
    // islands hold tens of bodies, so n_max is smaller than the paper's for every configuration to
    // partition, refine and couple sub-systems.
    for (const char* s : {"chain_drop:links=30:height=1.15:bar_height=1", "log_tower:layers=8",
                          "rock_pile:rocks=60:layers=4", "large_rock_pile:rocks=90:layers=4"})
      spec.scenes.push_back(parse_study_scene(s));
    spec.scaling_rocks = {30, 60, 120};
    spec.scaling_overrides = {{"layers", "4"}};
    spec.steps = 40;
    spec.every = 2;
    spec.nmax = {kQuickNmax};
  } else {
    throw InputError("unknown preset '" + name + "' (choose paper or quick)");
  }
  return spec;
}

void validate_study(const StudySpec& spec) {
  if (spec.scenes.empty() && spec.scaling_rocks.empty()) throw InputError("--scenes: no scene to study");
  if (spec.partitioners.empty()) throw InputError("--partitioners: empty list");
  for (const PartitionerKind p : spec.partitioners)
    if (p == PartitionerKind::None)
      throw InputError("--partitioners: 'none' is not a partitioner (the direct baseline is always measured)");
  if (spec.refiners.empty()) throw InputError("--refine: empty list");
  if (spec.nmax.empty()) throw InputError("--nmax: empty list");
  for (const int n : spec.nmax)
    if (n < 1) throw InputError("--nmax: must be at least 1 (got " + std::to_string(n) + ")");
  if (spec.threads.empty()) throw InputError("--threads: empty list");
  for (const int t : spec.threads)
    if (t < 1) throw InputError("--threads: must be at least 1 (got " + std::to_string(t) + ")");
  if (spec.repeats < 1) throw InputError("--repeats: must be at least 1 (got " + std::to_string(spec.repeats) + ")");
  if (spec.every < 1) throw InputError("--every: must be at least 1 (got " + std::to_string(spec.every) + ")");
  if (spec.steps < 0) throw InputError("--steps: must be positive (got " + std::to_string(spec.steps) + ")");
  if (spec.steps > 0 && spec.steps < spec.every)
    throw InputError("--steps " + std::to_string(spec.steps) + " records no step with --every " +
                     std::to_string(spec.every));
  for (const int rocks : spec.scaling_rocks)
    if (rocks < 1) throw InputError("--scaling: rock counts must be at least 1 (got " + std::to_string(rocks) + ")");
  for (std::size_t i = 0; i < spec.scenes.size(); ++i) {
    // Labels are CSV fields and Markdown headings.
    if (spec.scenes[i].label.find_first_of(",\"\n") != std::string::npos)
      throw InputError("--scenes: '" + spec.scenes[i].label + "' contains a comma, quote or newline");
    for (std::size_t k = 0; k < i; ++k)
      if (spec.scenes[i].label == spec.scenes[k].label)
        throw InputError("--scenes: '" + spec.scenes[i].label + "' is listed twice");
  }
}

std::vector<StudyConfig> study_configs(const StudySpec& spec) {
  std::vector<StudyConfig> configs;
  const auto add = [&configs](const StudyConfig& c) {
    for (const StudyConfig& e : configs)
      if (e.partitioner == c.partitioner && e.refiner == c.refiner && e.nmax == c.nmax && e.threads == c.threads)
        return;
    configs.push_back(c);
  };
  const auto listed = [&spec](PartitionerKind p) {
    return std::find(spec.partitioners.begin(), spec.partitioners.end(), p) != spec.partitioners.end();
  };
  const bool mindp_none = listed(PartitionerKind::MinDp) &&
                          std::find(spec.refiners.begin(), spec.refiners.end(), RefinerKind::None) != spec.refiners.end();
  for (const int threads : spec.threads) {
    add({PartitionerKind::None, RefinerKind::None, 0, threads});
    for (const int nmax : spec.nmax) {
      if (spec.mindp_reference && !mindp_none) add({PartitionerKind::MinDp, RefinerKind::None, nmax, threads});
      for (const PartitionerKind p : spec.partitioners) {
        if (p == PartitionerKind::Metis) continue;
        for (const RefinerKind r : spec.refiners) add({p, r, nmax, threads});
      }
      if (listed(PartitionerKind::Metis)) add({PartitionerKind::Metis, RefinerKind::None, nmax, threads});
    }
  }
  return configs;
}

void run_study(const StudySpec& spec, const std::string& out_dir, std::FILE* log, bool resume) {
  validate_study(spec);
  // Every scene is built once here, so that a bad name or parameter fails before hours of work.
  std::vector<Run> runs;
  for (const StudyScene& s : spec.scenes) {
    make_study_scene(s);
    runs.push_back({s, {}, true});
  }
  for (const int rocks : spec.scaling_rocks) {
    const StudyScene s = scaling_scene(spec, rocks);
    make_study_scene(s);
    const auto same = std::find_if(runs.begin(), runs.end(), [&](const Run& r) { return scene_key(r.scene) == scene_key(s); });
    if (same != runs.end()) same->scaling_rocks.push_back(rocks);
    else runs.push_back({s, {rocks}, false});
  }

  // Before the directory is touched: in a checkout, removing the old figures below would make the
  // tree look modified.
  MachineInfo machine = machine_info();
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw InputError("--out '" + out_dir + "': " + ec.message());
  const std::vector<StudyConfig> configs = study_configs(spec);
  std::string started = utc_now();
  std::map<std::string, SceneResult> finished;
  if (resume) finished = finished_scenes(spec, configs, out_dir, started);
  // Figures of an earlier study in this directory would not match the new tables.
  for (const char* figure :
       {"fig3.png", "fig3.svg", "fig4.png", "fig4.svg", "fig5.png", "fig5.svg", "estimates.png", "estimates.svg"})
    std::filesystem::remove(std::filesystem::path(out_dir) / figure, ec);
  StudyWriter writer(spec, out_dir, configs, std::move(machine), started);
  writer.write(false);  // fails now, not after the run, if the directory cannot be written

  for (const Run& run : runs) {
    if (const auto done = finished.find(run.scene.label); done != finished.end()) {
      writer.add(done->second, run);
      writer.write(false);
      if (log)
        std::fprintf(log, "bench: %s: resumed (measured at %s)\n", run.scene.label.c_str(),
                     done->second.git_revision.c_str());
      continue;
    }
    const SceneDef scene = make_study_scene(run.scene);
    const int steps = spec.steps > 0 ? spec.steps : scene.steps;
    SceneResult result;
    result.label = run.scene.label;
    result.configs = configs;
    result.git_revision = writer.revision();
    {
      Trajectory trajectory;
      {
        Progress progress(run.scene.label + ": capture", steps);
        trajectory = capture_trajectory(scene, steps, spec.every, spec.step_params, spec.solver_params,
                                        [&progress](int done) { progress.update(done); });
      }
      result.dynamic_bodies = trajectory.dynamic_bodies;
      result.simulated_steps = trajectory.simulated_steps;
      result.capture_ms = trajectory.capture_ms;
      for (const StepProblem& p : trajectory.steps) {
        result.steps.push_back(p.step);
        result.rows.push_back(static_cast<int>(p.rows.size()));
      }
      const long total = static_cast<long>(trajectory.steps.size() * configs.size()) * spec.repeats;
      Progress progress(run.scene.label + ": replay", total);
      long done = 0;
      const Timer timer;
      result.replay = replay_trajectory(trajectory, configs, spec.repeats, spec.solver_params, spec.partition_params,
                                        [&] { progress.update(++done); });
      result.replay_ms = timer.ms();
    }  // the recorded problems are freed before the next scene is captured
    writer.add(result, run);
    writer.write(false);
    log_scene(log, result, static_cast<std::size_t>(spec.repeats));
  }
  writer.write(true);
  if (log && writer.direct_mismatches() > 0)
    std::fprintf(log, "bench: warning: %d replayed direct solves differ from the live run (machine.json replay_check)\n",
                 writer.direct_mismatches());
}

}  // namespace rbpart
