#pragma once
// The paper's claims beside what the study measured (claims.md, issue #25): per claim the paper's
// figure, ours and a verdict, by the rules of docs/study.md ("The paper's claims"). Claims are
// judged on mean solve times, as the paper quotes them, of the scenes matched by their kind (the
// built-in scene a label names, whatever its parameters), at the study's first thread count and
// first n_max.
#include <string>
#include <vector>

#include "study/report.hpp"

namespace rbpart {

enum class Verdict { Reproduced, NotReproduced, Contradicted, NotMeasured };
const char* verdict_name(Verdict v);  // "reproduced", "not reproduced", "contradicted", "not measured"

// The rules' constants (docs/study.md).
inline constexpr double kClaimNoise = 0.05;   // a relative change smaller than this is none
inline constexpr double kClaimFactor = 2;     // "the same size": within this factor of the paper's
inline constexpr double kClaimMargin = 0.10;  // another configuration "wins" when this much faster

// A relative change of the solve time (ours / reference - 1) against the paper's (e.g. -0.31):
// none if |ours| < kClaimNoise (not reproduced); the opposite sign of the paper's: contradicted;
// the same sign and within kClaimFactor of the paper's: reproduced; else not reproduced.
Verdict change_verdict(double paper, double ours);
// "X wins": the claimed configuration(s) fastest: reproduced; another faster than the fastest
// claimed one by more than kClaimMargin (claimed / best - 1 > kClaimMargin): contradicted; else
// not reproduced.
Verdict winner_verdict(double best_claimed_ms, double best_other_ms);
// "the gain does not depend on size": `changes` per size (ours / reference - 1), at least two.
// An increase of kClaimNoise or more at some size: contradicted; a decrease of kClaimNoise or more
// at every size, the largest within kClaimFactor of the smallest: reproduced; else not reproduced.
Verdict size_independence_verdict(const std::vector<double>& changes);
// An absolute time: within kClaimFactor of the paper's: reproduced; else not reproduced (it depends
// on the machine and the scene's size, so it cannot contradict).
Verdict time_verdict(double paper_ms, double ours_ms);

struct ClaimCheck {
  std::string claim;   // what the paper says, with its claim letter: "(b) Log Tower: FM against MinDP"
  std::string paper;   // the paper's figure, and where it is: "−31 % (Table 1, Fig. 5)"
  std::string ours;    // our figure and the numbers it rests on, or why it was not measured
  std::string data;    // our output that shows it: "table1.md, fig5"
  Verdict verdict = Verdict::NotMeasured;
};

// The claims (a)-(e), in order: `table1` are Table 1's scenes, `scaling` the Rock Pile scaling
// (SceneResult::rocks set), sorted by rock count.
std::vector<ClaimCheck> check_claims(const std::vector<SceneResult>& table1, const std::vector<SceneResult>& scaling);

// claims.md: `context` (machine, preset, what was compared) above the table, the count of each
// verdict below it.
std::string claims_markdown(const std::vector<ClaimCheck>& claims, const std::string& context);

}  // namespace rbpart
