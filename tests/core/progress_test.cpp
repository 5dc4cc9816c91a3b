// The progress bar: fraction, elapsed time and the estimate of the rest; the line it leaves ended.
#include "core/progress.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace rbpart {
namespace {

std::string contents(std::FILE* file) {
  std::rewind(file);
  std::string text;
  for (int c; (c = std::fgetc(file)) != EOF;) text += static_cast<char>(c);
  return text;
}

TEST(Progress, LineShowsFractionElapsedAndTheRestEstimated) {
  EXPECT_EQ(Progress::line("run", 25, 100, 10.0),
            "run [##########                              ]  25.0% (25/100) 0:10 elapsed, 0:30 left");
  // Hours from an hour on; the rest extrapolates the mean time per item.
  EXPECT_EQ(Progress::line("run", 1, 3, 1800.0).substr(54), "(1/3) 30:00 elapsed, 1:00:00 left");
  EXPECT_NE(Progress::line("run", 0, 10, 0.0).find("0:00 elapsed, --:-- left"), std::string::npos);
  EXPECT_NE(Progress::line("run", 10, 10, 75.4).find("100.0% (10/10) 1:15 elapsed, 0:00 left"), std::string::npos);
}

TEST(Progress, FinishEndsTheLineOnceSoTheSummaryStartsOnItsOwn) {
  std::FILE* out = std::tmpfile();
  ASSERT_NE(out, nullptr);
  {
    Progress progress("run", 4, out);
    progress.update(1);
    progress.update(4);
    progress.finish();
    std::fputs("summary\n", out);
  }  // the destructor adds no second line end
  const std::string text = contents(out);
  std::fclose(out);
  EXPECT_EQ(text.rfind("\r", 0), 0u);
  EXPECT_NE(text.find("(4/4)"), std::string::npos);
  EXPECT_EQ(text.substr(text.size() - 9), "\nsummary\n");
  EXPECT_EQ(text.find('\n'), text.size() - 9);
}

TEST(Progress, InALogEveryLineIsWholeAndNoneComesBeforeTheInterval) {
  std::FILE* out = std::tmpfile();
  ASSERT_NE(out, nullptr);
  {
    Progress progress("run", 4, out, Progress::Style::Lines, 0.0);
    progress.update(1);
    progress.update(4);
    progress.finish();
  }
  std::string text = contents(out);
  EXPECT_EQ(text.find('\r'), std::string::npos);
  EXPECT_EQ(text.find("\033"), std::string::npos);
  const std::size_t first_end = text.find('\n');
  ASSERT_NE(first_end, std::string::npos);
  EXPECT_NE(text.substr(0, first_end).find("(1/4)"), std::string::npos);
  EXPECT_NE(text.substr(first_end + 1).find("(4/4)"), std::string::npos);
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(text.find('\n', first_end + 1), text.size() - 1);  // two lines, finish() adds none
  std::fclose(out);

  out = std::tmpfile();
  ASSERT_NE(out, nullptr);
  {
    Progress progress("run", 4, out, Progress::Style::Lines, 3600.0);
    progress.update(1);
    progress.update(4);
  }
  EXPECT_EQ(contents(out), "");
  std::fclose(out);
}

TEST(Progress, NothingDrawnNothingEnded) {
  std::FILE* out = std::tmpfile();
  ASSERT_NE(out, nullptr);
  { Progress("run", 4, out).finish(); }
  EXPECT_EQ(contents(out), "");
  std::fclose(out);
}

}  // namespace
}  // namespace rbpart
