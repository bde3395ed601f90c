// printf-style formatting of one number into a std::string, for the messages of Options,
// Summary and the iteration (ncp::Solver, ncp::petsc::Solver).
#pragma once

#include <charconv>
#include <cstdio>
#include <string>

namespace ncp::internal {

/// "%.<d>e" (d one digit) goes through std::to_chars, which the standard defines to
/// print as printf does in the C locale, at a fraction of snprintf's cost (the converged
/// message of every small solve formats two or three numbers); other formats through
/// snprintf.
inline std::string FormatNumber(const char* format, double value) {
  char buffer[64];
  if (format[0] == '%' && format[1] == '.' && format[2] >= '0' && format[2] <= '9' &&
      format[3] == 'e' && format[4] == '\0') {
    const std::to_chars_result r =
        std::to_chars(buffer, buffer + sizeof buffer, value,
                      std::chars_format::scientific, format[2] - '0');
    if (r.ec == std::errc()) return std::string(buffer, r.ptr);
  }
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

}  // namespace ncp::internal
