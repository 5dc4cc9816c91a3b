#include "study/claims.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>

#include "partition/partition.hpp"

namespace rbpart {

namespace {

const char* display_name(PartitionerKind p) {
  switch (p) {
    case PartitionerKind::Bfs: return "BFS";
    case PartitionerKind::MinDp: return "MinDP";
    case PartitionerKind::MaxDp: return "MaxDP";
    case PartitionerKind::Mr: return "MR";
    case PartitionerKind::Mix: return "MIX";
    case PartitionerKind::Metis: return "METIS";
    case PartitionerKind::None: break;
  }
  return "direct";
}

std::string display_name(const StudyConfig& c) {
  std::string out = display_name(c.partitioner);
  switch (c.refiner) {
    case RefinerKind::Kl: return out + "+KL";
    case RefinerKind::Fm: return out + "+FM";
    case RefinerKind::FmRollback: return out + "+FM(rollback)";
    case RefinerKind::None: break;
  }
  return out;
}

std::string ms(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, v < 10 ? "%.2f ms" : v < 100 ? "%.1f ms" : "%.0f ms", v);
  return buffer;
}

// The paper's partitioners and refiners: METIS is its min-cut reference and FM with rollback our
// extension, so neither is a candidate of "X is the best".
constexpr PartitionerKind kPaperPartitioners[] = {PartitionerKind::Bfs, PartitionerKind::MinDp, PartitionerKind::MaxDp,
                                                  PartitionerKind::Mr, PartitionerKind::Mix};
constexpr RefinerKind kPaperRefiners[] = {RefinerKind::None, RefinerKind::Kl, RefinerKind::Fm};

// The built-in scene a label names ("rock_pile:rocks=60:layers=4" is a rock_pile).
std::string kind(const std::string& label) { return label.substr(0, label.find(':')); }

// One scene's configurations at the study's first thread count and first n_max.
class SceneView {
 public:
  explicit SceneView(const SceneResult& scene) : scene_(&scene), summary_(summarize(scene)) {
    const int threads = scene.configs.empty() ? 0 : scene.configs.front().threads;
    int nmax = -1;
    for (const StudyConfig& c : scene.configs)
      if (!c.direct() && c.threads == threads) {
        nmax = c.nmax;
        break;
      }
    for (const ConfigSummary& s : summary_)
      if (s.config.threads == threads && !s.config.direct() && s.config.nmax == nmax) shown_.push_back(&s);
  }

  const SceneResult& scene() const { return *scene_; }

  // Mean solve ms of partitioner + refiner; nullopt if the study did not run it.
  std::optional<double> mean(PartitionerKind p, RefinerKind r) const {
    for (const ConfigSummary* s : shown_)
      if (s->config.partitioner == p && s->config.refiner == r && s->mean_solve_ms > 0) return s->mean_solve_ms;
    return std::nullopt;
  }

  // The candidates measured, fastest first.
  std::vector<const ConfigSummary*> ranked(const std::function<bool(const StudyConfig&)>& candidate) const {
    std::vector<const ConfigSummary*> out;
    for (const ConfigSummary* s : shown_)
      if (candidate(s->config) && s->mean_solve_ms > 0) out.push_back(s);
    std::stable_sort(out.begin(), out.end(), [](const ConfigSummary* a, const ConfigSummary* b) {
      return a->mean_solve_ms < b->mean_solve_ms;
    });
    return out;
  }

