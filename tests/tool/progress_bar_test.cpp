// The progress bar's text (rate, time left) and when it draws: never to a
// file or pipe, never in the first second, always in place on one line.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <limits>
#include <string>

#include "progress_bar.hpp"

namespace stridemap::io {
namespace {

std::string contents(std::FILE* file) {
  std::fflush(file);
  std::rewind(file);
  std::string text;
  for (int c; (c = std::fgetc(file)) != EOF;) text += static_cast<char>(c);
  return text;
}

TEST(ProgressLine, ShowsShareBarRateAndTimeLeft) {
  // 250 of 1000 scans in 10 s: 25 scans/s, 750 left take 30 s.
  EXPECT_EQ(progress_line("map", 250, 1000, "scans", 10.0),
            "map  25% [#####               ] 250/1000 scans, 25 scans/s, 0:30 left");
  // Slow work keeps two significant digits of the rate.
  EXPECT_EQ(progress_line("mount-analysis", 3, 12, "mounts", 4.0),
            "mount-analysis  25% [#####               ] 3/12 mounts, 0.75 mounts/s, 0:12 left");
  // Done: a full bar, no time left.
  EXPECT_EQ(progress_line("map", 8, 8, "scans", 2.0), "map 100% [####################] 8/8 scans, 4 scans/s");
}

TEST(ProgressLine, NothingDoneOrUnknownTotalLeavesOutWhatCannotBeKnown) {
  EXPECT_EQ(progress_line("map", 0, 100, "scans", 3.0), "map   0% [                    ] 0/100 scans");
  EXPECT_EQ(progress_line("import", 512, 0, "kB", 2.0), "import 512 kB, 256 kB/s");
  // More done than the total (a total that was an estimate): capped at 100 %.
  EXPECT_EQ(progress_line("x", 12, 10, "scans", 1.0), "x 100% [####################] 12/10 scans, 12 scans/s");
}

TEST(DurationText, MinutesAndHours) {
  EXPECT_EQ(duration_text(0.4), "0:00");
  EXPECT_EQ(duration_text(59.6), "1:00");
  EXPECT_EQ(duration_text(725.0), "12:05");
  EXPECT_EQ(duration_text(3723.0), "1:02:03");
  EXPECT_EQ(duration_text(-1.0), "?");
  EXPECT_EQ(duration_text(std::numeric_limits<double>::infinity()), "?");
}

TEST(ProgressBar, DrawsInPlaceAndEndsTheLine) {
  std::FILE* file = std::tmpfile();
  ASSERT_NE(file, nullptr);
  {
    ProgressBar bar("map", "scans", file, true, 0.0);
    bar.update(1, 4);
    bar.update(4, 4);  // the last step is drawn even within the redraw period
  }
  const std::string text = contents(file);
  std::fclose(file);
  EXPECT_EQ(text.rfind("\rmap  25% [", 0), 0u) << text;
  EXPECT_NE(text.find("\rmap 100% [####################] 4/4 scans"), std::string::npos) << text;
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(text.find('\n'), text.size() - 1) << "one line, redrawn in place";
}

TEST(ProgressBar, ShortRunsAndDisabledBarsWriteNothing) {
  std::FILE* file = std::tmpfile();
  ASSERT_NE(file, nullptr);
  {
    ProgressBar short_run("map", "scans", file, true);  // within its first second
    short_run.update(1, 2);
    short_run.update(2, 2);
    ProgressBar off("map", "scans", file, false, 0.0);
    off.update(1, 2);
    off.clear();
    EXPECT_FALSE(off.callback());
  }
  EXPECT_EQ(contents(file), "");
  std::fclose(file);
}

TEST(ProgressBar, StderrThatIsNoTerminalGetsNoBar) {
  std::FILE* file = std::tmpfile();
  ASSERT_NE(file, nullptr);
  std::fflush(stderr);
  const int saved = ::dup(STDERR_FILENO);
  ASSERT_GE(saved, 0);
  ::dup2(::fileno(file), STDERR_FILENO);
  const bool enabled = ProgressBar::for_stderr("map", "scans", false).enabled();
  ::dup2(saved, STDERR_FILENO);
  ::close(saved);
  std::fclose(file);
  EXPECT_FALSE(enabled);
  // --quiet turns it off even on a terminal.
  EXPECT_FALSE(ProgressBar::for_stderr("map", "scans", true).enabled());
}

}  // namespace
}  // namespace stridemap::io
