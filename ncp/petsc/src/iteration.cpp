// ncp::petsc::Solver: Algorithm 1 of the thesis (section 3.1), the globalized semismooth
// Newton method of De Luca, Facchinei and Kanzow (1996), over distributed PETSc Vec/Mat:
// the iteration of one solve on the rows of the mixed form (mixed_layout.hpp).
//
// Every decision (z-vector rule, descent test, Armijo, restarts, stopping tests) is taken
// by the functions of ncp/src/globalization.hpp and ncp_function_internal.hpp, the serial
// solver's own, from norms and dot products reduced over the communicator: every rank
// takes the same decision, so no rank can wait in a collective call the others skipped.

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "globalization.hpp"
#include "huge_page_memory.hpp"
#include "log_events.hpp"
#include "mumps_factor.hpp"
#include "ncp_function_internal.hpp"
#include "rank_revealing.hpp"
#include "semismooth_newton.hpp"
#include "solver_impl.hpp"
#include "strategy.hpp"

namespace ncp::petsc {

// ---------------------------------------------------------------------------------------
// One solve, phase by phase: the PETSc back end of Algorithm 1. The loop and its
// decisions are internal::SemismoothNewton's (semismooth_newton.hpp), the serial
// solver's own; this class supplies the distributed vector and matrix work.

class Iteration : public internal::SemismoothNewton<Iteration> {
 public:
  Iteration(Solver::Impl& impl, const BoxMcp& problem, Vec x, Summary& summary,
            const MixedLayout& layout)
      : SemismoothNewton(impl.options, summary, armijo_reference_, stagnation_,
                         schedule_),
        impl_(impl),
        comm_(impl.comm),
        p_(problem),
        x_(x),
        layout_(layout),
        lower_(layout.lower),
        upper_(layout.upper),
        local_(layout.LocalRows()) {}

  // The solve; x holds the x part of the last iterate afterwards.
  void Run() {
    SemismoothNewton::Run();
    if (layout_.total_slacks > 0) CopyXPart(y_, x_);
  }

 private:
  friend class internal::SemismoothNewton<Iteration>;
  using Direction = internal::Direction;
  struct LineSearchScope {
    LogScope scope{SolverLogEvents().line_search};
  };

  // ---- Start: work vectors, Phi(x^0)
  // ---------------------------------------------------
  bool Start() {
    LogScope scope(SolverLogEvents().start);
    start_ = Clock::now();
    InitializeSummary();
    y_ = x_;
    if (layout_.total_slacks > 0) {
      y_owned_.Create(comm_, local_);
      y_ = y_owned_;
    }
    impl_.Configure();
    MakeWorkVectors();
    NCP_PETSC_CHECK(VecSet(sensitivity_, 0.0));  // no round-off floor: stays 0
    const bool new_matrix = impl_.PrepareNewtonMatrix(p_.jacobian_matrix, layout_);
    G_ = impl_.SourceMatrix(p_.jacobian_matrix);
    summary_.symbolic_factorizations = new_matrix ? 1 : 0;
    if (new_matrix && DetectsNullPivots())
      ResetFactorization(impl_.ksp, impl_.newton, impl_.newton_workspace_percent);
    impl_.DescribeKsp();
    ResetStrategies();
    progress_.ResetRecord(options_, summary_.num_variables);
    if (options_.hybrid) best_y_.DuplicateOf(y_);
    impl_.report.linear_iterations = 0;
    impl_.report.residual_test_iterations = 0;
    impl_.outer_test.ResetCount();
    if (layout_.total_slacks > 0) {
      CopyXPart(x_, y_);
      if (!SetSlacks(y_)) {
        NCP_PETSC_CHECK(VecSet(phi_, std::numeric_limits<double>::quiet_NaN()));
        Finish(TerminationType::kEvaluationFailure,
               "F cannot be evaluated (or is not finite) at the start point");
        return false;
      }
    }
    if (!Evaluate(y_, f_, phi_)) {
      NCP_PETSC_CHECK(VecSet(phi_, std::numeric_limits<double>::quiet_NaN()));
      Finish(TerminationType::kEvaluationFailure,
             "the problem cannot be evaluated at the start point");
      return false;
    }
    const bool finite = ReducePhi(phi_, &phi_inf_, &psi_);
    summary_.initial_phi_inf = phi_inf_;
    if (!finite) {
      Finish(TerminationType::kNonFiniteValues, "Phi(x0) has NaN or Inf entries");
      return false;
    }
    ResetMemories();
    return true;
  }

