#pragma once
// Progress of long work on stderr: the fraction done, the time elapsed and an estimate of the time
// left. On a terminal the bar is redrawn in place; in a log (stderr redirected, e.g. a run under
// nohup or CI) it is written as a line of its own once a minute, so that a run of hours says how
// far it is without filling the log.
#include <chrono>
#include <cstdio>
#include <string>

namespace rbpart {

class Progress {
 public:
  // Redraw: one line rewritten in place (a terminal). Lines: a full line at most every
  // `line_every_s` seconds, and none before the first interval has passed (a log).
  enum class Style { Redraw, Lines };
  static constexpr double kLogEverySeconds = 60;

  // On stderr: Redraw if it is a terminal, else Lines.
  Progress(std::string label, long total);
  // On `out` in the given style whether or not it is a terminal (tests).
  Progress(std::string label, long total, std::FILE* out, Style style = Style::Redraw,
           double line_every_s = kLogEverySeconds);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void update(long done);
  // Ends the bar's line, so that what is printed next starts on a line of its own. Idempotent.
  void finish();

  // One drawing of the bar, e.g. "simulate rock_pile [####    ] 45.0% (225/500) 0:23 elapsed,
  // 0:28 left": the time left extrapolates the mean time per item so far ("--:--" before the first).
  static std::string line(const std::string& label, long done, long total, double elapsed_s);

 private:
  std::string label_;
  long total_;
  std::FILE* out_;
  Style style_;
  double line_every_s_;
  bool drawn_ = false;
  int last_permille_ = -1;
  long last_second_ = -1;
  double last_line_s_ = 0;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace rbpart
