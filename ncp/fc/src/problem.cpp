#include "ncp/fc/problem.hpp"

#include <stdexcept>
#include <string>

namespace ncp::fc {

namespace {
void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("FrictionProblem: " + what);
}
}  // namespace

void FrictionProblem::Validate() const {
  Require(dimension == 2 || dimension == 3,
          "dimension must be 2 or 3, got " + std::to_string(dimension));
  Require(num_contacts >= 0,
          "num_contacts must be >= 0, got " + std::to_string(num_contacts));
  const long n = size();
  Require(W.rows() == n && W.cols() == n,
          "W must be " + std::to_string(n) + " x " + std::to_string(n) + ", got " +
              std::to_string(W.rows()) + " x " + std::to_string(W.cols()));
  Require(q.size() == n, "q must have " + std::to_string(n) + " entries, got " +
                             std::to_string(q.size()));
  Require(mu.size() == num_contacts, "mu must have " + std::to_string(num_contacts) +
                                         " entries, got " + std::to_string(mu.size()));
  Require(q.allFinite(), "q has a non-finite entry");
  for (int k = 0; k < W.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(W, k); it; ++it)
      Require(std::isfinite(it.value()), "W has a non-finite entry at (" +
                                             std::to_string(it.row()) + ", " +
                                             std::to_string(it.col()) + ")");
  for (int a = 0; a < num_contacts; ++a)
    Require(std::isfinite(mu[a]) && mu[a] >= 0.0, "mu[" + std::to_string(a) +
                                                      "] must be finite and >= 0, got " +
                                                      std::to_string(mu[a]));
}

}  // namespace ncp::fc