  // The work vectors: those laid out like x in one block of memory, those laid out like y
  // in another (huge_page_memory.hpp: on a new grid their first touch is most of the
  // cost), or by VecDuplicate for Vec types other than the standard ones.
  void MakeWorkVectors() {
    std::vector<OwnedVec*> like_x = {&f_, &f_trial_};
    if (layout_.total_slacks > 0) like_x.push_back(&x_part_);
    std::vector<OwnedVec*> like_y = {
        &phi_, &phi_trial_, &grad_, &d_,     &x_trial_,      &c_f_,    &c_i_,
        &z_,   &f_z_,       &work_, &work2_, &fixed_values_, &diag_g_, &sensitivity_};
    if (impl_.outer_test.fraction() > 0.0)
      like_y.insert(like_y.end(),
                    {&ksp_row_weight_, &ksp_row_bound_, &ksp_residual_, &ksp_work_});
    for (const auto& [layout, vectors] :
         {std::make_pair(Vec(x_), &like_x), std::make_pair(Vec(y_), &like_y)}) {
      std::vector<Vec> made(vectors->size(), nullptr);
      const bool in_block =
          CreateVecsInBlock(layout, static_cast<int>(made.size()), made.data());
      for (size_t k = 0; k < made.size(); ++k) {
        if (in_block)
          (*vectors)[k]->Adopt(made[k]);
        else
          (*vectors)[k]->DuplicateOf(layout);
      }
    }
  }

  void InitializeSummary() {
    long long equations = 0;
    for (Row r : layout_.rows)
      equations += r == Row::kFree || r == Row::kFixed || r == Row::kSplit;
    StartSummary(static_cast<int>(SumRanks(comm_, local_)),
                 static_cast<int>(SumRanks(comm_, equations)));
    summary_.linear_solver_requested = summary_.linear_solver_used =
        LinearSolverType::kAuto;
    summary_.predicted_factorization_flops =
        std::numeric_limits<double>::quiet_NaN();  // none predicted
  }

  // ---- Phi(x) row by row (mixed_layout.hpp); false when F cannot be evaluated (a rank)
  bool Evaluate(Vec point, Vec f, Vec phi) {
    LogScope scope(SolverLogEvents().evaluate);
    ++summary_.residual_evaluations;
    const auto t0 = Clock::now();
    const PetscErrorCode code = p_.residual(XPart(point), f);
    summary_.evaluation_time_s += Seconds(t0);
    if (AnyRank(comm_, code != 0)) return false;
    LocalRead ya(point), fa(f);
    LocalWrite out(phi);
    for (PetscInt r = 0; r < local_; ++r) {
      const auto rr = static_cast<size_t>(r);
      double a = 0.0, b = 0.0;
      if (layout_.PairValues(r, ya, fa, &a, &b)) {
        out[r] = internal::PhiValue(function_, options_.penalized_fb_lambda, a, b);
        continue;
      }
      const Row row = layout_.row(r);
      if (row == Row::kFree) out[r] = fa[r];
      if (row == Row::kFixed) out[r] = ya[r] - lower_[rr];
      if (row == Row::kSplit) {
        const PetscInt k = layout_.Link(r);
        out[r] = fa[r] - ya[layout_.WRow(k)] + ya[layout_.VRow(k)];
      }
    }
    return true;
  }

  // The x part of the unknowns y (y itself without slacks; else a copy in x_part_).
  Vec XPart(Vec y) {
    if (layout_.total_slacks == 0) return y;
    CopyXPart(y, x_part_);
    return x_part_;
  }
  // The local x entries from one layout to the other (y -> x or x -> y).
  void CopyXPart(Vec from, Vec to) {
    LocalRead a(from);
    LocalWrite b(to);
    for (PetscInt i = 0; i < layout_.components; ++i) b[i] = a[i];
  }

  // The slacks of y from F at its x part: w = max(F_i, 0), v = max(-F_i, 0)
  // (box_mcp.cpp's InitialSlacks, an evaluation not counted in the Summary); false when F
  // cannot be evaluated or is not finite there.
  bool SetSlacks(Vec y) {
    if (AnyRank(comm_, p_.residual(XPart(y), f_trial_) != 0) ||
        !AllFinite(comm_, f_trial_))
      return false;
    LocalRead fa(f_trial_);
    LocalWrite ya(y);
    for (PetscInt r = 0; r < layout_.components; ++r) {
      if (layout_.row(r) != Row::kSplit) continue;
      const PetscInt k = layout_.Link(r);
      ya[layout_.WRow(k)] = std::max(fa[r], 0.0);
      ya[layout_.VRow(k)] = std::max(-fa[r], 0.0);
    }
    return true;
  }

