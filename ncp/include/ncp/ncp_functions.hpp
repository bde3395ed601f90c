/// \file ncp_functions.hpp
/// Scalar NCP functions phi : R^2 -> R with phi(a, b) = 0 <=> a >= 0, b >= 0, a b = 0.
#pragma once

namespace ncp {

/// phi_FB(a, b) = sqrt(a^2 + b^2) - (a + b)   (Fischer 1992; thesis eq. 17).
double FischerBurmeister(double a, double b);

/// phi_min(a, b) = min(a, b)   (thesis eq. 16).
double MinFunction(double a, double b);

/// phi_lambda(a, b) = lambda phi_FB(a, b) - (1 - lambda) max(a, 0) max(b, 0)
/// (Chen, Chen and Kanzow 2000), lambda in (0, 1].
double PenalizedFischerBurmeister(double a, double b, double lambda);

}  // namespace ncp
