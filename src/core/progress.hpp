#pragma once
// A progress bar on stderr, drawn only when stderr is a terminal (logs stay clean): the fraction
// done, the time elapsed and an estimate of the time left.
#include <chrono>
#include <cstdio>
#include <string>

namespace rbpart {

class Progress {
 public:
  Progress(std::string label, long total);
  // Drawn on `out` whether or not it is a terminal (tests).
  Progress(std::string label, long total, std::FILE* out);
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
  bool enabled_;
  bool drawn_ = false;
  int last_permille_ = -1;
  long last_second_ = -1;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace rbpart
