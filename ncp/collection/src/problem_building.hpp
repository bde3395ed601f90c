// Internal: small helpers shared by the files that write out the collection's problems.
#pragma once

#include <initializer_list>
#include <limits>

#include "ncp/types.hpp"
#include "ncp_collection/test_problem.hpp"

namespace ncp::collection::internal {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// A vector from its entries, e.g. a start point written as in its source.
inline Vector Vec(std::initializer_list<double> values) {
  Vector v(static_cast<Eigen::Index>(values.size()));
  Eigen::Index i = 0;
  for (double value : values) v(i++) = value;
  return v;
}

/// l = 0, u = +inf: p becomes a standard NCP (p->F must be set).
inline void MakeStandardNcp(TestProblem* p) {
  const int n = p->NumVariables();
  p->lower = Vector::Zero(n);
  p->upper = Vector::Constant(n, kInf);
}

}  // namespace ncp::collection::internal
