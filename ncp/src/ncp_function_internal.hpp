#pragma once

#include "ncp/types.hpp"

namespace ncp::internal {

/// phi(a, b) for the chosen NCP function.
double PhiValue(NcpFunction f, double lambda, double a, double b);

/// Coefficients (da, db) of one B-subdifferential element of phi(A(x), B(x)):
/// row = da grad A' + db grad B'. `degenerate` marks a in gamma (a = b = 0), where the
/// FB element follows the z-vector rule with za = grad A' z, zb = grad B' z (DFK eq. 27).
struct PhiPartials {
  double da;
  double db;
};
PhiPartials PhiDerivatives(NcpFunction f, double lambda, double a, double b,
                           bool degenerate, double za, double zb, bool min_tie_takes_b);

}  // namespace ncp::internal
