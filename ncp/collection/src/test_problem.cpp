#include "ncp_collection/test_problem.hpp"

#include <algorithm>
#include <cmath>

namespace ncp::collection {

bool ExpectedFailure::AppliesTo(const std::string& label, NcpFunction function) const {
  if (label != start_label) return false;
  return functions.empty() ||
         std::find(functions.begin(), functions.end(), function) != functions.end();
}

bool TestProblem::IsStandardNcp() const {
  for (Eigen::Index i = 0; i < lower.size(); ++i) {
    if (lower(i) != 0.0 || !(std::isinf(upper(i)) && upper(i) > 0)) return false;
  }
  return lower.size() == NumVariables() && upper.size() == NumVariables();
}

const ExpectedFailure* TestProblem::FindExpectedFailure(const std::string& start_label,
                                                        NcpFunction function) const {
  for (const ExpectedFailure& failure : expected_failures) {
    if (failure.AppliesTo(start_label, function)) return &failure;
  }
  return nullptr;
}

}  // namespace ncp::collection
