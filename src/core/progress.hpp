#pragma once
// A progress bar on stderr, drawn only when stderr is a terminal (logs stay clean).
#include <string>

namespace rbpart {

class Progress {
 public:
  Progress(std::string label, long total);
  ~Progress();
  void update(long done);

 private:
  std::string label_;
  long total_;
  int last_permille_ = -1;
  bool enabled_;
};

}  // namespace rbpart