 private:
  const SceneResult* scene_;
  std::vector<ConfigSummary> summary_;
  std::vector<const ConfigSummary*> shown_;
};

const SceneResult* find_scene(const std::vector<SceneResult>& scenes, const char* scene_kind) {
  for (const SceneResult& s : scenes)
    if (kind(s.label) == scene_kind) return &s;
  return nullptr;
}

bool paper_partitioner(PartitionerKind p) {
  return std::find(std::begin(kPaperPartitioners), std::end(kPaperPartitioners), p) != std::end(kPaperPartitioners);
}
bool paper_refiner(RefinerKind r) {
  return std::find(std::begin(kPaperRefiners), std::end(kPaperRefiners), r) != std::end(kPaperRefiners);
}

std::string in_scene(const SceneResult& s) {
  return " (" + s.label + ", " + std::to_string(s.dynamic_bodies) + " bodies)";
}

ClaimCheck not_measured(std::string claim, std::string paper, std::string data, std::string why) {
  return {std::move(claim), std::move(paper), std::move(why), std::move(data), Verdict::NotMeasured};
}

// (a), one scene: the fastest unrefined partitioner of the paper's is MinDP or MIX.
ClaimCheck best_partitioners(const std::vector<SceneResult>& table1, const char* scene_kind, const char* scene_name) {
  std::string claim = std::string("(a) MinDP and MIX are the best partitioners: ") + scene_name;
  std::string paper = "MinDP or MIX fastest unrefined (Table 1, Fig. 3)";
  const char* data = "table1.md, fig3";
  const SceneResult* scene = find_scene(table1, scene_kind);
  if (!scene) return not_measured(claim, paper, data, std::string("no ") + scene_kind + " scene in this run");
  const SceneView view(*scene);
  const auto claimed = [](PartitionerKind p) { return p == PartitionerKind::MinDp || p == PartitionerKind::Mix; };
  const std::vector<const ConfigSummary*> ranked = view.ranked(
      [](const StudyConfig& c) { return paper_partitioner(c.partitioner) && c.refiner == RefinerKind::None; });
  const auto best_claimed =
      std::find_if(ranked.begin(), ranked.end(), [&](auto s) { return claimed(s->config.partitioner); });
  const auto best_other =
      std::find_if(ranked.begin(), ranked.end(), [&](auto s) { return !claimed(s->config.partitioner); });
  if (best_claimed == ranked.end() || best_other == ranked.end())
    return not_measured(claim, paper, data, "needs MinDP or MIX and one of BFS, MaxDP, MR, unrefined");
  std::string ours;
  for (const ConfigSummary* s : ranked)
    ours += (ours.empty() ? "" : ", ") + display_name(s->config) + " " + ms(s->mean_solve_ms);
  if (const std::optional<double> metis = view.mean(PartitionerKind::Metis, RefinerKind::None);
      metis && *metis < ranked.front()->mean_solve_ms)
    ours += "; METIS (reference) " + ms(*metis);
  return {claim, paper, ours + in_scene(*scene), data,
          winner_verdict((*best_claimed)->mean_solve_ms, (*best_other)->mean_solve_ms)};
}

// (b), (c): the mean solve time of partitioner p with refiner r against unrefined MinDP's, beside the
// paper's change.
ClaimCheck change_against_mindp(const std::vector<SceneResult>& table1, const char* scene_kind, std::string claim,
                                PartitionerKind p, RefinerKind r, double paper_change, std::string paper,
                                const char* data) {
  const SceneResult* scene = find_scene(table1, scene_kind);
  if (!scene) return not_measured(claim, paper, data, std::string("no ") + scene_kind + " scene in this run");
  const SceneView view(*scene);
  const std::optional<double> ours = view.mean(p, r), mindp = view.mean(PartitionerKind::MinDp, RefinerKind::None);
  const std::string name = display_name(StudyConfig{p, r, 1, 1});
  if (!ours || !mindp)
    return not_measured(claim, paper, data, "no " + std::string(ours ? "MinDP" : name) + " configuration");
  const double ratio = *ours / *mindp;
  return {claim, paper,
          percent_change(ratio) + ": " + name + " " + ms(*ours) + ", MinDP " + ms(*mindp) + in_scene(*scene), data,
          change_verdict(paper_change, ratio - 1)};
}

// (d): MIX+FM's change against MinDP at every size of the Rock Pile scaling.
ClaimCheck size_independence(const std::vector<SceneResult>& scaling) {
  std::string claim = "(d) The gains do not depend on size (Rock Pile, MIX+FM against MinDP)";
  std::string paper = "the same gain at 50-800 rocks (Fig. 4)";
  const char* data = "scaling.csv, fig4";
  std::vector<double> changes;
  std::string ours;
  for (const SceneResult& scene : scaling) {
    if (scene.rocks <= 0) continue;
    const SceneView view(scene);
    const std::optional<double> mix = view.mean(PartitionerKind::Mix, RefinerKind::Fm),
                                mindp = view.mean(PartitionerKind::MinDp, RefinerKind::None);
    if (!mix || !mindp) continue;
    changes.push_back(*mix / *mindp - 1);
    ours += (ours.empty() ? "" : ", ") + percent_change(*mix / *mindp) + " at " + std::to_string(scene.rocks);
  }
  if (changes.size() < 2)
    return not_measured(claim, paper, data, "needs MIX+FM and MinDP at two rock counts or more of the scaling");
  return {claim, paper, ours + " rocks", data, size_independence_verdict(changes)};
}

// (e): the Chain Drop's time with MinDP, and its best configuration.
ClaimCheck chain_drop_time(const std::vector<SceneResult>& table1) {
  std::string claim = "(e) Chain Drop takes about 4 ms with MinDP";
  std::string paper = "≈ 4 ms (Table 1)";
  const char* data = "table1.md";
  const SceneResult* scene = find_scene(table1, "chain_drop");
  if (!scene) return not_measured(claim, paper, data, "no chain_drop scene in this run");
  const std::optional<double> mindp = SceneView(*scene).mean(PartitionerKind::MinDp, RefinerKind::None);
  if (!mindp) return not_measured(claim, paper, data, "no MinDP configuration");
  return {claim, paper, "MinDP " + ms(*mindp) + in_scene(*scene), data, time_verdict(4.0, *mindp)};
}

ClaimCheck chain_drop_best(const std::vector<SceneResult>& table1) {
  std::string claim = "(e) BFS+FM is the Chain Drop's best configuration";
  std::string paper = "BFS+FM fastest of the partitioners × refinements (Table 1)";
  const char* data = "table1.md, fig3";
  const SceneResult* scene = find_scene(table1, "chain_drop");
  if (!scene) return not_measured(claim, paper, data, "no chain_drop scene in this run");
  const SceneView view(*scene);
  const std::optional<double> bfs_fm = view.mean(PartitionerKind::Bfs, RefinerKind::Fm);
  const std::vector<const ConfigSummary*> ranked = view.ranked([](const StudyConfig& c) {
    return paper_partitioner(c.partitioner) && paper_refiner(c.refiner) &&
           !(c.partitioner == PartitionerKind::Bfs && c.refiner == RefinerKind::Fm);
  });
  if (!bfs_fm || ranked.empty()) return not_measured(claim, paper, data, "needs BFS+FM and another configuration");
  const ConfigSummary& best = *ranked.front();
  std::string ours = "BFS+FM " + ms(*bfs_fm) + "; fastest other: " + display_name(best.config) + " " +
                     ms(best.mean_solve_ms) + ", BFS+FM " + percent_change(*bfs_fm / best.mean_solve_ms) + " against it";
  return {claim, paper, ours + in_scene(*scene), data, winner_verdict(*bfs_fm, best.mean_solve_ms)};
}

}  // namespace

