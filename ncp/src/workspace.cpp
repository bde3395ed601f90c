// Solver::Workspace (workspace.hpp): row weights, the Jacobian J of Phi assembled from
// the problem's JE, JA, JB on a cached pattern, and products with J.

#include "workspace.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "format_number.hpp"

namespace ncp {
namespace {

using internal::FormatNumber;

// row_i *= weight_i for every stored entry of a compressed column-major matrix.
void ScaleRows(const Vector& weight, SparseMatrix* J) {
  double* values = J->valuePtr();
  const int* rows = J->innerIndexPtr();
  for (Eigen::Index k = 0; k < J->nonZeros(); ++k) values[k] *= weight(rows[k]);
}

// weight = 1 / (scale + floor / tolerance), checked; `what` names the vector in errors.
// (|row| weight <= tolerance  <=>  |row| <= floor + tolerance * scale; the weighted rows
// are relative residuals of order 1 at a typical point, which keeps the penalized FB
// function, not positively homogeneous, on data of order 1.)
void Weights(const Vector& scale, const Vector& floor, Eigen::Index size,
             double tolerance, const char* what, Vector* weight) {
  if (scale.size() != size || (floor.size() != 0 && floor.size() != size))
    throw std::invalid_argument(std::string("ncp::Solver: MixedProblem::Scales gave ") +
                                what + " of size " + std::to_string(scale.size()) +
                                " (floor " + std::to_string(floor.size()) +
                                "), expected " + std::to_string(size));
  weight->resize(size);
  for (Eigen::Index i = 0; i < size; ++i) {
    const double f = floor.size() ? floor(i) : 0.0;
    const double accuracy = tolerance > 0.0 ? scale(i) + f / tolerance : scale(i);
    if (!(scale(i) > 0.0) || !(f >= 0.0) || !std::isfinite(accuracy))
      throw std::invalid_argument(
          std::string("ncp::Solver: MixedProblem::Scales gave ") + what + "[" +
          std::to_string(i) + "] = " + FormatNumber("%.3e", scale(i)) + " with floor " +
          FormatNumber("%.3e", f) +
          ": scales must be finite and > 0, floors finite and >= 0");
    (*weight)(i) = 1.0 / accuracy;
  }
}

}  // namespace

void Solver::Workspace::Resize(int n, int m) {
  const int p = n - m;
  for (Vector* v : {&E, &Et}) v->setZero(m);
  for (Vector* v : {&A, &B, &At, &Bt, &da, &db, &za, &zb}) v->setZero(p);
  for (Vector* v : {&phi, &phi_trial, &grad, &d, &x_trial, &z, &newton_rhs,
                    &newton_residual, &newton_terms, &sensitivity})
    v->setZero(n);
  if (JE.rows() != m || JE.cols() != n) JE.resize(m, n);
  if (JA.rows() != p || JA.cols() != n) JA.resize(p, n);
  if (JB.rows() != p || JB.cols() != n) JB.resize(p, n);
}

bool Solver::Workspace::UpdatePattern(int m) {
  const SparseMatrix* sources[3] = {&JE, &JA, &JB};
  bool same = have_pattern;
  for (int s = 0; s < 3 && same; ++s) same = pattern[s].Matches(*sources[s]);
  if (same) return false;

  const Eigen::Index n = JE.cols();
  std::vector<Eigen::Triplet<double, int>> triplets;
  triplets.reserve(static_cast<size_t>(JE.nonZeros() + JA.nonZeros() + JB.nonZeros()));
  for (int s = 0; s < 3; ++s) {
    const SparseMatrix& S = *sources[s];
    const int row_offset = s == 0 ? 0 : m;
    for (int c = 0; c < S.outerSize(); ++c)
      for (SparseMatrix::InnerIterator it(S, c); it; ++it)
        triplets.emplace_back(static_cast<int>(it.row()) + row_offset, c, 0.0);
    pattern[s].Store(S);
  }
  J.resize(n, n);
  J.setFromTriplets(triplets.begin(), triplets.end());
  J.makeCompressed();
  for (int s = 0; s < 3; ++s) {
    const SparseMatrix& S = *sources[s];
    const int row_offset = s == 0 ? 0 : m;
    map[s].resize(static_cast<size_t>(S.nonZeros()));
    size_t k = 0;
    for (int c = 0; c < S.outerSize(); ++c) {
      const int* begin = J.innerIndexPtr() + J.outerIndexPtr()[c];
      const int* end = J.innerIndexPtr() + J.outerIndexPtr()[c + 1];
      for (SparseMatrix::InnerIterator it(S, c); it; ++it, ++k) {
        const int* pos =
            std::lower_bound(begin, end, static_cast<int>(it.row()) + row_offset);
        map[s][k] = static_cast<int>(pos - J.innerIndexPtr());
      }
    }
  }
  have_pattern = true;
  return true;
}

template <class Add>
void Solver::Workspace::ForEachJacobianEntry(int m, Add&& add) const {
  const SparseMatrix* sources[3] = {&JE, &JA, &JB};
  const Vector* scale[3] = {nullptr, &da, &db};
  for (int s = 0; s < 3; ++s) {
    const SparseMatrix& S = *sources[s];
    const int row_offset = s == 0 ? 0 : m;
    int k = 0;
    for (int c = 0; c < S.outerSize(); ++c)
      for (SparseMatrix::InnerIterator it(S, c); it; ++it, ++k)
        add(s, k, static_cast<int>(it.row()) + row_offset, c,
            scale[s] ? (*scale[s])(it.row()) * it.value() : it.value());
  }
}

void Solver::Workspace::FillDenseJacobian(int m, const Vector& x) {
  const Eigen::Index n = JE.cols();
  Jd.resize(n, n);
  Jd.setZero();
  sensitivity.setZero();
  ForEachJacobianEntry(m, [&](int, int, int row, int col, double value) {
    Jd(row, col) += value;
    sensitivity(row) += std::abs(value) * std::abs(x(col));
  });
}

void Solver::Workspace::MultiplyJacobianTransposed(const Vector& v, Vector* out) const {
  if (dense)
    out->noalias() = Jd.transpose() * v;
  else
    out->noalias() = J.transpose() * v;
}

double Solver::Workspace::ResidualAndTerms(const Vector& v, const Vector& b,
                                           Vector* residual, Vector* terms) const {
  *residual = b;
  terms->setZero();
  auto add = [&](Eigen::Index row, Eigen::Index col, double value) {
    (*residual)(row) += value * v(col);
    (*terms)(row) += std::abs(value * v(col));
  };
  if (dense) {
    for (Eigen::Index c = 0; c < Jd.cols(); ++c)
      for (Eigen::Index r = 0; r < Jd.rows(); ++r) add(r, c, Jd(r, c));
  } else {
    for (int c = 0; c < J.outerSize(); ++c)
      for (SparseMatrix::InnerIterator it(J, c); it; ++it) add(it.row(), c, it.value());
  }
  return terms->lpNorm<Eigen::Infinity>();
}

void Solver::Workspace::FillJacobian(int m, const Vector& x) {
  double* values = J.valuePtr();
  std::fill(values, values + J.nonZeros(), 0.0);
  sensitivity.setZero();
  ForEachJacobianEntry(m, [&](int s, int k, int row, int col, double value) {
    values[map[s][k]] += value;
    sensitivity(row) += std::abs(value) * std::abs(x(col));
  });
}

// (`scales` is kept between solves so that no vector is allocated again.)
void Solver::Workspace::SetWeights(MixedProblem& problem, const Vector& x0, int m, int p,
                                   double tolerance) {
  if (!problem.Scales(x0, &scales)) {
    weighted = false;  // weights untouched
    return;
  }
  Weights(scales.equation, scales.equation_floor, m, tolerance, "equation", &we);
  Weights(scales.a, scales.a_floor, p, tolerance, "a", &wa);
  Weights(scales.b, scales.b_floor, p, tolerance, "b", &wb);
  weighted = true;
}

void Solver::Workspace::WeightJacobianRows() {
  ScaleRows(we, &JE);
  ScaleRows(wa, &JA);
  ScaleRows(wb, &JB);
}

}  // namespace ncp
