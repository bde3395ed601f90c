// printf-style formatting of one number into a std::string, for the messages of Options,
// Summary and the iteration (ncp::Solver, ncp::petsc::Solver).
#pragma once

#include <cstdio>
#include <string>

namespace ncp::internal {

inline std::string FormatNumber(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

}  // namespace ncp::internal