const char* verdict_name(Verdict v) {
  switch (v) {
    case Verdict::Reproduced: return "reproduced";
    case Verdict::NotReproduced: return "not reproduced";
    case Verdict::Contradicted: return "contradicted";
    case Verdict::NotMeasured: break;
  }
  return "not measured";
}

Verdict change_verdict(double paper, double ours) {
  if (!std::isfinite(ours)) return Verdict::NotMeasured;
  if (std::abs(ours) < kClaimNoise) return Verdict::NotReproduced;
  if ((ours < 0) != (paper < 0)) return Verdict::Contradicted;
  const double a = std::abs(ours), p = std::abs(paper);
  return a >= p / kClaimFactor && a <= p * kClaimFactor ? Verdict::Reproduced : Verdict::NotReproduced;
}

Verdict winner_verdict(double best_claimed_ms, double best_other_ms) {
  if (best_claimed_ms <= best_other_ms) return Verdict::Reproduced;
  return best_claimed_ms / best_other_ms - 1 > kClaimMargin ? Verdict::Contradicted : Verdict::NotReproduced;
}

Verdict size_independence_verdict(const std::vector<double>& changes) {
  if (changes.size() < 2) return Verdict::NotMeasured;
  double smallest = INFINITY, largest = 0;
  bool every_size_gains = true;
  for (const double c : changes) {
    if (c >= kClaimNoise) return Verdict::Contradicted;
    every_size_gains = every_size_gains && c <= -kClaimNoise;
    smallest = std::min(smallest, std::abs(c));
    largest = std::max(largest, std::abs(c));
  }
  return every_size_gains && largest <= kClaimFactor * smallest ? Verdict::Reproduced : Verdict::NotReproduced;
}