  // ---- J^k in the B-subdifferential and grad psi = J' Phi (eq. 24) --------------------
  // false only when the solve has finished (non-finite Jacobian).
  bool EvaluateJacobian(int k) {
    LogScope scope(SolverLogEvents().jacobian);
    ++summary_.jacobian_evaluations;
    const long long degenerate = MarkDegenerateSet();
    const auto t0 = Clock::now();
    const bool failed = p_.jacobian(XPart(y_), p_.jacobian_matrix) != 0;
    summary_.evaluation_time_s += Seconds(t0);
    bool finite = true;
    if (!failed)
      ForEachLocalValue<false>(p_.jacobian_matrix, [&](const PetscScalar& v) {
        finite = finite && std::isfinite(PetscRealPart(v));
      });
    // Callback failures, non-finite entries and the degenerate pairs: one reduction.
    const std::array<long long, 3> counts =
        SumRanks<3>(comm_, {failed ? 1 : 0, finite ? 0 : 1, degenerate});
    iterate_.jacobian_ok = counts[0] == 0;
    if (!iterate_.jacobian_ok) return true;
    if (counts[1] > 0) {
      Finish(TerminationType::kNonFiniteValues,
             "the Jacobian has NaN or Inf entries at iteration " + std::to_string(k));
      return false;
    }
    iterate_.degenerate_count = static_cast<int>(counts[2]);
    if (layout_.total_slacks > 0) impl_.slack.Refresh(p_.jacobian_matrix, layout_);
    GDiagonalAtA();
    PhiPartials();
    if (!impl_.symmetric_newton) FillNewtonMatrix(impl_.newton);  // else by Symmetrize
    // grad psi = J' Phi = G' (c_F Phi) + c_I,r Phi_r added at y_AColumn(r)
    NCP_PETSC_CHECK(VecPointwiseMult(work_, c_f_, phi_));
    NCP_PETSC_CHECK(MatMultTranspose(G_, work_, grad_));
    {
      LocalRead c_i(c_i_), phi(phi_);
      LocalWrite grad(grad_);
      for (PetscInt r = 0; r < local_; ++r)
        grad[layout_.AColumn(r)] += c_i[r] * PetscRealPart(phi[r]);
    }
    return true;
  }

  // diag_g_ = G_{r, AColumn(r)}: the diagonal of G (of F') on the rows of x, 0 on the
  // slack rows (G's stored zeros at (w, i) and (v, i)).
  void GDiagonalAtA() {
    NCP_PETSC_CHECK(MatGetDiagonal(G_, diag_g_));
    LocalWrite diag(diag_g_);
    for (PetscInt r = layout_.components; r < local_; ++r) diag[r] = 0.0;
  }

  // The z-vector rule's set gamma at y (DFK 1996, eq. 27): z = 1 at the variable of every
  // degenerate pair (the row's own unknown), 0 elsewhere; returns this rank's count.
  long long MarkDegenerateSet() {
    long long degenerate = 0;
    LocalRead ya(y_), fa(f_);
    LocalWrite z(z_);
    for (PetscInt r = 0; r < local_; ++r) {
      z[r] = 0.0;
      double a = 0.0, b = 0.0;
      if (!layout_.PairValues(r, ya, fa, &a, &b)) continue;
      if (internal::InDegenerateSet(function_, options_.degenerate_tolerance, a, b)) {
        z[r] = 1.0;
        ++degenerate;
      }
    }
    return degenerate;
  }

  // c_F, c_I of every row (c_I: the coefficient of the A side, c_A of mixed_layout.hpp on
  // a slack row): the partials (da, db) of phi at (A_r, B_r) with the signs of A and B,
  // the z-vector rule on the degenerate set (z_ and iterate_.degenerate_count of
  // MarkDegenerateSet): za = A' z = +-z_AColumn(r), zb = B' z = +-(G z)_r.
  void PhiPartials() {
    if (iterate_.degenerate_count > 0) NCP_PETSC_CHECK(MatMult(G_, z_, f_z_));
    LocalRead ya(y_), fa(f_), z(z_);
    std::unique_ptr<LocalRead> fz(iterate_.degenerate_count > 0 ? new LocalRead(f_z_)
                                                                : nullptr);
    LocalWrite c_f(c_f_), c_i(c_i_);
    for (PetscInt r = 0; r < local_; ++r) {
      const Row row = layout_.row(r);
      double a = 0.0, b = 0.0;
      if (!layout_.PairValues(r, ya, fa, &a, &b)) {
        c_f[r] = row == Row::kFixed ? 0.0 : 1.0;
        c_i[r] = row == Row::kFixed ? 1.0 : 0.0;
        continue;
      }
      // A = +-(x_i - bound), B = +-F_i or the slack.
      const double sign_a = row == Row::kLower || row == Row::kLowerSlack ? 1.0 : -1.0;
      const double sign_b = row == Row::kUpper ? -1.0 : 1.0;
      const bool gamma = z[r] == 1.0;
      const internal::PhiPartials dp = internal::PhiDerivatives(
          function_, options_.penalized_fb_lambda, a, b, gamma,
          gamma ? sign_a * z[layout_.AColumn(r)] : 0.0, gamma ? sign_b * (*fz)[r] : 0.0,
          options_.min_tie_takes_b);
      c_i[r] = sign_a * dp.da;
      c_f[r] = sign_b * dp.db;
    }
  }

  // out = J v: out_r = c_F,r (G v)_r + c_I,r v_a with a = AColumn(r) (r itself on the
  // rows of x; FillNewtonMatrix's J without forming it; v and out distinct).
  void MultNewton(Vec v, Vec out) {
    NCP_PETSC_CHECK(MatMult(G_, v, out));
    LocalRead vv(v), c_f(c_f_), c_i(c_i_);
    LocalWrite o(out);
    for (PetscInt r = 0; r < local_; ++r)
      o[r] =
          c_f[r] * PetscRealPart(o[r]) + c_i[r] * PetscRealPart(vv[layout_.AColumn(r)]);
  }

