// The progress line: silent for short runs, rate and time left from the steps done.
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
