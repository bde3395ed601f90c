#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cstdio>
#include <sstream>
#include <string>

namespace contact::internal {

/// A number with all 17 significant digits, for error messages (round trip exact).
inline std::string Format(double value) {
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

/// A number with 6 significant digits ("1e-300", "2.5e+06"), for limits and ranges.
inline std::string FormatShort(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

/// A duration for people: "42 s", "3 min 05 s", "1 h 02 min".
inline std::string FormatDuration(double seconds) {
  const long s = seconds > 0 ? static_cast<long>(std::min(seconds, 1e12) + 0.5)
                             : 0;  // (no overflow)
  char text[48];
  if (s < 60)
    std::snprintf(text, sizeof text, "%ld s", s);
  else if (s < 3600)
    std::snprintf(text, sizeof text, "%ld min %02ld s", s / 60, s % 60);
  else
    std::snprintf(text, sizeof text, "%ld h %02ld min", s / 3600, (s % 3600) / 60);
  return text;
}

/// "37.5 %, 12 s elapsed, ETA 20 s" for a run `fraction` in [0, 1] done after elapsed_s:
/// the remaining time extrapolated at the mean rate so far, elapsed (1 - f) / f (the same
/// text as the Python package's progress bar, contact.progress_text).
inline std::string ProgressText(double fraction, double elapsed_s) {
  char percent[16];
  std::snprintf(percent, sizeof percent, "%5.1f %%", 100.0 * fraction);
  std::string text = std::string(percent) + ", " + FormatDuration(elapsed_s) + " elapsed";
  if (fraction >= 1.0) return text;
  if (fraction > 0.0)
    return text + ", ETA " + FormatDuration(elapsed_s * (1.0 - fraction) / fraction);
  return text + ", ETA --";
}

/// "(v0, v1, ...)" with Format for each entry.
inline std::string Format(const Eigen::VectorXd& v) {
  std::string out = "(";
  for (Eigen::Index i = 0; i < v.size(); ++i) out += (i ? ", " : "") + Format(v(i));
  return out + ")";
}

}  // namespace contact::internal
