#pragma once

#include <Eigen/Core>
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

/// "(v0, v1, ...)" with Format for each entry.
inline std::string Format(const Eigen::VectorXd& v) {
  std::string out = "(";
  for (Eigen::Index i = 0; i < v.size(); ++i) out += (i ? ", " : "") + Format(v(i));
  return out + ")";
}

}  // namespace contact::internal
