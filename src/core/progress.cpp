#include "core/progress.hpp"

#include <unistd.h>

#include <cmath>

namespace rbpart {

namespace {

// m:ss, or h:mm:ss from an hour on.
std::string duration(double seconds) {
  const long s = static_cast<long>(std::lround(seconds));
  char buffer[32];
  if (s >= 3600)
    std::snprintf(buffer, sizeof buffer, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  else
    std::snprintf(buffer, sizeof buffer, "%ld:%02ld", s / 60, s % 60);
  return buffer;
}

}  // namespace

Progress::Progress(std::string label, long total)
    : Progress(std::move(label), total, stderr, isatty(fileno(stderr)) ? Style::Redraw : Style::Lines) {}

Progress::Progress(std::string label, long total, std::FILE* out, Style style, double line_every_s)
    : label_(std::move(label)), total_(total > 0 ? total : 1), out_(out), style_(style), line_every_s_(line_every_s) {}

Progress::~Progress() { finish(); }

std::string Progress::line(const std::string& label, long done, long total, double elapsed_s) {
  constexpr int kWidth = 40;
  const int permille = static_cast<int>(1000 * done / total);
  const int filled = permille * kWidth / 1000;
  const std::string left = done > 0 ? duration(elapsed_s * (total - done) / done) : "--:--";
  char buffer[128];
  std::snprintf(buffer, sizeof buffer, " [%.*s%*s] %5.1f%% (%ld/%ld) %s elapsed, %s left", filled,
                "########################################", kWidth - filled, "", permille / 10.0, done,
                total, duration(elapsed_s).c_str(), left.c_str());
  return label + buffer;
}

void Progress::update(long done) {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (style_ == Style::Lines) {
    if (elapsed - last_line_s_ < line_every_s_) return;
    last_line_s_ = elapsed;
    std::fprintf(out_, "%s\n", line(label_, done, total_, elapsed).c_str());
    std::fflush(out_);
    return;
  }
  const int permille = static_cast<int>(1000 * done / total_);
  const long second = static_cast<long>(elapsed);
  if (permille == last_permille_ && second == last_second_) return;
  last_permille_ = permille;
  last_second_ = second;
  // "\033[K" clears what a longer previous drawing left at the end of the line.
  std::fprintf(out_, "\r%s\033[K", line(label_, done, total_, elapsed).c_str());
  std::fflush(out_);
  drawn_ = true;
}

void Progress::finish() {
  if (!drawn_) return;
  std::fprintf(out_, "\n");
  std::fflush(out_);
  drawn_ = false;
}

}  // namespace rbpart
