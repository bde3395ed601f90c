#include "ncp_collection/mixed_examples.hpp"

#include <algorithm>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace ncp::collection {
namespace {

// KKT system of  min 1/2 ||x - a||^2  s.t.  sum x = 1, x >= 0,  unknowns (y, x):
// stationarity x - a - y 1 - mu = 0 with mu = B(y, x) >= 0 perp x >= 0.
class SimplexProjectionProblem : public MixedProblem {
 public:
  explicit SimplexProjectionProblem(Vector a) : a_(std::move(a)) {}

  int NumVariables() const override { return static_cast<int>(a_.size()) + 1; }
  int NumEquations() const override { return 1; }

  bool Evaluate(const Vector& z, Vector* E, Vector* A, Vector* B) override {
    const int k = static_cast<int>(a_.size());
    const double y = z(0);
    const auto x = z.tail(k);
    (*E)(0) = x.sum() - 1.0;               // E = sum_j x_j - 1
    *A = x;                                // A_j = x_j
    *B = x - a_ - Vector::Constant(k, y);  // B_j = x_j - a_j - y
    return true;
  }

  bool Jacobian(const Vector& /*z*/, SparseMatrix* JE, SparseMatrix* JA,
                SparseMatrix* JB) override {
    const int k = static_cast<int>(a_.size());
    const int n = k + 1;
    std::vector<Eigen::Triplet<double, int>> t;
    // dE/dz = (0, 1, ..., 1); the 0 for y is stored explicitly (fixed pattern).
    t.emplace_back(0, 0, 0.0);
    for (int j = 0; j < k; ++j) t.emplace_back(0, 1 + j, 1.0);
    JE->resize(1, n);
    JE->setFromTriplets(t.begin(), t.end());
    t.clear();
    for (int j = 0; j < k; ++j) t.emplace_back(j, 1 + j, 1.0);  // dA_j/dx_j = 1
    JA->resize(k, n);
    JA->setFromTriplets(t.begin(), t.end());
    t.clear();
    for (int j = 0; j < k; ++j) {
      t.emplace_back(j, 0, -1.0);     // dB_j/dy = -1
      t.emplace_back(j, 1 + j, 1.0);  // dB_j/dx_j = 1
    }
    JB->resize(k, n);
    JB->setFromTriplets(t.begin(), t.end());
    return true;
  }

 private:
  Vector a_;
};

}  // namespace

MixedTestProblem SimplexProjection(const Vector& a) {
  const int k = static_cast<int>(a.size());
  if (k < 1)
    throw std::invalid_argument("SimplexProjection: a is empty, expected size >= 1");

  // tau by sorting (Duchi, Shalev-Shwartz, Singer and Chandra, ICML 2008, Fig. 1):
  // with u = a sorted decreasingly, rho = max{ j : u_j - (sum_{r<=j} u_r - 1)/j > 0 } and
  // tau = (sum_{r<=rho} u_r - 1)/rho; then x = max(a - tau, 0).
  std::vector<double> u(a.data(), a.data() + k);
  std::sort(u.begin(), u.end(), std::greater<double>());
  double partial = 0.0, tau = 0.0;
  for (int j = 0; j < k; ++j) {
    partial += u[j];
    const double candidate = (partial - 1.0) / (j + 1);
    if (u[j] - candidate > 0.0) tau = candidate;
  }
  Vector solution(k + 1);
  solution(0) = -tau;
  solution.tail(k) = (a.array() - tau).cwiseMax(0.0);

  MixedTestProblem p;
  p.name = "simplex-projection-" + std::to_string(k);
  p.source =
      "KKT system of the Euclidean projection onto the unit simplex (Held, Wolfe and "
      "Crowder 1974; closed form by sorting, Duchi et al. 2008)";
  p.problem = std::make_unique<SimplexProjectionProblem>(a);
  Vector uniform(k + 1);
  uniform(0) = 0.0;
  uniform.tail(k).setConstant(1.0 / k);
  p.starts = {{"zero", Vector::Zero(k + 1)}, {"uniform", uniform}};
  p.solutions = {solution};
  p.notes = "unknowns (y, x_1..x_k): 1 equation (variable y), k pairs (variables x_j)";
  return p;
}

}  // namespace ncp::collection
