#include "ncp/ncp_functions.hpp"

#include <algorithm>
#include <cmath>

#include "ncp_function_internal.hpp"

namespace ncp {

double FischerBurmeister(double a, double b) {
  // sqrt(a^2 + b^2) - (a + b) cancels when a >> b > 0 (e.g. a large gap and a small
  // force); for a + b > 0 the equal form -2ab / (sqrt(a^2 + b^2) + a + b) does not.
  const double r = std::hypot(a, b);
  return a + b > 0.0 ? -2.0 * a * b / (r + a + b) : r - (a + b);
}

double MinFunction(double a, double b) { return std::min(a, b); }

double PenalizedFischerBurmeister(double a, double b, double lambda) {
  return lambda * FischerBurmeister(a, b) -
         (1.0 - lambda) * std::max(a, 0.0) * std::max(b, 0.0);
}

namespace internal {

double PhiValue(NcpFunction f, double lambda, double a, double b) {
  switch (f) {
    case NcpFunction::kFischerBurmeister:
      return FischerBurmeister(a, b);
    case NcpFunction::kMin:
      return MinFunction(a, b);
    case NcpFunction::kPenalizedFischerBurmeister:
      return PenalizedFischerBurmeister(a, b, lambda);
  }
  return std::nan("");
}

PhiPartials PhiDerivatives(NcpFunction f, double lambda, double a, double b,
                           bool degenerate, double za, double zb, bool min_tie_takes_b) {
  // FB part: (d phi / da, d phi / db) = (a / r - 1, b / r - 1), r = ||(a, b)||  (DFK eq.
  // 26). On the degenerate set (a = b = 0) the B-subdifferential element of DFK eq. (27)
  // uses the directional values za = grad A' z, zb = grad B' z in place of (a, b).
  auto fb_partials = [&](double p, double q) {
    const double r = std::hypot(p, q);
    if (r == 0.0) {
      // grad A' z = grad B' z = 0: any (alpha, beta) on the unit circle gives an element
      // of the generalized Jacobian (thesis eq. 30); we take alpha = beta = 1/sqrt(2).
      const double s = std::sqrt(0.5) - 1.0;
      return PhiPartials{s, s};
    }
    return PhiPartials{p / r - 1.0, q / r - 1.0};
  };
  switch (f) {
    case NcpFunction::kFischerBurmeister:
      return degenerate ? fb_partials(za, zb) : fb_partials(a, b);
    case NcpFunction::kMin:
      // B-subdifferential of min: grad A where a < b, grad B where b < a; at a tie a = b
      // either is an element, chosen by Options::min_tie_takes_b.
      if (b < a || (a == b && min_tie_takes_b)) return PhiPartials{0.0, 1.0};
      return PhiPartials{1.0, 0.0};
    case NcpFunction::kPenalizedFischerBurmeister: {
      // d/da [a+ b+] = [a > 0] b+, d/db = a+ [b > 0] (one B-subdifferential element).
      const PhiPartials fb = degenerate ? fb_partials(za, zb) : fb_partials(a, b);
      const double ap = std::max(a, 0.0), bp = std::max(b, 0.0);
      return PhiPartials{lambda * fb.da - (1.0 - lambda) * (a > 0.0 ? bp : 0.0),
                         lambda * fb.db - (1.0 - lambda) * (b > 0.0 ? ap : 0.0)};
    }
  }
  return PhiPartials{std::nan(""), std::nan("")};
}

}  // namespace internal
}  // namespace ncp
