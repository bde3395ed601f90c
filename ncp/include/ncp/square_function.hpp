/// \file square_function.hpp
/// Problems given by one function F : R^n -> R^n: the standard NCP
///     x >= 0,  F(x) >= 0,  x' F(x) = 0
/// and the box-constrained mixed complementarity problem (MCP)
///     l <= x <= u  perp  F(x):  for every i one of
///         x_i = l_i and F_i(x) >= 0,   x_i = u_i and F_i(x) <= 0,
///         l_i < x_i < u_i and F_i(x) = 0,
/// with l_i = -inf and/or u_i = +inf allowed (a free variable is an equation F_i = 0).
#pragma once

#include <functional>

#include "ncp/types.hpp"

namespace ncp {

/// F : R^n -> R^n with its sparse Jacobian.
class SquareFunction {
 public:
  virtual ~SquareFunction() = default;
  virtual int NumVariables() const = 0;
  /// F(x) into *F (already sized n). false = cannot evaluate at x (line search shortens).
  virtual bool Evaluate(const Vector& x, Vector* F) = 0;
  /// dF/dx (n x n). Keep the sparsity pattern fixed between calls.
  virtual bool Jacobian(const Vector& x, SparseMatrix* J) = 0;
  /// true when F(x) = M x + q (an LCP / box LCP): a box MCP solve that gets stuck then
  /// checks whether the problem has no solution at all (TerminationType::kInfeasible, a
  /// Farkas certificate; box_mcp.cpp). Default false: nothing is claimed about F.
  virtual bool IsAffine() const { return false; }
};

/// Convenience for small problems: F and a dense Jacobian given as callables.
class DenseSquareFunction : public SquareFunction {
 public:
  using ResidualFn = std::function<bool(const Vector& x, Vector* F)>;
  using JacobianFn = std::function<bool(const Vector& x, DenseMatrix* J)>;

  DenseSquareFunction(int n, ResidualFn residual, JacobianFn jacobian);

  int NumVariables() const override { return n_; }
  bool Evaluate(const Vector& x, Vector* F) override { return residual_(x, F); }
  /// Stores all n^2 entries (explicit zeros included) so the pattern never changes.
  bool Jacobian(const Vector& x, SparseMatrix* J) override;

 private:
  int n_;
  ResidualFn residual_;
  JacobianFn jacobian_;
  DenseMatrix dense_;
};

}  // namespace ncp
