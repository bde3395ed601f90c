// The Newton KSP's convergence test tied to the outer stopping test.
#pragma once

#include <petscksp.h>

#include "petsc_support.hpp"

namespace ncp::petsc {

// The Krylov solve of a Newton system continued past the KSP's own test (rtol, atol)
// until its residual, in the units of Phi, passes the outer stopping test with the margin
// `fraction` (-<prefix>newton_residual_fraction, docs/petsc.md): every row
//
//   |w_r (b - A d)_r| <= fraction (tolerance + roundoff_ulps eps s_r),
//
// with w_r the factor from the KSP's row r to the row of J d + Phi (1, or in symmetric
// mode c_F,r on a kept row and c_I,r on an eliminated one) and s_r the round-off
// sensitivity of the stopping test at x. Where the Newton matrix does not change between
// x and x + d (the min function on a linear F with an unchanged active set) Phi(x + d) =
// J d + Phi exactly, so the step that lands on the final active set is also the last one;
// elsewhere Phi(x + d) differs by O(||d||^2) terms, for which 1 - fraction of the
// tolerance is left. The residual is formed (KSPBuildResidual: one product with A) only
// once the KSP's own test has passed. Margin of the Newton KSP's test against the outer
// stopping test (OuterResidualTest): half the tolerance for the linear residual, half for
// what the step changes beyond it. By default only for the min function, whose Phi(x + d)
// is J d + Phi on every row whose active side does not change; for FB and penalized FB
// the O(||d||^2) remainder decides, and continued solves only cost iterations
// (docs/petsc.md).
constexpr double kDefaultResidualFraction = 0.5;

class OuterResidualTest {
 public:
  ~OuterResidualTest() {
    if (default_context_) KSPConvergedDefaultDestroy(default_context_);
  }
  double fraction() const { return fraction_; }
  // Whether it applies to a Newton system of `function`: the min function by default,
  // every function when -<prefix>newton_residual_fraction was given.
  bool AppliesTo(NcpFunction function) const {
    return fraction_ > 0.0 && (explicit_ || function == NcpFunction::kMin);
  }
  long long continued() const { return continued_; }
  void ResetCount() { continued_ = 0; }

  // The test in place of ksp's (after KSPSetFromOptions); fraction 0 leaves ksp's own.
  void Install(KSP ksp, double fraction, bool given) {
    fraction_ = fraction;
    explicit_ = given;
    if (fraction_ == 0.0) return;
    NCP_PETSC_CHECK(KSPConvergedDefaultCreate(&default_context_));
    NCP_PETSC_CHECK(
        KSPSetConvergenceTest(ksp, &OuterResidualTest::Converged, this, nullptr));
  }

  // The rows' weights w and bounds for the next solve (Vecs laid out like its right-hand
  // side, kept by the caller until Disarm), and two work vectors of that layout.
  void Arm(Vec weight, Vec bound, Vec residual, Vec work) {
    weight_ = weight;
    bound_ = bound;
    residual_ = residual;
    work_ = work;
  }
  void Disarm() { weight_ = bound_ = residual_ = work_ = nullptr; }

 private:
  static PetscErrorCode Converged(KSP ksp, PetscInt it, PetscReal rnorm,
                                  KSPConvergedReason* reason, void* context) {
    auto* self = static_cast<OuterResidualTest*>(context);
    PetscCall(KSPConvergedDefault(ksp, it, rnorm, reason, self->default_context_));
    if (*reason <= 0 || !self->weight_) return 0;
    Vec r = nullptr;
    PetscCall(KSPBuildResidual(ksp, self->work_, self->residual_, &r));
    PetscCall(VecPointwiseMult(self->work_, r, self->weight_));
    PetscCall(VecAbs(self->work_));
    PetscCall(VecPointwiseDivide(self->work_, self->work_, self->bound_));
    PetscReal largest = 0.0;
    PetscCall(VecMax(self->work_, nullptr, &largest));
    if (largest > 1.0) {
      *reason = KSP_CONVERGED_ITERATING;
      ++self->continued_;
    }
    return 0;
  }

  double fraction_ = 0.0;
  bool explicit_ = false;  // given in the options database
  void* default_context_ = nullptr;
  Vec weight_ = nullptr, bound_ = nullptr, residual_ = nullptr, work_ = nullptr;
  long long continued_ = 0;  // iterations past the KSP's own test
};

}  // namespace ncp::petsc
