// ProgressText: contact-sim's progress line extrapolates the mean rate so far,
// ETA = elapsed (1 - f) / f, and prints durations in s, min and h.
#include "text_format.hpp"

#include <catch2/catch.hpp>

using contact::internal::FormatDuration;
using contact::internal::ProgressText;

TEST_CASE("durations are rounded to seconds and grouped in min and h", "[progress]") {
  CHECK(FormatDuration(0.4) == "0 s");
  CHECK(FormatDuration(59.4) == "59 s");
  CHECK(FormatDuration(125.0) == "2 min 05 s");
  CHECK(FormatDuration(3600.0 + 2 * 60 + 10) == "1 h 02 min");
  CHECK(FormatDuration(-1.0) == "0 s");
  CHECK(FormatDuration(1e300) == "277777777 h 46 min");  // clamped at 1e12 s, no overflow
}

TEST_CASE("progress text: percent, elapsed time and the extrapolated remaining time",
          "[progress]") {
  CHECK(ProgressText(0.0, 0.0) == "  0.0 %, 0 s elapsed, ETA --");
  CHECK(ProgressText(0.25, 10.0) ==
        " 25.0 %, 10 s elapsed, ETA 30 s");  // 10 (3/4) / (1/4)
  CHECK(ProgressText(0.1, 400.0) == " 10.0 %, 6 min 40 s elapsed, ETA 1 h 00 min");
  CHECK(ProgressText(1.0, 42.0) == "100.0 %, 42 s elapsed");
}