Verdict time_verdict(double paper_ms, double ours_ms) {
  return ours_ms >= paper_ms / kClaimFactor && ours_ms <= paper_ms * kClaimFactor ? Verdict::Reproduced
                                                                                   : Verdict::NotReproduced;
}

std::vector<ClaimCheck> check_claims(const std::vector<SceneResult>& table1, const std::vector<SceneResult>& scaling) {
  std::vector<ClaimCheck> out;
  for (const auto& [scene_kind, name] : {std::pair{"chain_drop", "Chain Drop"}, {"log_tower", "Log Tower"},
                                         {"rock_pile", "Rock Pile"}, {"large_rock_pile", "Large Rock Pile"}})
    out.push_back(best_partitioners(table1, scene_kind, name));
  out.push_back(change_against_mindp(table1, "log_tower", "(b) Log Tower: FM against unrefined MinDP",
                                     PartitionerKind::MinDp, RefinerKind::Fm, -0.31, "−31 % (Table 1, Fig. 5)",
                                     "table1.md, fig5"));
  out.push_back(change_against_mindp(table1, "log_tower", "(b) Log Tower: KL against unrefined MinDP",
                                     PartitionerKind::MinDp, RefinerKind::Kl, -0.12, "−12 % (Table 1, Fig. 5)",
                                     "table1.md, fig5"));
  out.push_back(change_against_mindp(table1, "rock_pile", "(c) Rock Pile: MIX+FM against unrefined MinDP",
                                     PartitionerKind::Mix, RefinerKind::Fm, -0.46, "−46 % (Table 1, Fig. 3)",
                                     "table1.md, fig3"));
  out.push_back(change_against_mindp(table1, "large_rock_pile", "(c) Large Rock Pile: MIX+FM against unrefined MinDP",
                                     PartitionerKind::Mix, RefinerKind::Fm, -0.35, "−35 % (Table 1, Fig. 3)",
                                     "table1.md, fig3"));
  out.push_back(size_independence(scaling));
  out.push_back(chain_drop_time(table1));
  out.push_back(chain_drop_best(table1));
  return out;
}

std::string claims_markdown(const std::vector<ClaimCheck>& claims, const std::string& context) {
  std::string out = "# The paper's claims beside this study\n\n" + context + "\n";
  out += "| claim | paper | ours | verdict | our data |\n|---|---|---|---|---|\n";
  int counts[4] = {};
  // A scene label may hold a '|', which would end its cell.
  const auto cell = [](const std::string& text) {
    std::string escaped;
    for (const char ch : text) escaped += ch == '|' ? std::string("\\|") : std::string(1, ch);
    return escaped;
  };
  for (const ClaimCheck& c : claims) {
    out += "| " + cell(c.claim) + " | " + cell(c.paper) + " | " + cell(c.ours) + " | " + verdict_name(c.verdict) +
           " | " + cell(c.data) + " |\n";
    ++counts[static_cast<int>(c.verdict)];
  }
  out += "\n";
  bool first = true;
  for (const Verdict v : {Verdict::Reproduced, Verdict::NotReproduced, Verdict::Contradicted, Verdict::NotMeasured}) {
    out += (first ? "" : ", ") + std::to_string(counts[static_cast<int>(v)]) + " " + verdict_name(v);
    first = false;
  }
  return out + ".\n";
}

}  // namespace rbpart