  // out = |J| |v|: row r of J is c_F,r G_r plus c_I,r at a = AColumn(r), so
  // out_r = |c_F,r| (|G||v|)_r + (|c_F,r G_ra + c_I,r| - |c_F,r G_ra|) |v_a| with
  // G_ra = diag_g_ (v and out distinct, neither work2_).
  void MultAbsNewton(Vec v, Vec out) {
    NCP_PETSC_CHECK(VecCopy(v, work2_));
    NCP_PETSC_CHECK(VecAbs(work2_));
    impl_.abs_source.Mult(G_, work2_, out);
    LocalRead abs_v(work2_), c_f(c_f_), c_i(c_i_), diag(diag_g_);
    LocalWrite o(out);
    for (PetscInt r = 0; r < local_; ++r) {
      const double cfd = c_f[r] * diag[r];
      o[r] = std::abs(c_f[r]) * PetscRealPart(o[r]) +
             (std::abs(cfd + c_i[r]) - std::abs(cfd)) * abs_v[layout_.AColumn(r)];
    }
  }

  // J = diag(c_F) G + diag(c_I) on the rows of x, c_I at (r, AColumn(r)) on slack rows,
  // into the matrix J (impl_.newton or impl_.lm_jacobian, both on newton's pattern).
  void FillNewtonMatrix(Mat J) {
    NCP_PETSC_CHECK(MatCopy(
        G_, J, impl_.same_pattern ? SAME_NONZERO_PATTERN : DIFFERENT_NONZERO_PATTERN));
    NCP_PETSC_CHECK(MatDiagonalScale(J, c_f_, nullptr));
    if (layout_.total_slacks == 0) {
      NCP_PETSC_CHECK(MatDiagonalSet(J, c_i_, ADD_VALUES));
      return;
    }
    PetscInt first = 0, last = 0;
    NCP_PETSC_CHECK(VecGetOwnershipRange(y_, &first, &last));
    NCP_PETSC_CHECK(VecCopy(c_i_, work_));
    {
      LocalRead c_i(c_i_);
      LocalWrite diagonal(work_);
      for (PetscInt r = layout_.components; r < local_; ++r) {
        diagonal[r] = 0.0;
        const PetscInt row = first + r, col = first + layout_.AColumn(r);
        const PetscScalar value = c_i[r];
        NCP_PETSC_CHECK(MatSetValues(J, 1, &row, 1, &col, &value, INSERT_VALUES));
      }
    }
    NCP_PETSC_CHECK(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
    NCP_PETSC_CHECK(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
    NCP_PETSC_CHECK(MatDiagonalSet(J, work_, ADD_VALUES));
  }

  // ---- ||grad psi||_inf (iterate_.grad_inf) and the round-off floor of the test
  // (Options::roundoff_ulps; never within when 0) in one reduction; true when every row
  // is within the floor. Row r's sensitivity is r_r = |c_F,r| (|G||y|)_r + |c_I,r|
  // |y_AColumn(r)|, the serial solver's |da| |J_A||x| + |db| |J_B||x| (and |J_E||x| for
  // equations) for these rows.
  bool GradientNormAndRoundoffFloor() {
    LogScope scope(SolverLogEvents().roundoff);
    bool within = options_.roundoff_ulps != 0.0;
    if (within) {
      RoundoffSensitivity();
      LocalRead phi(phi_), sensitivity(sensitivity_);
      for (PetscInt r = 0; r < local_ && within; ++r)
        within = internal::RowWithinRoundoffFloor(phi[r], options_.tolerance,
                                                  options_.roundoff_ulps, sensitivity[r]);
    }
    const std::array<double, 2> largest =
        MaxRanks<2>(comm_, {LocalNormInf(grad_), within ? 0.0 : 1.0});
    iterate_.grad_inf = largest[0];
    return largest[1] == 0.0;
  }

  // sensitivity_ = the rows' r of the round-off floor at y
  // (GradientNormAndRoundoffFloor).
  void RoundoffSensitivity() {
    NCP_PETSC_CHECK(VecCopy(y_, work2_));
    NCP_PETSC_CHECK(VecAbs(work2_));
    impl_.abs_source.Mult(G_, work2_, work_);  // |G||y|
    LocalRead abs_gy(work_), abs_y(work2_), c_f(c_f_), c_i(c_i_);
    LocalWrite sensitivity(sensitivity_);
    for (PetscInt r = 0; r < local_; ++r)
      sensitivity[r] =
          std::abs(c_f[r]) * abs_gy[r] + std::abs(c_i[r]) * abs_y[layout_.AColumn(r)];
  }

  // ---- the hooks of SemismoothNewton that are a line or two here --------------------
  std::pair<double, double> ResidualNorms() const { return {phi_inf_, psi_}; }

  // d = -grad psi, its slope -||grad psi||^2 and ||d||_2 in one reduction.
  void GradientDirection() {
    NCP_PETSC_CHECK(VecCopy(grad_, d_));
    NCP_PETSC_CHECK(VecScale(d_, -1.0));
    const auto [square, norm] = DotAndNorm(grad_, grad_, d_, NORM_2);
    iterate_.slope = -square;
    d_norm_ = norm;
  }

  // grad psi' d and ||d||_2 in one reduction (the descent test, eq. 22).
  std::pair<double, double> SlopeAndDirectionNorm() {
    double slope = 0.0;
    std::tie(slope, d_norm_) = DotAndNorm(grad_, d_, d_, NORM_2);
    return {slope, d_norm_};
  }

  double DirectionNorm() {
    if (d_norm_ < 0.0) NCP_PETSC_CHECK(VecNorm(d_, NORM_2, &d_norm_));
    return d_norm_;
  }

  // (The directions time their own linear algebra into Summary::linear_solver_time_s.)
  template <class Choose>
  Direction TimedDirection(Choose&& choose) {
    return choose();
  }

  // ---- step 3's trial point y + t d, evaluated into the trial buffers ---------------
  internal::LineSearchTrial TrialStep(double t) {
    using Trial = internal::LineSearchTrial;
    NCP_PETSC_CHECK(VecWAXPY(x_trial_, t, d_, y_));
    PetscBool unchanged = PETSC_FALSE;
    NCP_PETSC_CHECK(VecEqual(x_trial_, y_, &unchanged));
    if (unchanged) return Trial{Trial::kUnchanged, 0.0};
    if (!Evaluate(x_trial_, f_trial_, phi_trial_))
      return Trial{Trial::kNotEvaluable, 0.0};
    if (!ReducePhi(phi_trial_, &trial_phi_inf_, &trial_psi_))
      return Trial{Trial::kNonFinite, 0.0};
    return Trial{Trial::kEvaluated, trial_psi_};
  }

  // ---- the points a restart or a new strategy continues from ------------------------
  void CopyCurrentToTrial() { NCP_PETSC_CHECK(VecCopy(y_, x_trial_)); }
  void CopyBestToTrial() { NCP_PETSC_CHECK(VecCopy(best_y_, x_trial_)); }

  // The trial point moved to the point a restart or a new strategy continues from
  // (box_mcp.cpp's RestartPoint): projected onto [l, u], the slacks recomputed from F
  // there; then evaluated. false when F cannot be evaluated there.
  bool EvaluateRestartTrial() {
    ProjectOntoBox(lower_, upper_, x_trial_);
    return (layout_.total_slacks == 0 || SetSlacks(x_trial_)) &&
           Evaluate(x_trial_, f_trial_, phi_trial_) &&
           ReducePhi(phi_trial_, &trial_phi_inf_, &trial_psi_);
  }

  // psi(x^k) to the progress record, x^k kept when it is the strategy's best point.
  void ObserveProgress(size_t kk, int k) {
    if (progress_.Record(kk, psi_, k)) NCP_PETSC_CHECK(VecCopy(y_, best_y_));
  }
  const internal::StrategyProgress& Progress() const { return progress_; }

  // Options::max_seconds passed on any rank? (collective: called under a finite limit)
  bool TimeLimitPassed() const {
    return AnyRank(comm_, Seconds(start_) > options_.max_seconds);
  }
  bool OnAnyRank(bool local) const { return AnyRank(comm_, local); }
  template <class... Args>
  void Print(const char* format, Args... args) const {
    PetscFPrintf(comm_, PETSC_STDERR, format, args...);
  }
  static bool WeightedResidual() { return false; }
  std::string NewtonSolveName() const {
    return "KSP solve (" + impl_.report.ksp_type + " + " + impl_.report.pc_type + ")";
  }
  static const char* JacobianFailure() { return "the Jacobian callback failed"; }

  // Levenberg-Marquardt direction (J'J + mu I) d = -J' Phi with mu = ||Phi||_2 (Fan and
  // Yuan 2005), the serial solver's, by the KSP lm_ksp (default MUMPS LU); false when the
  // KSP failed or d is not finite.
  bool RegularizedDirection() {
    const auto t0 = Clock::now();
    impl_.PrepareNormalMatrix(ExplicitJacobian(), std::sqrt(2.0 * psi_));
    NCP_PETSC_CHECK(VecCopy(grad_, work_));
    NCP_PETSC_CHECK(VecScale(work_, -1.0));
    const bool solved =
        KspSolve(impl_.lm_ksp, impl_.normal, &impl_.lm_workspace_percent, work_, d_);
    summary_.linear_solver_time_s += Seconds(t0);
    return solved;
  }

  // J as a matrix: impl_.newton, or with symmetric_newton (where newton holds the
  // symmetrized system) impl_.lm_jacobian, created on first use and filled here.
  Mat ExplicitJacobian() {
    if (!impl_.symmetric_newton) return impl_.newton;
    if (!impl_.lm_jacobian)
      NCP_PETSC_CHECK(
          MatDuplicate(impl_.newton, MAT_DO_NOT_COPY_VALUES, &impl_.lm_jacobian));
    FillNewtonMatrix(impl_.lm_jacobian);
    return impl_.lm_jacobian;
  }

  // out = op^-1 rhs by ksp; false (on every rank) when the KSP failed or out is not
  // finite. A failed factorization is set up afresh (ResetFactorization): MUMPS skips
  // every numeric factorization after a failed one (its INFOG(1) stays < 0), while the
  // serial backends factorize each Newton matrix anew. When MUMPS ran out of its
  // estimated workspace (pivots delayed by the zero entries of slack rows, for one) the
  // same system is factorized again with ICNTL(14) doubled, kept in *workspace_percent
  // for the later factorizations of this KSP.
  bool KspSolve(KSP ksp, Mat op, int* workspace_percent, Vec rhs, Vec out) {
    constexpr int kWorkspaceRetries = 4;  // up to 2^4 times the first estimate's margin
    for (int attempt = 0;; ++attempt) {
      const PetscErrorCode code = KSPSolve(ksp, rhs, out);
      KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
      if (code == 0) {
        PetscInt its = 0;
        NCP_PETSC_CHECK(KSPGetConvergedReason(ksp, &reason));
        NCP_PETSC_CHECK(KSPGetIterationNumber(ksp, &its));
        impl_.report.linear_iterations += static_cast<int>(its);
        impl_.report.residual_test_iterations =
            static_cast<int>(impl_.outer_test.continued());
      }
      // Failed (the PC included), not converged, out not finite: one reduction.
      const std::array<long long, 3> counts = SumRanks<3>(
          comm_, {code != 0 || reason == KSP_DIVERGED_PC_FAILED ? 1 : 0,
                  reason <= 0 ? 1 : 0, code == 0 && !LocallyFinite(out) ? 1 : 0});
      if (counts[0] == 0) return counts[1] == 0 && counts[2] == 0;
      const int more = MumpsWorkspaceToRetry(comm_, ksp);
      if (more > 0) *workspace_percent = more;
      ResetFactorization(ksp, op, *workspace_percent);
      if (more == 0 || attempt == kWorkspaceRetries) return false;
    }
  }

  // The factorization of ksp's PC from scratch at the next solve
  // (ResetMumpsFactorization), for the Newton KSP with MUMPS' null-pivot detection when
  // DetectsNullPivots().
  void ResetFactorization(KSP ksp, Mat op, int workspace_percent) {
    ResetMumpsFactorization(ksp, op, workspace_percent,
                            ksp == impl_.ksp && DetectsNullPivots());
  }

  // Whether the Newton systems are solved by a direct MUMPS factorization (the default):
  // the solves Options::minimum_norm_step acts on. An iterative KSP that fails goes to
  // the LM direction or -grad psi at once.
  bool DirectMumpsSolve() const { return IsDirectMumpsSolve(impl_.ksp); }

  // J d = -Phi (eq. 21) by the KSP; false when the KSP diverged, MUMPS found null pivots
  // (DetectsNullPivots), d is not finite or fails the backward-error guard of
  // globalization.hpp. An LU that failed or called J singular is tried again on J
  // equilibrated when J's rows or columns spread over more than 2^20
  // (Options::scale_newton_system, the serial dense LU's rule; nothing is computed for
  // the scaling while the LU of J succeeds).
  bool NewtonDirection(int /*k*/) {
    d_norm_ = -1.0;  // ||d||_2 not yet known
    const auto t0 = Clock::now();
    NCP_PETSC_CHECK(VecCopy(phi_, work_));
    NCP_PETSC_CHECK(VecScale(work_, -1.0));
    if (impl_.symmetric_newton && !Symmetrize(work_)) {
      summary_.linear_solver_time_s += Seconds(t0);
      return false;
    }
    if (impl_.outer_test.AppliesTo(function_)) ArmOuterResidualTest();
    bool factored =
        KspSolve(impl_.ksp, impl_.newton, &impl_.newton_workspace_percent, work_, d_) &&
        !FoundNullPivots();
    impl_.outer_test.Disarm();
    if (!factored && options_.scale_newton_system && DetectsNullPivots() &&
        impl_.equilibration.Compute(impl_.newton))
      factored = EquilibratedNewtonSolve();
    const bool solved = factored && SolvesNewtonSystem();
    summary_.linear_solver_time_s += Seconds(t0);
    return solved;
  }

  // Whether d_ solves J d = -Phi as accurately as a backward-stable solve would (the
  // guard of globalization.hpp); overwrites work_.
  bool SolvesNewtonSystem() {
    LogScope scope(SolverLogEvents().backward);
    MultNewton(d_, work_);  // J d + Phi
    NCP_PETSC_CHECK(VecAXPY(work_, 1.0, phi_));
    const double residual_inf = LocalNormInf(work_);
    MultAbsNewton(d_, work_);  // |J||d|
    // ||J d + Phi||_inf and || |J||d| ||_inf in one reduction (LocalNormInf: +inf for a
    // non-finite entry, which fails the guard)
    const std::array<double, 2> inf =
        MaxRanks<2>(comm_, {residual_inf, LocalNormInf(work_)});
    return std::isfinite(inf[0]) && std::isfinite(inf[1]) &&
           internal::NewtonSolutionAccurate(inf[0], phi_inf_, inf[1]);
  }

  // J d = -Phi as Js y = diag(r) (-Phi), d = diag(c) y with Js = diag(r) J diag(c) of
  // impl_.equilibration, factorized by the Newton KSP (J restored exactly afterwards:
  // the scales are powers of two). false when the LU failed or called Js singular.
  bool EquilibratedNewtonSolve() {
    ++summary_.equilibrated_factorizations;
    const DistributedEquilibration& e = impl_.equilibration;
    e.Scale(impl_.newton);
    NCP_PETSC_CHECK(VecPointwiseMult(work_, e.row(), phi_));
    NCP_PETSC_CHECK(VecScale(work_, -1.0));
    const bool factored =
        KspSolve(impl_.ksp, impl_.newton, &impl_.newton_workspace_percent, work_, d_) &&
        !FoundNullPivots();
    e.Unscale(impl_.newton);
    if (factored) NCP_PETSC_CHECK(VecPointwiseMult(d_, d_, e.column()));
    return factored;
  }

  // Whether the Newton KSP's MUMPS LU runs with null-pivot detection
  // (ArmNullPivotDetection), so that it calls a singular J singular as the serial dense
  // LU does: with Options::minimum_norm_step or scale_newton_system, a direct MUMPS LU
  // and J itself as the operator (not the symmetrized system).
  bool DetectsNullPivots() const {
    if (!(options_.minimum_norm_step || options_.scale_newton_system) ||
        impl_.symmetric_newton || !DirectMumpsSolve())
      return false;
    PC pc = nullptr;
    NCP_PETSC_CHECK(KSPGetPC(impl_.ksp, &pc));
    PetscBool lu = PETSC_FALSE;
    NCP_PETSC_CHECK(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCLU, &lu));
    return lu == PETSC_TRUE;
  }

  // Whether the last Newton factorization found null pivots (INFOG(28) > 0).
  bool FoundNullPivots() {
    return DetectsNullPivots() && MumpsNullPivots(MumpsFactor(impl_.ksp)) > 0;
  }

  // The least-norm solution of J d = -Phi in the unknowns of J equilibrated
  // (MinimumNormSolver: MUMPS' null-pivot detection and null-space basis), kept when it
  // solves the system to the backward error asked of the Newton solve: a singular but
  // consistent Newton system (the serial MinimumNormDirection). false when it failed or
  // does not solve the system, or the Newton systems are not solved by a direct MUMPS LU.
  bool MinimumNormDirection() {
    if (!DirectMumpsSolve()) return false;
    const auto t0 = Clock::now();
    NCP_PETSC_CHECK(VecCopy(phi_, work_));
    NCP_PETSC_CHECK(VecScale(work_, -1.0));
    const bool solved =
        impl_.minimum_norm->Solve(ExplicitJacobian(), work_, d_) && SolvesNewtonSystem();
    summary_.linear_solver_time_s += Seconds(t0);
    return solved;
  }

  // The rows' weights and bounds of OuterResidualTest for this Newton system: the KSP's
  // row r is row r of J (weight 1), or in symmetric mode row r of J divided by c_F,r (a
  // kept row) or by c_I,r (an eliminated one); the bound is the fraction of the stopping
  // test's bound on |Phi_r| at this iterate (tolerance and round-off floor; sensitivity_
  // is this iterate's: GradientNormAndRoundoffFloor ran before the direction, or 0
  // without floor).
  void ArmOuterResidualTest() {
    {
      LocalRead c_f(c_f_), c_i(c_i_), sensitivity(sensitivity_);
      LocalWrite weight(ksp_row_weight_), bound(ksp_row_bound_);
      const double fraction = impl_.outer_test.fraction();
      for (PetscInt r = 0; r < local_; ++r) {
        weight[r] = !impl_.symmetric_newton ? 1.0 : c_f[r] != 0.0 ? c_f[r] : c_i[r];
        bound[r] =
            fraction * internal::RoundoffFloorBound(
                           options_.tolerance, options_.roundoff_ulps, sensitivity[r]);
      }
    }
    impl_.outer_test.Arm(ksp_row_weight_, ksp_row_bound_, ksp_residual_, ksp_work_);
  }

  // The same system J d = rhs made symmetric (the serial kCholmod backend's
  // transformation, types.hpp): a row with c_F != 0 is divided by c_F, giving diag(c_I /
  // c_F) + F'_i with c_I / c_F >= 0 for FB, min and penalized FB (both partials are <=
  // 0); a row with c_F = 0 fixes d_i = rhs_i / c_I and is eliminated from the others
  // (MatZeroRowsColumns). For a symmetric positive (semi)definite F' (obstacle problems)
  // the result is symmetric positive definite: CG and AMG apply. rhs is replaced by the
  // symmetric system's right-hand side; false when a row is zero (c_F = c_I = 0) on some
  // rank.
  bool Symmetrize(Vec rhs) {
    LogScope scope(SolverLogEvents().symmetrize);
    Mat S = impl_.newton;
    NCP_PETSC_CHECK(MatCopy(
        G_, S, impl_.same_pattern ? SAME_NONZERO_PATTERN : DIFFERENT_NONZERO_PATTERN));
    PetscInt first = 0, last = 0;
    NCP_PETSC_CHECK(VecGetOwnershipRange(y_, &first, &last));
    std::vector<PetscInt> fixed_rows;
    bool zero_row = false;
    {
      LocalRead c_f(c_f_), c_i(c_i_);
      LocalWrite b(rhs), ratio(work2_), known(fixed_values_);
      for (PetscInt i = 0; i < local_; ++i) {
        ratio[i] = 0.0;
        known[i] = 0.0;
        if (c_f[i] != 0.0) {
          ratio[i] = c_i[i] / c_f[i];
          b[i] = PetscRealPart(b[i]) / c_f[i];
        } else if (c_i[i] != 0.0) {
          known[i] = PetscRealPart(b[i]) / c_i[i];
          fixed_rows.push_back(first + i);
        } else {
          zero_row = true;
        }
      }
    }
    if (AnyRank(comm_, zero_row)) return false;
    NCP_PETSC_CHECK(MatDiagonalSet(S, work2_, ADD_VALUES));
    NCP_PETSC_CHECK(MatZeroRowsColumns(S, static_cast<PetscInt>(fixed_rows.size()),
                                       fixed_rows.data(), 1.0, fixed_values_, rhs));
    if (impl_.multigrid.grid()) {  // 1 on the eliminated rows of S, 0 on the others
      NCP_PETSC_CHECK(VecSet(work2_, 0.0));
      {
        LocalWrite eliminated(work2_);
        for (PetscInt row : fixed_rows) eliminated[row - first] = 1.0;
      }
      PC pc = nullptr;
      NCP_PETSC_CHECK(KSPGetPC(impl_.ksp, &pc));
      impl_.multigrid.Update(pc, S, work2_);
    }
    return true;
  }

  // y = the trial point, with its F, Phi, ||Phi||_inf and psi.
  void AcceptTrialPoint() {
    NCP_PETSC_CHECK(VecCopy(x_trial_, y_));
    f_.Swap(f_trial_);
    phi_.Swap(phi_trial_);
    phi_inf_ = trial_phi_inf_;
    psi_ = trial_psi_;
  }

  // ||phi||_inf and psi = phi'phi / 2 in one reduction; false when some entry of phi is
  // not finite. A finite phi'phi proves every entry finite; only when it is not (an entry
  // NaN or Inf, or the squares overflow) are the entries checked (AllFinite).
  bool ReducePhi(Vec phi, double* inf, double* psi) {
    const auto [square, norm] = DotAndNorm(phi, phi, phi, NORM_INFINITY);
    *inf = norm;
    *psi = 0.5 * square;
    return std::isfinite(square) || AllFinite(comm_, phi);
  }

  // The final residuals and time of Summary (Finish).
  void CompleteSummary() {
    summary_.final_phi_inf = NormInf(phi_);
    summary_.final_psi = 0.5 * Dot(phi_, phi_);
    summary_.total_time_s = Seconds(start_);
  }

  Solver::Impl& impl_;
  MPI_Comm comm_;
  const BoxMcp& p_;
  Vec x_;  // the caller's x (layout of F)
  const MixedLayout& layout_;
  const LocalArray<double>& lower_;  // of the rank's components, normalized
  const LocalArray<double>& upper_;  // (+-inf = no bound)
  const PetscInt local_;             // rows of y on this rank
  Vec y_ = nullptr;                  // the unknowns: x_ itself, or y_owned_ with slacks
  OwnedVec y_owned_, x_part_;        // x_part_: the x part of a y (XPart)
  Mat G_ = nullptr;                  // G of mixed_layout.hpp
  // f_, f_trial_ laid out like x; x_trial_ (the trial y) and the others like y.
  OwnedVec f_, f_trial_, phi_, phi_trial_, grad_, d_, x_trial_, c_f_, c_i_, z_, f_z_,
      work_, work2_;
  OwnedVec fixed_values_;  // d_i of the rows the symmetrized system eliminates
  OwnedVec diag_g_;        // G_{r, AColumn(r)} (GDiagonalAtA)
  OwnedVec sensitivity_;   // r of the round-off floor at y (RoundoffSensitivity)
  // OuterResidualTest's rows: weights, bounds, and its work vectors.
  OwnedVec ksp_row_weight_, ksp_row_bound_, ksp_residual_, ksp_work_;
  internal::StrategySchedule schedule_;
  internal::StrategyProgress progress_;
  OwnedVec best_y_;  // the current strategy's smallest-psi point (Options::hybrid)
  internal::StagnationTest stagnation_;
  internal::NonmonotoneReference armijo_reference_;
  double phi_inf_ = 0.0, psi_ = 0.0;              // of phi_ (ReducePhi)
  double trial_phi_inf_ = 0.0, trial_psi_ = 0.0;  // of phi_trial_ (ReducePhi)
  double d_norm_ = -1.0;                          // ||d||_2, < 0: not computed
};

void RunIteration(Solver::Impl& impl, const BoxMcp& problem, Vec x, Summary* summary,
                  const MixedLayout& layout) {
  Iteration(impl, problem, x, *summary, layout).Run();
}

}  // namespace ncp::petsc
