// Numeric option checks with errors in the CLI's own form, "--erp: must lie in (0, 1] (got 0)".
// CLI11's NonNegativeNumber and PositiveNumber print their range, whose upper end is DBL_MAX as a
// 309-digit number, and its Range prints (0, 1] as "0.000000 to 1.000000".
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

#include "commands.hpp"

namespace rbpart::cli {
namespace {

std::string shown(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

// A check that `ok` holds for the option's value; `what` completes "must ...", `brief` is shown in
// --help.
CLI::Validator numeric_check(const std::string& what, const std::string& brief, std::function<bool(double)> ok) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        std::size_t used = 0;
        double x = 0;
        try {
          x = std::stod(text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used != text.size() || !std::isfinite(x)) return "must be a number (got '" + text + "')";
        return ok(x) ? std::string() : "must " + what + " (got " + text + ")";
      },
      brief);
}

}  // namespace

CLI::Validator at_least(double lo) {
  return numeric_check("be at least " + shown(lo), ">= " + shown(lo), [lo](double x) { return x >= lo; });
}

CLI::Validator positive() {
  return numeric_check("be positive", "> 0", [](double x) { return x > 0; });
}

CLI::Validator open_closed(double lo, double hi) {
  const std::string interval = "(" + shown(lo) + ", " + shown(hi) + "]";
  return numeric_check("lie in " + interval, "in " + interval, [lo, hi](double x) { return x > lo && x <= hi; });
}

}  // namespace rbpart::cli
