// The study (issue #6): recorded problems replay the live run exactly; a tiny study writes every
// table row and figure; the relative column is the ratio of the per-step medians in steps.csv; the
// estimates on more cores round-trip through bench --resume; claims.md's verdicts follow the rules
// of docs/study.md on hand-made results (issue #25).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <rbpart/world.hpp>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "core/error.hpp"
#include "io/text_format.hpp"
#include "partition/partition.hpp"
#include "solve/solve.hpp"
#include "step/world_internals.hpp"
#include "study/capture.hpp"
#include "study/claims.hpp"
#include "study/figures.hpp"
#include "study/report.hpp"
#include "study/study.hpp"

namespace rbpart {
namespace {

namespace fs = std::filesystem;

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  // (memcmp must not see the null data() of an empty vector.)
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

// A run with no observer is the reference: recording must not perturb the run, and the recorded
// problem must hold everything the direct solver reads.
TEST(Capture, DirectSolveOfARecordedProblemReproducesTheLiveImpulsesBitForBit) {
  // Each scene has loaded rows within the steps checked: the chain falls onto its bar at once.
  for (const char* text :
       {"chain_drop:links=12:height=1.15:bar_height=1", "rock_pile:rocks=24:layers=2", "log_tower:layers=4"}) {
    SCOPED_TRACE(text);
    const SceneDef scene = make_study_scene(parse_study_scene(text));
    constexpr int kSteps = 24, kEvery = 3;
    const Trajectory trajectory = capture_trajectory(scene, kSteps, kEvery, StepParams{}, SolverParams{});
    ASSERT_EQ(trajectory.steps.size(), static_cast<std::size_t>(kSteps / kEvery));

    World live(scene);
    std::size_t k = 0, rows_checked = 0;
    bool warm_started = false, loaded = false;
    for (int s = 1; s <= kSteps; ++s) {
      live.step();
      if (s % kEvery) continue;
      const StepProblem& p = trajectory.steps[k++];
      ASSERT_EQ(p.step, s);
      EXPECT_TRUE(same_bits(p.live_lambda, world_rows(live).lambda)) << "step " << s;
      Rows rows = p.rows;
      solve_newton_direct(rows, p.bodies, p.islands, SolverParams{});
      EXPECT_TRUE(same_bits(rows.lambda, world_rows(live).lambda)) << "step " << s;
      EXPECT_TRUE(rows.state == world_rows(live).state) << "step " << s;
      rows_checked += rows.size();
      // The recorded rows carry the warm start, not the answer: replays start where the live run did.
      for (std::size_t j = 0; j < rows.size(); ++j) {
        warm_started |= p.rows.lambda[j] != rows.lambda[j];
        loaded |= rows.lambda[j] != 0;
      }
    }
    EXPECT_GT(rows_checked, 50u);
    EXPECT_TRUE(warm_started);
    EXPECT_TRUE(loaded);
  }
}

TEST(StudyScene, ParsesNamesOverridesAndRejectsMalformedOnes) {
  const StudyScene s = parse_study_scene("rock_pile:rocks=10:seed=2");
  EXPECT_EQ(s.source, "rock_pile");
  EXPECT_EQ(s.label, "rock_pile:rocks=10:seed=2");
  ASSERT_EQ(s.overrides.size(), 2u);
  EXPECT_EQ(s.overrides[1], (std::pair<std::string, std::string>("seed", "2")));
  EXPECT_EQ(make_study_scene(s).bodies.size() - make_study_scene(parse_study_scene("rock_pile:rocks=4")).bodies.size(), 6u);
  EXPECT_THROW(parse_study_scene("rock_pile:rocks"), InputError);
  EXPECT_THROW(parse_study_scene(""), InputError);
  EXPECT_THROW(make_study_scene(parse_study_scene("no_such_scene")), InputError);
  EXPECT_THROW(make_study_scene(parse_study_scene("rock_pile:bogus=1")), InputError);
}

TEST(StudySpec, PresetsAndTheirGrid) {
  EXPECT_THROW(study_preset("nope"), InputError);
  const StudySpec paper = study_preset("paper");
  EXPECT_EQ(paper.scenes.size(), 4u);
  EXPECT_EQ(paper.scaling_rocks, (std::vector<int>{50, 100, 200, 400, 800}));
  EXPECT_EQ(paper.repeats, 3);
  // Per thread count: the direct baseline, five partitioners x {none, KL, FM}, METIS unrefined.
  const std::vector<StudyConfig> configs = study_configs(paper);
  ASSERT_EQ(configs.size(), 17u);
  EXPECT_TRUE(configs[0].direct());
  EXPECT_EQ(configs[16].partitioner, PartitionerKind::Metis);
  EXPECT_EQ(configs[16].refiner, RefinerKind::None);
  std::set<std::pair<PartitionerKind, RefinerKind>> grid;
  for (const StudyConfig& c : configs) grid.emplace(c.partitioner, c.refiner);
  EXPECT_EQ(grid.size(), 17u);
  validate_study(study_preset("quick"));

  // The reference of the relative column is added when the lists leave it out.
  StudySpec spec = paper;
  spec.partitioners = {PartitionerKind::Mix};
  spec.refiners = {RefinerKind::Fm};
  spec.threads = {1, 2};
  const std::vector<StudyConfig> small = study_configs(spec);
  ASSERT_EQ(small.size(), 6u);
  EXPECT_EQ(small[1].partitioner, PartitionerKind::MinDp);
  EXPECT_EQ(small[1].refiner, RefinerKind::None);
  EXPECT_EQ(small[3].threads, 2);

  for (auto bad : std::vector<void (*)(StudySpec&)>{
           [](StudySpec& s) { s.repeats = 0; }, [](StudySpec& s) { s.every = 0; },
           [](StudySpec& s) { s.nmax = {0}; }, [](StudySpec& s) { s.threads = {}; },
           [](StudySpec& s) { s.partitioners = {PartitionerKind::None}; }, [](StudySpec& s) { s.refiners.clear(); },
           [](StudySpec& s) { s.steps = 2, s.every = 3; }, [](StudySpec& s) { s.scaling_rocks = {0}; },
           [](StudySpec& s) { s.scenes.push_back(s.scenes[0]); }}) {
    StudySpec s = paper;
    bad(s);
    EXPECT_THROW(validate_study(s), InputError);
  }
}

// --- a tiny study, run once for the tests below ---------------------------------------------------

using Row = std::map<std::string, std::string>;

std::vector<Row> read_csv(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> header;
  std::vector<Row> rows;
  auto split = [](const std::string& text) {
    std::vector<std::string> out;
    std::stringstream s(text);
    std::string field;
    while (std::getline(s, field, ',')) out.push_back(field);
    if (!text.empty() && text.back() == ',') out.emplace_back();
    return out;
  };
  if (!std::getline(in, line)) return rows;
  header = split(line);
  while (std::getline(in, line)) {
    const std::vector<std::string> fields = split(line);
    EXPECT_EQ(fields.size(), header.size()) << line;
    Row row;
    for (std::size_t i = 0; i < header.size() && i < fields.size(); ++i) row[header[i]] = fields[i];
    rows.push_back(row);
  }
  return rows;
}

std::string key(const Row& r) {
  return r.at("scene") + "|" + r.at("solver") + "|" + r.at("partitioner") + "|" + r.at("refine") + "|" + r.at("nmax") +
         "|" + r.at("threads");
}

class TinyStudy : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() / ("rbpart_study_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    spec_ = new StudySpec(study_preset("quick"));
    spec_->preset = "tiny";
    spec_->scenes = {parse_study_scene("chain_drop:links=10:height=1.15:bar_height=1"),
                     parse_study_scene("log_tower:layers=3"), parse_study_scene("rock_pile:rocks=6:layers=2")};
    // 6 rocks is the Table 1 scene above (reused, not captured again); 10 rocks is captured.
    spec_->scaling_rocks = {10, 6};
    spec_->scaling_overrides = {{"layers", "2"}};
    spec_->steps = 16;  // the rocks land at step 9
    spec_->every = 4;
    spec_->nmax = {4};
    spec_->threads = {1};
    spec_->repeats = 2;
    run_study(*spec_, dir_->string(), nullptr);
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
    delete spec_;
  }
  static fs::path* dir_;
  static StudySpec* spec_;
};
fs::path* TinyStudy::dir_ = nullptr;
StudySpec* TinyStudy::spec_ = nullptr;

TEST_F(TinyStudy, WritesEveryRowOfEveryTable) {
  const std::vector<StudyConfig> configs = study_configs(*spec_);
  ASSERT_EQ(configs.size(), 17u);
  std::set<std::string> expected_configs;
  for (const StudyConfig& c : configs)
    expected_configs.insert(std::string(c.direct() ? "direct" : "substructured") + "|" + partitioner_name(c.partitioner) +
                            "|" + refiner_name(c.refiner) + "|" + (c.direct() ? "" : std::to_string(c.nmax)) + "|1");

  const std::vector<Row> table = read_csv(*dir_ / "table1.csv");
  ASSERT_EQ(table.size(), 3 * configs.size());
  for (const StudyScene& scene : spec_->scenes) {
    std::set<std::string> seen;
    for (const Row& r : table)
      if (r.at("scene") == scene.label) seen.insert(key(r).substr(scene.label.size() + 1));
    EXPECT_EQ(seen, expected_configs) << scene.label;
  }
  for (const Row& r : table) {
    EXPECT_EQ(r.at("recorded_steps"), "4");
    EXPECT_EQ(r.at("simulated_steps"), "16");
    // Every configuration returned the live run's impulses (docs/design.md#substructured: the
    // substructured backend's iterates are the monolithic ones up to round-off).
    EXPECT_LE(std::stod(r.at("max_lambda_error")), 1e-8) << key(r);
    EXPECT_GT(std::stod(r.at("mean_parts")), 0) << key(r);
  }

  // Scaling: both rock counts, every configuration, the 6-rock point from the Table 1 scene.
  const std::vector<Row> scaling = read_csv(*dir_ / "scaling.csv");
  ASSERT_EQ(scaling.size(), 2 * configs.size());
  EXPECT_EQ(scaling.front().at("rocks"), "6");
  EXPECT_EQ(scaling.front().at("scene"), "rock_pile:rocks=6:layers=2");
  EXPECT_EQ(scaling.back().at("rocks"), "10");
  EXPECT_EQ(scaling.back().at("dynamic_bodies"), "10");

  // steps.csv: per captured scene (three Table 1 scenes, one scaling point) x config x recorded step.
  const std::vector<Row> steps = read_csv(*dir_ / "steps.csv");
  EXPECT_EQ(steps.size(), 4 * configs.size() * 4);

  std::ifstream md(*dir_ / "table1.md");
  const std::string text((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  for (const StudyScene& scene : spec_->scenes) EXPECT_NE(text.find("## " + scene.label + "\n"), std::string::npos);
  std::size_t table_lines = 0;
  for (std::size_t at = text.find("\n| "); at != std::string::npos; at = text.find("\n| ", at + 1)) ++table_lines;
  EXPECT_EQ(table_lines, 3 * (configs.size() + 1));  // + each table's header line

  // claims.md: a row per claim, the tiny study's scenes matched by kind (no large_rock_pile).
  std::ifstream claims_file(*dir_ / "claims.md");
  const std::string claims((std::istreambuf_iterator<char>(claims_file)), std::istreambuf_iterator<char>());
  std::size_t claim_rows = 0;
  for (std::size_t at = claims.find("\n| ("); at != std::string::npos; at = claims.find("\n| (", at + 1)) ++claim_rows;
  EXPECT_EQ(claim_rows, 11u);
  EXPECT_NE(claims.find("| (c) Large Rock Pile: MIX+FM against unrefined MinDP | −35 % (Table 1, Fig. 3) | no "
                        "large_rock_pile scene in this run | not measured |"),
            std::string::npos)
      << claims;
  EXPECT_NE(claims.find("(log_tower:layers=3, "), std::string::npos) << claims;
  EXPECT_NE(claims.find(" at 6, "), std::string::npos) << claims;  // the scaling, by rock count

  std::ifstream machine_file(*dir_ / "machine.json");
  const nlohmann::json machine = nlohmann::json::parse(machine_file);
  for (const char* field : {"cpu", "logical_cpus", "threads", "compiler", "build_type", "git_revision", "git_dirty"})
    EXPECT_TRUE(machine.contains(field)) << field;
  EXPECT_TRUE(machine.at("complete").get<bool>());
  EXPECT_EQ(machine.at("threads"), nlohmann::json::array({1}));
  EXPECT_EQ(machine.at("replay_check").at("direct_replays").get<int>(), 16);
  EXPECT_EQ(machine.at("replay_check").at("bit_identical_to_live_run").get<int>(), 16);
  // Nothing but the outputs: no temporary files are left behind by the atomic writers.
  const std::set<std::string> outputs = {"machine.json", "table1.csv", "table1.md", "steps.csv", "scaling.csv",
                                         "claims.md", "fig3.png", "fig3.svg", "fig4.png", "fig4.svg", "fig5.png",
                                         "fig5.svg", "estimates.png", "estimates.svg"};
  for (const auto& entry : fs::directory_iterator(*dir_))
    EXPECT_TRUE(outputs.count(entry.path().filename().string())) << entry.path();
}

TEST_F(TinyStudy, MeansAndTheRelativeColumnComeFromTheMediansInStepsCsv) {
  // Means of the per-step medians, in step order, exactly as the table computes them.
  std::map<std::string, std::pair<double, int>> sums;
  std::map<std::string, double> maxima;
  std::map<std::string, std::vector<double>> solves;
  for (const Row& r : read_csv(*dir_ / "steps.csv")) {
    auto& [sum, count] = sums[key(r)];
    sum += std::stod(r.at("solve_ms"));
    solves[key(r)].push_back(std::stod(r.at("solve_ms")));
    ++count;
    maxima[key(r)] = std::max(maxima[key(r)], std::stod(r.at("solve_ms")));
  }
  const std::vector<Row> table = read_csv(*dir_ / "table1.csv");
  std::map<std::string, double> mindp;
  for (const Row& r : table)
    if (r.at("partitioner") == "mindp" && r.at("refine") == "none") mindp[r.at("scene")] = std::stod(r.at("mean_solve_ms"));
  for (const Row& r : table) {
    SCOPED_TRACE(key(r));
    const auto& [sum, count] = sums.at(key(r));
    ASSERT_EQ(count, 4);
    const double mean = sum / count;
    EXPECT_DOUBLE_EQ(std::stod(r.at("mean_solve_ms")), mean);
    EXPECT_DOUBLE_EQ(std::stod(r.at("max_solve_ms")), maxima.at(key(r)));
    std::vector<double> sorted = solves.at(key(r));  // four steps: the mean of the middle two
    std::sort(sorted.begin(), sorted.end());
    EXPECT_DOUBLE_EQ(std::stod(r.at("median_solve_ms")), 0.5 * (sorted[1] + sorted[2]));
    EXPECT_DOUBLE_EQ(std::stod(r.at("solve_vs_mindp")), mean / mindp.at(r.at("scene")));
  }
}

// est<c>_ms = max(critical_path_ms, work_ms / c) per step; table1's means are their means, and the
// speed-up is the direct solve's mean over the 16-core estimate's.
TEST_F(TinyStudy, EstimatesOnMoreCoresComeFromWorkAndCriticalPath) {
  std::map<std::string, std::array<double, kEstimates>> sums;
  std::map<std::string, int> counts;
  for (const Row& r : read_csv(*dir_ / "steps.csv")) {
    SCOPED_TRACE(key(r) + " step " + r.at("step"));
    for (std::size_t k = 0; k < kEstimates; ++k) {
      const std::string column = "est" + std::to_string(kEstimateCores[k]) + "_ms";
      if (r.at("solver") == "direct") {
        EXPECT_EQ(r.at(column), "");
        continue;
      }
      const double work = std::stod(r.at("work_ms")), critical = std::stod(r.at("critical_path_ms"));
      EXPECT_EQ(std::stod(r.at(column)), std::max(critical, work / kEstimateCores[k]));
      sums[key(r)][k] += std::stod(r.at(column));
    }
    ++counts[key(r)];
  }
  const std::vector<Row> table = read_csv(*dir_ / "table1.csv");
  std::map<std::string, double> direct;
  for (const Row& r : table)
    if (r.at("solver") == "direct") direct[r.at("scene")] = std::stod(r.at("mean_solve_ms"));
  for (const Row& r : table) {
    SCOPED_TRACE(key(r));
    if (r.at("solver") == "direct") {
      EXPECT_EQ(r.at("mean_est16_ms"), "");
      EXPECT_EQ(r.at("est16_speedup_vs_direct"), "");
      continue;
    }
    for (std::size_t k = 0; k < kEstimates; ++k)
      EXPECT_DOUBLE_EQ(std::stod(r.at("mean_est" + std::to_string(kEstimateCores[k]) + "_ms")),
                       sums.at(key(r))[k] / counts.at(key(r)));
    EXPECT_DOUBLE_EQ(std::stod(r.at("est16_speedup_vs_direct")),
                     direct.at(r.at("scene")) / std::stod(r.at("mean_est16_ms")));
  }
}

// --- steps.csv through the reader of bench --resume, on hand-made measures ----------------------------

std::string join(const std::vector<std::string>& fields) {
  std::string out;
  for (const std::string& f : fields) out += (out.empty() ? "" : ",") + f;
  return out;
}

// A scene of two configurations (the direct baseline and MIX+FM) over three steps, with times that
// print in many digits, and steps bounded by the critical path and by the work.
SceneResult hand_made_steps() {
  SceneResult scene;
  scene.label = "rock_pile:rocks=6";
  scene.steps = {3, 6, 9};
  scene.rows = {0, 12, 40};
  scene.configs = {{PartitionerKind::None, RefinerKind::None, 0, 2}, {PartitionerKind::Mix, RefinerKind::Fm, 4, 2}};
  StepMeasure d;
  d.solve_ms = 0.1 + 0.2;
  d.parts = 1;
  d.factorizations = 3;
  StepMeasure a;  // no rows: nothing to solve
  a.solve_ms = 3e-5;
  StepMeasure b;  // critical path bounds 4 cores and more
  b.solve_ms = 1.0 / 3;
  b.work_ms = 0.7;
  b.critical_path_ms = 0.2;
  b.parts = 3, b.interface_rows = 9, b.interface_bodies = 2, b.edge_cut = 3, b.factorizations = 2;
  b.partition_ms = 1e-3 / 7, b.refine_ms = 2e-3 / 3, b.lambda_error = 1e-13 / 3;
  StepMeasure c = b;  // work / c bounds 4 and 8 cores, the critical path 16
  c.work_ms = 12.7;
  c.critical_path_ms = 0.9;
  c.unsettled = 1;
  scene.replay.measures = {{d, d, d}, {a, b, c}};
  return scene;
}

TEST(StudyReport, StepsCsvRoundTripsThroughTheResumeReaderWithItsEstimates) {
  const SceneResult scene = hand_made_steps();
  const std::string text = steps_csv_rows(scene);
  std::vector<std::string> header = steps_csv_fields(steps_csv_header().substr(0, steps_csv_header().size() - 1));
  EXPECT_EQ(missing_steps_csv_column(header), "");

  // The estimates as written: empty for the baseline; max(critical path, work / c).
  std::vector<std::string> lines;
  std::stringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 6u);
  const auto field = [&](std::size_t line, const std::string& name) {
    const std::vector<std::string> f = steps_csv_fields(lines[line]);
    return f.at(static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin()));
  };
  EXPECT_EQ(field(0, "est4_ms"), "");
  EXPECT_EQ(field(0, "est16_ms"), "");
  EXPECT_EQ(field(3, "est4_ms"), "0");
  EXPECT_EQ(field(4, "est4_ms"), round_trip(0.2));
  EXPECT_EQ(field(4, "est16_ms"), round_trip(0.2));
  EXPECT_EQ(field(5, "est4_ms"), round_trip(12.7 / 4));
  EXPECT_EQ(field(5, "est8_ms"), round_trip(12.7 / 8));
  EXPECT_EQ(field(5, "est16_ms"), round_trip(0.9));

  // Read back and written again: the same text, the estimates derived again from what was read.
  const auto reread = [&](const std::vector<std::string>& h, const std::vector<std::string>& rows) {
    SceneResult again = scene;
    again.replay.measures.assign(2, {});
    for (std::size_t i = 0; i < rows.size(); ++i)
      again.replay.measures[i / 3].push_back(read_step_measure(h, steps_csv_fields(rows[i])));
    return steps_csv_rows(again);
  };
  EXPECT_EQ(reread(header, lines), text);

  // A steps.csv written before the estimates (its last three columns) reads to the same measures.
  std::vector<std::string> old_header(header.begin(), header.end() - kEstimates), old_lines;
  for (const std::string& line : lines) {
    const std::vector<std::string> f = steps_csv_fields(line);
    old_lines.push_back(join(std::vector<std::string>(f.begin(), f.end() - kEstimates)));
  }
  EXPECT_EQ(missing_steps_csv_column(old_header), "");
  EXPECT_EQ(reread(old_header, old_lines), text);
  // The columns may come in any order; a measured one missing is named.
  std::vector<std::string> shuffled = header;
  std::swap(shuffled[0], shuffled[16]);
  std::vector<std::string> shuffled_lines;
  for (const std::string& line : lines) {
    std::vector<std::string> f = steps_csv_fields(line);
    std::swap(f[0], f[16]);
    shuffled_lines.push_back(join(f));
  }
  EXPECT_EQ(reread(shuffled, shuffled_lines), text);
  header.erase(std::find(header.begin(), header.end(), "critical_path_ms"));
  EXPECT_EQ(missing_steps_csv_column(header), "critical_path_ms");

  // The table's means of the estimates, and the speed-up over the direct baseline's mean.
  const std::vector<ConfigSummary> summary = summarize(scene);
  const double est4 = (0 + 0.2 + 12.7 / 4) / 3, est16 = (0 + 0.2 + 0.9) / 3;
  EXPECT_DOUBLE_EQ(summary[1].mean_estimate_ms[0], est4);
  EXPECT_DOUBLE_EQ(summary[1].mean_estimate_ms[2], est16);
  EXPECT_DOUBLE_EQ(summary[1].direct_over_estimate, (0.1 + 0.2) / est16);
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// --resume: the scenes an earlier run of the same study finished are kept as they were, not
// measured again, and the others run; a study with another protocol is refused, its files kept.
TEST(StudyResume, KeepsFinishedScenesAndRefusesAnotherProtocol) {
  const fs::path dir = fs::temp_directory_path() / ("rbpart_resume_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  StudySpec spec = study_preset("quick");
  spec.preset = "tiny";
  spec.scenes = {parse_study_scene("log_tower:layers=3"), parse_study_scene("rock_pile:rocks=6:layers=2")};
  spec.scaling_rocks.clear();
  spec.steps = 12;
  spec.every = 4;
  spec.nmax = {4};
  spec.threads = {1};
  spec.repeats = 1;
  spec.partitioners = {PartitionerKind::Bfs, PartitionerKind::MinDp};
  spec.refiners = {RefinerKind::None};
  StudySpec interrupted = spec;  // a run that ended after its first scene
  interrupted.scenes.resize(1);
  run_study(interrupted, dir.string(), nullptr);
  const std::vector<Row> before = read_csv(dir / "table1.csv");
  const std::string steps_before = read_file(dir / "steps.csv");
  {  // as a study written before the estimates were added left it: they are derived again on resume
    std::stringstream in(steps_before);
    std::string old, line;
    while (std::getline(in, line)) {
      const std::vector<std::string> f = steps_csv_fields(line);
      old += join(std::vector<std::string>(f.begin(), f.end() - kEstimates)) + '\n';
    }
    std::ofstream(dir / "steps.csv") << old;
  }
  const nlohmann::json machine_before = nlohmann::json::parse(read_file(dir / "machine.json"));
  ASSERT_EQ(before.size(), 3u);  // direct, BFS, MinDP

  run_study(spec, dir.string(), nullptr, true);
  const std::vector<Row> after = read_csv(dir / "table1.csv");
  ASSERT_EQ(after.size(), 6u);
  for (std::size_t i = 0; i < before.size(); ++i) EXPECT_EQ(after[i], before[i]) << i;  // bit for bit
  for (std::size_t i = before.size(); i < after.size(); ++i) EXPECT_EQ(after[i].at("scene"), spec.scenes[1].label);
  const std::string steps_after = read_file(dir / "steps.csv");
  EXPECT_EQ(steps_after.substr(0, steps_before.size()), steps_before);
  EXPECT_GT(steps_after.size(), steps_before.size());
  const nlohmann::json machine = nlohmann::json::parse(read_file(dir / "machine.json"));
  EXPECT_TRUE(machine.at("complete").get<bool>());
  EXPECT_EQ(machine.at("started"), machine_before.at("started"));
  ASSERT_EQ(machine.at("scenes").size(), 2u);
  EXPECT_EQ(machine.at("scenes")[0], machine_before.at("scenes")[0]);  // its capture time and revision too
  EXPECT_EQ(machine.at("replay_check").at("direct_replays").get<int>(), 6);

  StudySpec other = spec;
  other.repeats = 2;
  const std::string table = read_file(dir / "table1.csv");
  EXPECT_THROW(run_study(other, dir.string(), nullptr, true), InputError);
  EXPECT_EQ(read_file(dir / "table1.csv"), table);
  EXPECT_EQ(read_file(dir / "steps.csv"), steps_after);
  fs::remove_all(dir);
}

TEST_F(TinyStudy, DrawsEveryFigure) {
  EXPECT_TRUE(fs::equivalent(plot_script_path(), fs::path(RBPART_SOURCE_DIR) / "scripts" / "plot_study.py"));
  const std::string python = find_plot_python();
  if (python.empty()) GTEST_SKIP() << "no Python with matplotlib (Debian: python3-matplotlib): figures not checked";
  ASSERT_EQ(draw_figures(python, dir_->string()), 0);
  for (const char* name :
       {"fig3.png", "fig3.svg", "fig4.png", "fig4.svg", "fig5.png", "fig5.svg", "estimates.png", "estimates.svg"}) {
    const fs::path path = *dir_ / name;
    ASSERT_TRUE(fs::exists(path)) << name;
    std::ifstream in(path, std::ios::binary);
    std::string head(8, '\0');
    in.read(head.data(), 8);
    if (path.extension() == ".png") EXPECT_EQ(head, "\x89PNG\r\n\x1a\n") << name;
    else EXPECT_GT(fs::file_size(path), 1000u) << name;
  }
}

// --- claims.md: the verdict rules (docs/study.md), on hand-made results, not on timings -------------

TEST(Claims, VerdictRules) {
  // A relative change against the paper's: same sign and within a factor of 2; opposite sign; none.
  EXPECT_EQ(change_verdict(-0.31, -0.16), Verdict::Reproduced);
  EXPECT_EQ(change_verdict(-0.31, -0.62), Verdict::Reproduced);
  EXPECT_EQ(change_verdict(-0.12, -0.66), Verdict::NotReproduced);  // far larger
  EXPECT_EQ(change_verdict(-0.46, -0.07), Verdict::NotReproduced);  // far smaller
  EXPECT_EQ(change_verdict(-0.31, -0.04), Verdict::NotReproduced);  // no change
  EXPECT_EQ(change_verdict(-0.31, +0.04), Verdict::NotReproduced);  // no change either way
  EXPECT_EQ(change_verdict(-0.12, +0.06), Verdict::Contradicted);
  // A claimed winner: fastest; beaten by more than 10 %; beaten by less.
  EXPECT_EQ(winner_verdict(1.0, 1.0), Verdict::Reproduced);
  EXPECT_EQ(winner_verdict(1.0, 2.0), Verdict::Reproduced);
  EXPECT_EQ(winner_verdict(1.05, 1.0), Verdict::NotReproduced);
  EXPECT_EQ(winner_verdict(1.2, 1.0), Verdict::Contradicted);
  // Gains at every size: of one size within a factor of 2; spread further; none at one size; a loss.
  EXPECT_EQ(size_independence_verdict({-0.4, -0.3, -0.45}), Verdict::Reproduced);
  EXPECT_EQ(size_independence_verdict({-0.4, -0.1}), Verdict::NotReproduced);
  EXPECT_EQ(size_independence_verdict({-0.4, -0.01, -0.4}), Verdict::NotReproduced);
  EXPECT_EQ(size_independence_verdict({-0.4, +0.1}), Verdict::Contradicted);
  EXPECT_EQ(size_independence_verdict({-0.4}), Verdict::NotMeasured);
  // An absolute time: within a factor of 2, else not reproduced (never contradicted).
  EXPECT_EQ(time_verdict(4, 7.9), Verdict::Reproduced);
  EXPECT_EQ(time_verdict(4, 2.1), Verdict::Reproduced);
  EXPECT_EQ(time_verdict(4, 55.8), Verdict::NotReproduced);
  EXPECT_EQ(time_verdict(4, 0.47), Verdict::NotReproduced);
}

using Times = std::vector<std::tuple<PartitionerKind, RefinerKind, double>>;

// A scene whose configurations (and a direct baseline of 1 ms) took these mean solve times, over
// two recorded steps of 0.5 and 1.5 times the mean. Thread count 1, n_max 8; `other` configurations
// at 2 threads (or n_max 16) are added at 1000 ms each, which the claims must not read.
SceneResult made_scene(const std::string& label, const Times& times, int rocks = 0) {
  SceneResult scene;
  scene.label = label;
  scene.rocks = rocks;
  scene.dynamic_bodies = rocks > 0 ? rocks : 30;
  scene.steps = {2, 4};
  scene.rows = {10, 10};
  const auto add = [&scene](const StudyConfig& c, double ms) {
    scene.configs.push_back(c);
    StepMeasure low, high;
    low.solve_ms = 0.5 * ms;
    high.solve_ms = 1.5 * ms;
    scene.replay.measures.push_back({low, high});
  };
  add({PartitionerKind::None, RefinerKind::None, 0, 1}, 1.0);
  for (const auto& [p, r, ms] : times) add({p, r, 8, 1}, ms);
  for (const auto& [p, r, ms] : times) add({p, r, 16, 1}, 1000);
  add({PartitionerKind::None, RefinerKind::None, 0, 2}, 1000);
  for (const auto& [p, r, ms] : times) add({p, r, 8, 2}, 1000);
  return scene;
}

const ClaimCheck& claim_starting(const std::vector<ClaimCheck>& claims, const std::string& start) {
  for (const ClaimCheck& c : claims)
    if (c.claim.rfind(start, 0) == 0) return c;
  static const ClaimCheck none{"missing: " + start, "", "", "", Verdict::NotMeasured};
  ADD_FAILURE() << "no claim " << start;
  return none;
}

TEST(Claims, EveryVerdictFromHandMadeResults) {
  using P = PartitionerKind;
  using R = RefinerKind;
  // Labels of the quick preset: matched by the scene's kind, whatever its parameters.
  const std::vector<SceneResult> table1 = {
      // MIX the fastest unrefined: (a) reproduced; MinDP 5 ms: (e) about 4 ms reproduced; BFS+FM
      // beaten by more than 10 % by MIX+KL: (e) contradicted.
      made_scene("chain_drop:links=30:height=1.15:bar_height=1",
                 {{P::Bfs, R::None, 6}, {P::MinDp, R::None, 5}, {P::Mix, R::None, 4.5}, {P::Mix, R::Kl, 3},
                  {P::Bfs, R::Fm, 3.5}, {P::Metis, R::None, 1}}),
      // BFS fastest but MIX within 10 %: (a) not reproduced; FM -30 %: (b) reproduced; KL +20 %:
      // (b) contradicted.
      made_scene("log_tower:layers=8", {{P::Bfs, R::None, 9.5}, {P::MinDp, R::None, 20}, {P::Mix, R::None, 10},
                                        {P::MinDp, R::Fm, 14}, {P::MinDp, R::Kl, 24}}),
      // MR faster than MinDP and MIX by more than 10 %: (a) contradicted; MIX+FM -3 %: (c) no change.
      made_scene("rock_pile:rocks=60:layers=4", {{P::Mr, R::None, 10}, {P::MinDp, R::None, 12}, {P::Mix, R::None, 12.5},
                                                 {P::Mix, R::Fm, 11.64}}),
  };
  // The scaling: MIX+FM -40 %, -30 %, -45 % against MinDP.
  const std::vector<SceneResult> scaling = {
      made_scene("rock_pile:rocks=30:layers=4", {{P::MinDp, R::None, 10}, {P::Mix, R::Fm, 6}}, 30),
      made_scene("rock_pile:rocks=60:layers=4", {{P::MinDp, R::None, 10}, {P::Mix, R::Fm, 7}}, 60),
      made_scene("rock_pile:rocks=120:layers=4", {{P::MinDp, R::None, 10}, {P::Mix, R::Fm, 5.5}}, 120)};
  const std::vector<ClaimCheck> claims = check_claims(table1, scaling);
  ASSERT_EQ(claims.size(), 11u);

  EXPECT_EQ(claim_starting(claims, "(a) MinDP and MIX are the best partitioners: Chain Drop").verdict,
            Verdict::Reproduced);
  EXPECT_EQ(claim_starting(claims, "(a) MinDP and MIX are the best partitioners: Log Tower").verdict,
            Verdict::NotReproduced);
  EXPECT_EQ(claim_starting(claims, "(a) MinDP and MIX are the best partitioners: Rock Pile").verdict,
            Verdict::Contradicted);
  // No large_rock_pile scene: the rock_pile is not taken for it.
  EXPECT_EQ(claim_starting(claims, "(a) MinDP and MIX are the best partitioners: Large Rock Pile").verdict,
            Verdict::NotMeasured);
  EXPECT_EQ(claim_starting(claims, "(b) Log Tower: FM").verdict, Verdict::Reproduced);
  EXPECT_EQ(claim_starting(claims, "(b) Log Tower: KL").verdict, Verdict::Contradicted);
  EXPECT_EQ(claim_starting(claims, "(c) Rock Pile").verdict, Verdict::NotReproduced);
  EXPECT_EQ(claim_starting(claims, "(c) Large Rock Pile").verdict, Verdict::NotMeasured);
  EXPECT_EQ(claim_starting(claims, "(d)").verdict, Verdict::Reproduced);
  EXPECT_EQ(claim_starting(claims, "(e) Chain Drop takes about 4 ms").verdict, Verdict::Reproduced);
  EXPECT_EQ(claim_starting(claims, "(e) BFS+FM").verdict, Verdict::Contradicted);

  // Our figures, from the means (0.5 and 1.5 times the given time: the given time).
  EXPECT_NE(claim_starting(claims, "(b) Log Tower: FM").ours.find("−30 %: MinDP+FM 14.0 ms, MinDP 20.0 ms"),
            std::string::npos)
      << claim_starting(claims, "(b) Log Tower: FM").ours;
  EXPECT_NE(claim_starting(claims, "(d)").ours.find("−40 % at 30, −30 % at 60, −45 % at 120 rocks"), std::string::npos)
      << claim_starting(claims, "(d)").ours;
  // METIS is the paper's reference, not a candidate, but shown when it is faster still.
  EXPECT_NE(claim_starting(claims, "(a) MinDP and MIX are the best partitioners: Chain Drop").ours.find(
                "METIS (reference) 1.00 ms"),
            std::string::npos);

  // A scene without the claimed configuration, and a scaling of one size: not measured.
  const std::vector<ClaimCheck> sparse =
      check_claims({made_scene("log_tower", {{P::MinDp, R::None, 20}, {P::Mix, R::None, 10}})}, {scaling[0]});
  EXPECT_EQ(claim_starting(sparse, "(a) MinDP and MIX are the best partitioners: Log Tower").verdict,
            Verdict::NotMeasured);  // nothing to beat
  EXPECT_EQ(claim_starting(sparse, "(b) Log Tower: FM").verdict, Verdict::NotMeasured);
  EXPECT_EQ(claim_starting(sparse, "(d)").verdict, Verdict::NotMeasured);
  // The large pile is not taken for the Rock Pile either.
  const std::vector<ClaimCheck> large =
      check_claims({made_scene("large_rock_pile", {{P::MinDp, R::None, 20}, {P::Mix, R::Fm, 13}})}, {});
  EXPECT_EQ(claim_starting(large, "(c) Rock Pile").verdict, Verdict::NotMeasured);
  EXPECT_EQ(claim_starting(large, "(c) Large Rock Pile").verdict, Verdict::Reproduced);

  // claims.md: a row per claim, and the count of each verdict.
  const std::string md = claims_markdown(claims, "context");
  std::size_t rows = 0;
  for (std::size_t at = md.find("\n| ("); at != std::string::npos; at = md.find("\n| (", at + 1)) ++rows;
  EXPECT_EQ(rows, 11u);
  EXPECT_NE(md.find("4 reproduced, 2 not reproduced, 3 contradicted, 2 not measured.\n"), std::string::npos) << md;
  EXPECT_NE(md.find("| (b) Log Tower: KL against unrefined MinDP | −12 % (Table 1, Fig. 5) | +20 %: MinDP+KL 24.0 ms, "
                    "MinDP 20.0 ms (log_tower:layers=8, 30 bodies) | contradicted | table1.md, fig5 |"),
            std::string::npos)
      << md;
}

}  // namespace
}  // namespace rbpart
