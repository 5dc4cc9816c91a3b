#include "core/progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace rbpart {

Progress::Progress(std::string label, long total)
    : label_(std::move(label)), total_(total > 0 ? total : 1), enabled_(isatty(fileno(stderr)) != 0) {}

Progress::~Progress() {
  if (enabled_ && last_permille_ >= 0) std::fprintf(stderr, "\n");
}

void Progress::update(long done) {
  if (!enabled_) return;
  const int permille = static_cast<int>(1000 * done / total_);
  if (permille == last_permille_) return;
  last_permille_ = permille;
  constexpr int kWidth = 40;
  const int filled = permille * kWidth / 1000;
  std::fprintf(stderr, "\r%s [%.*s%*s] %5.1f%% (%ld/%ld)", label_.c_str(), filled,
               "########################################", kWidth - filled, "", permille / 10.0, done, total_);
  std::fflush(stderr);
}

}  // namespace rbpart
