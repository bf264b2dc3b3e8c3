// The progress line: silent for short runs, rate and time left from the steps done.
#include <algorithm>
#include <catch2/catch.hpp>
#include <sstream>

#include "lua/run_progress.hpp"

using granule::lua::RunProgress;

TEST_CASE("progress: durations read as m:ss or h:mm:ss", "[progress]") {
  CHECK(RunProgress::format_duration(0) == "0:00");
  CHECK(RunProgress::format_duration(42.4) == "0:42");
  CHECK(RunProgress::format_duration(725) == "12:05");
  CHECK(RunProgress::format_duration(3 * 3600 + 2 * 60 + 9) == "3:02:09");
  CHECK(RunProgress::format_duration(-1) == "?");
}

TEST_CASE("progress: nothing before the delay, then time, percent, rate and ETA", "[progress]") {
  double now = 0;
  std::ostringstream out;
  {
    RunProgress p(
        out, 1000, 0.5, false, [&] { return now; }, 2.0, 0.25);
    now = 1.0;
    p.update(100, 0.05);
    CHECK(out.str().empty());  // a short run stays silent
    now = 4.0;
    p.update(400, 0.2);  // 400 steps in 4 s: 100 steps/s, 600 left: 6 s
    std::string line = out.str();
    CHECK_THAT(line, Catch::StartsWith("\r"));
    CHECK_THAT(line, Catch::Contains("t = 0.2 s of 0.5 s"));
    CHECK_THAT(line, Catch::Contains("40.0%"));
    CHECK_THAT(line, Catch::Contains("100 steps/s"));
    CHECK_THAT(line, Catch::Contains("ETA 0:06"));
    now = 4.1;
    p.update(410, 0.205);
    CHECK(out.str() == line);  // redrawn at most every interval
  }
  // Destroying it erases the line it drew.
  CHECK_THAT(out.str(), Catch::EndsWith("\r\033[K"));
}

TEST_CASE("progress: an open-ended run says its ETA is an upper bound", "[progress]") {
  CHECK_THAT(RunProgress::format(1, 2, 0.5, 10, 5, true), Catch::Contains("(at most)"));
  CHECK_THAT(RunProgress::format(1, 2, 0.5, 10, 5, false), !Catch::Contains("(at most)"));
}

TEST_CASE("progress: a batch log gets a line of its own at each tenth of the run", "[progress]") {
  double now = 0;
  std::ostringstream out;
  RunProgress p(
      out, 1000, 1.0, false, [&] { return now; }, 0.0, 0.25, RunProgress::Style::log);
  now = 1;
  p.update(50, 0.05);  // 5 %: no tenth passed yet
  CHECK(out.str().empty());
  p.update(100, 0.1);  // 10 %
  p.update(150, 0.15);
  p.update(350, 0.35);  // past 20 % and 30 % in one chunk: one line
  CHECK(out.str() ==
        "progress: " + RunProgress::format(0.1, 1.0, 0.1, 100, 9, false) + "\n" +
            "progress: " + RunProgress::format(0.35, 1.0, 0.35, 350, 650.0 / 350, false) + "\n");
  p.finish();
  CHECK_THAT(out.str(), !Catch::Contains("\r"));
}

TEST_CASE("progress: with every_seconds, a log line that often whatever the fraction",
          "[progress]") {
  double now = 0;
  std::ostringstream out;
  RunProgress p(
      out, 1000, 1.0, false, [&] { return now; }, 0.0, 0.25, RunProgress::Style::log, 60);
  now = 59;
  p.update(10, 0.01);
  CHECK(out.str().empty());  // the first line a full period in
  now = 60;
  p.update(11, 0.011);
  now = 100;
  p.update(500, 0.5);  // 40 s later: not yet
  now = 121;
  p.update(600, 0.6);
  const std::string s = out.str();
  CHECK(std::count(s.begin(), s.end(), '\n') == 2);
  CHECK_THAT(s, Catch::Contains("1.1%") && Catch::Contains("60.0%"));
}

TEST_CASE("progress: clear() erases the terminal line until the next update", "[progress]") {
  double now = 0;
  std::ostringstream out;
  RunProgress p(
      out, 1000, 1.0, false, [&] { return now; }, 0.0, 0.25);
  now = 1;
  p.update(100, 0.1);
  granule::lua::clear_progress_line();  // what print() does first
  CHECK_THAT(out.str(), Catch::EndsWith("\r\033[K"));
  CHECK(!p.shown());
  now = 1.01;  // within the redraw interval, but the line was erased: drawn again
  p.update(101, 0.101);
  CHECK(p.shown());
  CHECK_THAT(out.str(), Catch::EndsWith("10.1%  100 steps/s  ETA 0:09\033[K"));
}

// A run continued from a checkpoint counts its percentage over the whole run, as
// its times (t of the end time) do; rate and time left are this process's.
TEST_CASE("progress: a continued run's percentage is of the whole run", "[progress]") {
  double now = 0;
  std::ostringstream out;
  RunProgress p(
      out, 600, 1.0, false, [&] { return now; }, 0.0, 0.25, RunProgress::Style::log);
  p.continued_after(400);
  now = 1;
  p.update(50, 0.45);  // 45 %: the tenth it began in, no line
  CHECK(out.str().empty());
  p.update(100, 0.5);  // 50 %
  CHECK(out.str() == "progress: " + RunProgress::format(0.5, 1.0, 0.5, 100, 5, false) + "\n");
}
