#include "ncp/fc/problem.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace ncp::fc {

namespace {
// The message is built only when the check fails (Validate runs over every entry of W).
[[noreturn]] void Fail(const std::string& what) {
  throw std::invalid_argument("FrictionProblem: " + what);
}
}  // namespace

void FrictionProblem::Validate() const {
  if (dimension != 2 && dimension != 3)
    Fail("dimension must be 2 or 3, got " + std::to_string(dimension));
  if (num_contacts < 0)
    Fail("num_contacts must be >= 0, got " + std::to_string(num_contacts));
  const long n = size();
  if (W.rows() != n || W.cols() != n)
    Fail("W must be " + std::to_string(n) + " x " + std::to_string(n) + ", got " +
         std::to_string(W.rows()) + " x " + std::to_string(W.cols()));
  if (q.size() != n)
    Fail("q must have " + std::to_string(n) + " entries, got " +
         std::to_string(q.size()));
  if (mu.size() != num_contacts)
    Fail("mu must have " + std::to_string(num_contacts) + " entries, got " +
         std::to_string(mu.size()));
  if (!q.allFinite()) Fail("q has a non-finite entry");
  for (int k = 0; k < W.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(W, k); it; ++it)
      if (!std::isfinite(it.value()))
        Fail("W has a non-finite entry at (" + std::to_string(it.row()) + ", " +
             std::to_string(it.col()) + ")");
  for (int a = 0; a < num_contacts; ++a)
    if (!(std::isfinite(mu[a]) && mu[a] >= 0.0))
      Fail("mu[" + std::to_string(a) + "] must be finite and >= 0, got " +
           std::to_string(mu[a]));
}

}  // namespace ncp::fc
