// ncp::petsc::Solver: Algorithm 1 of the thesis (section 3.1), the globalized semismooth
// Newton method of De Luca, Facchinei and Kanzow (1996), over distributed PETSc Vec/Mat.
//
// The box MCP l <= x <= u perp F(x) is written row by row as the serial solver's mixed
// form (ncp/src/box_mcp.cpp) without reordering:
//
//   free  (l = -inf, u = +inf):  Phi_i = F_i(x)                  J_i = F'_i
//   fixed (l = u):               Phi_i = x_i - l_i               J_i = e_i'
//   lower (l finite, u = +inf):  Phi_i = phi(x_i - l_i,  F_i)     J_i = da e_i' + db F'_i
//   upper (l = -inf, u finite):  Phi_i = phi(u_i - x_i, -F_i)     J_i = -da e_i' - db
//   F'_i
//
// so the Newton matrix is J = diag(c_F) F' + diag(c_I) with per-row coefficients c_F,
// c_I, assembled by MatCopy + MatDiagonalScale + MatDiagonalSet on the pattern of F'.
// Every decision (z-vector rule, descent test, Armijo, restarts, stopping tests) is taken
// by the functions of ncp/src/globalization.hpp and ncp_function_internal.hpp, the serial
// solver's own, from norms and dot products reduced over the communicator: every rank
// takes the same decision, so no rank can wait in a collective call the others skipped.

#include "ncp/petsc/solver.hpp"

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "globalization.hpp"
#include "ncp_function_internal.hpp"

namespace ncp::petsc {
namespace {

using Clock = std::chrono::steady_clock;
using internal::FormatNumber;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

// A PETSc call of the solver itself failed (out of memory, a PETSc bug): not a numerical
// event of the iteration, so it is thrown, naming the call.
void Check(PetscErrorCode code, const char* call) {
  if (code != 0)
    throw std::runtime_error(std::string("ncp::petsc::Solver: ") + call +
                             " failed with PETSc error " +
                             std::to_string(static_cast<int>(code)));
}
#define NCP_PETSC_CHECK(call) Check((call), #call)

// ---- reductions over the communicator ------------------------------------------------
bool AnyRank(MPI_Comm comm, bool local) {
  int in = local ? 1 : 0, out = 0;
  MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LOR, comm);
  return out != 0;
}
long long SumRanks(MPI_Comm comm, long long local) {
  long long out = 0;
  MPI_Allreduce(&local, &out, 1, MPI_LONG_LONG, MPI_SUM, comm);
  return out;
}
long long MinRanks(MPI_Comm comm, long long local) {
  long long out = 0;
  MPI_Allreduce(&local, &out, 1, MPI_LONG_LONG, MPI_MIN, comm);
  return out;
}

// ---- Vec and Mat helpers -------------------------------------------------------------
class OwnedVec {
 public:
  OwnedVec() = default;
  ~OwnedVec() {
    if (v_) VecDestroy(&v_);
  }
  OwnedVec(const OwnedVec&) = delete;
  OwnedVec& operator=(const OwnedVec&) = delete;
  void DuplicateOf(Vec layout) { NCP_PETSC_CHECK(VecDuplicate(layout, &v_)); }
  operator Vec() const { return v_; }
  void Swap(OwnedVec& other) { std::swap(v_, other.v_); }

 private:
  Vec v_ = nullptr;
};

// Read access to the local part of a Vec for the lifetime of the object.
class LocalRead {
 public:
  explicit LocalRead(Vec v) : v_(v) { NCP_PETSC_CHECK(VecGetArrayRead(v_, &a_)); }
  ~LocalRead() { VecRestoreArrayRead(v_, &a_); }
  double operator[](PetscInt i) const { return PetscRealPart(a_[i]); }

 private:
  Vec v_;
  const PetscScalar* a_ = nullptr;
};
class LocalWrite {
 public:
  explicit LocalWrite(Vec v) : v_(v) { NCP_PETSC_CHECK(VecGetArray(v_, &a_)); }
  ~LocalWrite() { VecRestoreArray(v_, &a_); }
  PetscScalar& operator[](PetscInt i) { return a_[i]; }

 private:
  Vec v_;
  PetscScalar* a_ = nullptr;
};

bool AllFinite(MPI_Comm comm, Vec v) {
  PetscInt n = 0;
  NCP_PETSC_CHECK(VecGetLocalSize(v, &n));
  bool finite = true;
  {
    LocalRead a(v);
    for (PetscInt i = 0; i < n && finite; ++i) finite = std::isfinite(a[i]);
  }
  return !AnyRank(comm, !finite);
}

double NormInf(Vec v) {
  PetscReal norm = 0.0;
  NCP_PETSC_CHECK(VecNorm(v, NORM_INFINITY, &norm));
  return norm;
}
double Dot(Vec a, Vec b) {
  PetscScalar dot = 0.0;
  NCP_PETSC_CHECK(VecDot(a, b, &dot));
  return PetscRealPart(dot);
}

bool IsAij(Mat M, bool* parallel) {
  PetscBool seq = PETSC_FALSE, mpi = PETSC_FALSE;
  NCP_PETSC_CHECK(
      PetscObjectBaseTypeCompare(reinterpret_cast<PetscObject>(M), MATSEQAIJ, &seq));
  NCP_PETSC_CHECK(
      PetscObjectBaseTypeCompare(reinterpret_cast<PetscObject>(M), MATMPIAIJ, &mpi));
  *parallel = mpi == PETSC_TRUE;
  return seq == PETSC_TRUE || mpi == PETSC_TRUE;
}

// Calls f(value&) for every stored entry of the local rows of an AIJ matrix (the diagonal
// and off-diagonal blocks of MPIAIJ); read only (f(const value&)) when !kWrite.
template <bool kWrite, class Function>
void ForEachLocalValue(Mat M, Function&& f) {
  bool parallel = false;
  if (!IsAij(M, &parallel))
    throw std::invalid_argument(
        "ncp::petsc::Solver: the Jacobian matrix must be of type AIJ "
        "(MATSEQAIJ or MATMPIAIJ)");
  Mat blocks[2] = {M, nullptr};
  if (parallel) NCP_PETSC_CHECK(MatMPIAIJGetSeqAIJ(M, &blocks[0], &blocks[1], nullptr));
  for (Mat block : blocks) {
    if (!block) continue;
    MatInfo info;
    NCP_PETSC_CHECK(MatGetInfo(block, MAT_LOCAL, &info));
    const auto count = static_cast<PetscInt>(info.nz_used);
    if constexpr (kWrite) {
      PetscScalar* values = nullptr;
      NCP_PETSC_CHECK(MatSeqAIJGetArray(block, &values));
      for (PetscInt k = 0; k < count; ++k) f(values[k]);
      NCP_PETSC_CHECK(MatSeqAIJRestoreArray(block, &values));
    } else {
      const PetscScalar* values = nullptr;
      NCP_PETSC_CHECK(MatSeqAIJGetArrayRead(block, &values));
      for (PetscInt k = 0; k < count; ++k) f(values[k]);
      NCP_PETSC_CHECK(MatSeqAIJRestoreArrayRead(block, &values));
    }
  }
}

// *abs_copy = |M| entry by entry (created on first use with M's pattern).
void AbsoluteCopy(Mat M, Mat* abs_copy) {
  if (*abs_copy == nullptr)
    NCP_PETSC_CHECK(MatDuplicate(M, MAT_COPY_VALUES, abs_copy));
  else
    NCP_PETSC_CHECK(MatCopy(M, *abs_copy, SAME_NONZERO_PATTERN));
  ForEachLocalValue<true>(*abs_copy,
                          [](PetscScalar& v) { v = std::abs(PetscRealPart(v)); });
}

void DestroyMat(Mat* M) {
  if (*M) MatDestroy(M);
  *M = nullptr;
}

// The kind of row i of the mixed form (file comment).
enum class Row : char { kFree, kFixed, kLower, kUpper };

double NormalizeBound(double bound, double infinite_bound) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  return bound >= infinite_bound ? kInf : bound <= -infinite_bound ? -kInf : bound;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// The solver's state kept between solves: the KSP and the Newton matrix (so a direct
// solver's symbolic factorization is reused while F' keeps its pattern).

struct Solver::Impl {
  MPI_Comm comm = MPI_COMM_NULL;
  Options options;
  std::string prefix;
  KSP ksp = nullptr;
  bool ksp_configured = false;
  KspReport report;
  // The KSP's operator on the pattern of F' (plus its diagonal), built for the user's
  // matrix `source` in the nonzero state `source_state`: J = diag(c_F) F' + diag(c_I),
  // or with symmetric_newton the reduced symmetric system (Iteration::Symmetrize: rows
  // with c_F != 0 divided by c_F, the others eliminated; KspReport::symmetric_newton).
  // Products with J itself (gradient, backward error) are formed from F' and c_F, c_I,
  // so the symmetric mode keeps no second matrix.
  Mat newton = nullptr;
  Mat source = nullptr;
  PetscObjectState source_state = -1;
  bool same_pattern = true;  // the operator's pattern is F''s (no diagonal entry added)
  Mat abs_source = nullptr;  // |F'| (round-off floor, backward error)
  bool symmetric_newton = false;

  ~Impl() {
    DestroyMat(&newton);
    DestroyMat(&abs_source);
    if (ksp) KSPDestroy(&ksp);
  }

  // J's structure for the matrix F' (again when F' is another matrix or changed pattern).
  // Returns true when J was (re)built.
  bool PrepareNewtonMatrix(Mat F) {
    PetscObjectState state = 0;
    NCP_PETSC_CHECK(MatGetNonzeroState(F, &state));
    if (newton && source == F && state == source_state) return false;
    DestroyMat(&newton);
    DestroyMat(&abs_source);
    NCP_PETSC_CHECK(MatDuplicate(F, MAT_COPY_VALUES, &newton));
    PetscBool missing = PETSC_FALSE;
    PetscInt row = 0;
    NCP_PETSC_CHECK(MatMissingDiagonal(newton, &missing, &row));
    same_pattern = !AnyRank(comm, missing == PETSC_TRUE);
    if (!same_pattern) {  // c_I needs every diagonal entry: add the missing ones as zeros
      NCP_PETSC_CHECK(MatSetOption(newton, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
      Vec zero = nullptr;
      NCP_PETSC_CHECK(MatCreateVecs(newton, &zero, nullptr));
      NCP_PETSC_CHECK(VecSet(zero, 0.0));
      NCP_PETSC_CHECK(MatDiagonalSet(newton, zero, ADD_VALUES));
      VecDestroy(&zero);
    }
    source = F;
    source_state = state;
    if (symmetric_newton) {  // MatZeroRowsColumns keeps the pattern for the next MatCopy
      NCP_PETSC_CHECK(MatSetOption(newton, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE));
      NCP_PETSC_CHECK(MatSetOption(newton, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
    }
    NCP_PETSC_CHECK(KSPSetOperators(ksp, newton, newton));
    return true;
  }

  // Once, at the first solve: the KSP from the options database, and whether the Newton
  // systems are symmetrized: -<prefix>symmetric_newton <bool>, by default on for the KSPs
  // and PCs that need a symmetric operator (CG family, MINRES, Cholesky, ICC).
  void Configure() {
    if (ksp_configured) return;
    NCP_PETSC_CHECK(KSPSetFromOptions(ksp));
    PC pc = nullptr;
    NCP_PETSC_CHECK(KSPGetPC(ksp, &pc));
    PetscBool symmetric_ksp = PETSC_FALSE, symmetric_pc = PETSC_FALSE;
    NCP_PETSC_CHECK(PetscObjectTypeCompareAny(
        reinterpret_cast<PetscObject>(ksp), &symmetric_ksp, KSPCG, KSPPIPECG, KSPGROPPCG,
        KSPCR, KSPPIPECR, KSPMINRES, KSPSYMMLQ, ""));
    NCP_PETSC_CHECK(PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(pc),
                                              &symmetric_pc, PCCHOLESKY, PCICC, ""));
    PetscBool flag = symmetric_ksp || symmetric_pc ? PETSC_TRUE : PETSC_FALSE,
              set = PETSC_FALSE;
    NCP_PETSC_CHECK(
        PetscOptionsGetBool(nullptr, prefix.c_str(), "-symmetric_newton", &flag, &set));
    symmetric_newton = flag == PETSC_TRUE;
    report.symmetric_newton = symmetric_newton;
    ksp_configured = true;
  }

  // KspReport's names of the KSP, PC and factorization package in use.
  void DescribeKsp() {
    KSPType ksp_type = nullptr;
    PCType pc_type = nullptr;
    PC pc = nullptr;
    NCP_PETSC_CHECK(KSPGetType(ksp, &ksp_type));
    NCP_PETSC_CHECK(KSPGetPC(ksp, &pc));
    NCP_PETSC_CHECK(PCGetType(pc, &pc_type));
    report.ksp_type = ksp_type ? ksp_type : "";
    report.pc_type = pc_type ? pc_type : "";
    PetscBool factor = PETSC_FALSE;
    NCP_PETSC_CHECK(PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(pc), &factor,
                                              PCLU, PCCHOLESKY, PCILU, PCICC, ""));
    MatSolverType solver_type = nullptr;
    if (factor) NCP_PETSC_CHECK(PCFactorGetMatSolverType(pc, &solver_type));
    report.factor_solver_type = solver_type ? solver_type : "";
  }
};

// ---------------------------------------------------------------------------------------
// Misuse at the API boundary, checked collectively: the same exception on every rank.

namespace {

[[noreturn]] void Misuse(const std::string& what) {
  throw std::invalid_argument("ncp::petsc::Solver::Solve: " + what);
}

void CheckLayout(MPI_Comm comm, Vec x, Vec v, const char* name) {
  PetscInt n = 0, nl = 0, N = 0, NL = 0;
  NCP_PETSC_CHECK(VecGetSize(x, &n));
  NCP_PETSC_CHECK(VecGetLocalSize(x, &nl));
  NCP_PETSC_CHECK(VecGetSize(v, &N));
  NCP_PETSC_CHECK(VecGetLocalSize(v, &NL));
  if (AnyRank(comm, N != n || NL != nl))
    Misuse(std::string(name) + " has global size " + std::to_string(N) +
           ", the start point " + std::to_string(n) +
           (N == n ? " (but the local sizes differ on some rank)" : "") +
           ": both must have the same layout");
}

void CheckMatrixLayout(MPI_Comm comm, Vec x, Mat J) {
  PetscInt n = 0, nl = 0, rows = 0, cols = 0, local_rows = 0, local_cols = 0;
  NCP_PETSC_CHECK(VecGetSize(x, &n));
  NCP_PETSC_CHECK(VecGetLocalSize(x, &nl));
  NCP_PETSC_CHECK(MatGetSize(J, &rows, &cols));
  NCP_PETSC_CHECK(MatGetLocalSize(J, &local_rows, &local_cols));
  if (AnyRank(comm, rows != n || cols != n || local_rows != nl || local_cols != nl))
    Misuse("the Jacobian matrix is " + std::to_string(rows) + " x " +
           std::to_string(cols) + ", the start point has size " + std::to_string(n) +
           ": the matrix must be square with rows and columns laid out like x");
}

// The first (lowest global index) bad entry of the bounds or the start point, reported
// with its values on every rank (the owner contributes them to a sum, the others zeros).
void CheckBoundsAndStart(MPI_Comm comm, PetscInt first, const std::vector<double>& lower,
                         const std::vector<double>& upper, Vec x) {
  const auto n = static_cast<PetscInt>(lower.size());
  LocalRead xa(x);
  long long bad = LLONG_MAX;
  for (PetscInt i = 0; i < n && bad == LLONG_MAX; ++i) {
    const double l = lower[static_cast<size_t>(i)], u = upper[static_cast<size_t>(i)];
    const bool problem = std::isnan(l) || std::isnan(u) || l > u ||
                         l == std::numeric_limits<double>::infinity() ||
                         u == -std::numeric_limits<double>::infinity() ||
                         !std::isfinite(xa[i]);
    if (problem) bad = first + i;
  }
  const long long global_bad = MinRanks(comm, bad);
  if (global_bad == LLONG_MAX) return;
  double values[3] = {0.0, 0.0, 0.0};  // l, u, x0 at global_bad
  if (bad == global_bad) {
    const auto i = static_cast<size_t>(bad - first);
    values[0] = lower[i];
    values[1] = upper[i];
    values[2] = xa[static_cast<PetscInt>(i)];
  }
  double at_bad[3];
  MPI_Allreduce(values, at_bad, 3, MPI_DOUBLE, MPI_SUM, comm);
  const double l = at_bad[0], u = at_bad[1], x0 = at_bad[2];
  const std::string at = "[" + std::to_string(global_bad) + "]";
  if (std::isnan(l) || std::isnan(u)) Misuse("bound" + at + " is NaN");
  if (l > u)
    Misuse("lower" + at + " = " + FormatNumber("%.17g", l) + " > upper" + at + " = " +
           FormatNumber("%.17g", u));
  if (l == std::numeric_limits<double>::infinity() ||
      u == -std::numeric_limits<double>::infinity())
    Misuse("empty box at" + at + " (lower = +inf or upper = -inf)");
  Misuse("start point x" + at + " = " + FormatNumber("%g", x0) + " is not finite");
}

}  // namespace

// ---------------------------------------------------------------------------------------
// One solve, phase by phase; Run() has the layout of ncp::Solver::Iteration::Run
// (ncp/src/solver.cpp) and takes its decisions from globalization.hpp.

class Iteration {
 public:
  Iteration(Solver::Impl& impl, const BoxMcp& problem, Vec x, Summary& summary,
            std::vector<Row> rows, std::vector<double> lower, std::vector<double> upper,
            PetscInt n)
      : impl_(impl),
        o_(impl.options),
        comm_(impl.comm),
        p_(problem),
        x_(x),
        s_(summary),
        rows_(std::move(rows)),
        lower_(std::move(lower)),
        upper_(std::move(upper)),
        local_(static_cast<PetscInt>(rows_.size())),
        n_(n) {}

  void Run() {
    if (!Start()) return;
    for (int k = 0;;) {
      phi_inf_ = NormInf(phi_);
      psi_ = 0.5 * Dot(phi_, phi_);
      converged_ = phi_inf_ <= o_.tolerance;
      roundoff_limited_ = false;
      have_jacobian_ = !converged_ && k < o_.max_iterations;
      jacobian_ok_ = true;
      degenerate_count_ = 0;
      if (have_jacobian_ && !EvaluateJacobian(k)) return;
      if (have_jacobian_ && jacobian_ok_)
        converged_ = roundoff_limited_ = WithinRoundoffFloor();
      if (!Report(k)) return;
      if (TestStop(k)) {
        if (Restart(k)) continue;
        return;
      }
      const bool gradient = ChooseDirection(k);
      if (finished_) return;
      if (!LineSearch(k, gradient)) {
        if (Restart(k)) continue;
        return;
      }
      Accept(gradient);
      ++k;
    }
  }

 private:
  // ---- Start: work vectors, Phi(x^0)
  // -----------------------------------------------------
  bool Start() {
    start_ = Clock::now();
    InitializeSummary();
    for (OwnedVec* v : {&f_, &f_trial_, &phi_, &phi_trial_, &grad_, &d_, &x_trial_, &c_f_,
                        &c_i_, &z_, &f_z_, &work_, &work2_, &fixed_values_, &diag_f_})
      v->DuplicateOf(x_);
    impl_.Configure();
    const bool new_matrix = impl_.PrepareNewtonMatrix(p_.jacobian_matrix);
    s_.symbolic_factorizations = new_matrix ? 1 : 0;
    impl_.DescribeKsp();
    function_ = o_.ncp_function;
    restarts_left_ = o_.merit_restarts;
    first_k_ = 0;
    impl_.report.linear_iterations = 0;
    if (!Evaluate(x_, f_, phi_)) {
      NCP_PETSC_CHECK(VecSet(phi_, std::numeric_limits<double>::quiet_NaN()));
      Finish(TerminationType::kEvaluationFailure,
             "the problem cannot be evaluated at the start point");
      return false;
    }
    s_.initial_phi_inf = NormInf(phi_);
    if (!AllFinite(comm_, phi_)) {
      Finish(TerminationType::kNonFiniteValues, "Phi(x0) has NaN or Inf entries");
      return false;
    }
    stagnation_.Reset(o_.stagnation_window);
    armijo_reference_.Reset(o_.nonmonotone_memory);
    if (o_.log_to_stderr)
      PetscFPrintf(comm_, PETSC_STDERR, "%5s %12s %12s %12s %10s %4s %4s %5s\n", "iter",
                   "|Phi|_inf", "psi", "|grad|_inf", "step", "bt", "dir", "|gam|");
    return true;
  }

  void InitializeSummary() {
    s_ = Summary();
    s_.num_variables = static_cast<int>(n_);
    long long equations = 0;
    for (Row r : rows_) equations += r == Row::kFree || r == Row::kFixed;
    s_.num_equations = static_cast<int>(SumRanks(comm_, equations));
    s_.num_pairs = s_.num_variables - s_.num_equations;
    s_.ncp_function = o_.ncp_function;
    s_.linear_solver_requested = s_.linear_solver_used = LinearSolverType::kAuto;
    s_.iterations = s_.jacobian_evaluations = s_.residual_evaluations = 0;
    s_.gradient_steps = s_.regularized_steps = s_.merit_restarts = 0;
    s_.linear_solver_failures = s_.descent_test_failures = s_.backtracks = 0;
    s_.cholesky_fallbacks = s_.projected_start_components = 0;
    s_.evaluation_time_s = s_.linear_solver_time_s = 0.0;
    s_.predicted_factorization_flops =
        std::numeric_limits<double>::quiet_NaN();  // none predicted
  }

  // ---- Phi(x) row by row (file comment); false when F cannot be evaluated on some rank
  // ----
  bool Evaluate(Vec point, Vec f, Vec phi) {
    ++s_.residual_evaluations;
    const auto t0 = Clock::now();
    const PetscErrorCode code = p_.residual(point, f);
    s_.evaluation_time_s += Seconds(t0);
    if (AnyRank(comm_, code != 0)) return false;
    LocalRead xa(point), fa(f);
    LocalWrite out(phi);
    for (PetscInt i = 0; i < local_; ++i) {
      const auto ii = static_cast<size_t>(i);
      switch (rows_[ii]) {
        case Row::kFree:
          out[i] = fa[i];
          break;
        case Row::kFixed:
          out[i] = xa[i] - lower_[ii];
          break;
        case Row::kLower:
          out[i] = internal::PhiValue(function_, o_.penalized_fb_lambda,
                                      xa[i] - lower_[ii], fa[i]);
          break;
        case Row::kUpper:
          out[i] = internal::PhiValue(function_, o_.penalized_fb_lambda,
                                      upper_[ii] - xa[i], -fa[i]);
          break;
      }
    }
    return true;
  }

  // ---- J^k in the B-subdifferential and grad psi = J' Phi (eq. 24)
  // --------------------- false only when the solve has finished (non-finite Jacobian).
  bool EvaluateJacobian(int k) {
    ++s_.jacobian_evaluations;
    const auto t0 = Clock::now();
    jacobian_ok_ = !AnyRank(comm_, p_.jacobian(x_, p_.jacobian_matrix) != 0);
    s_.evaluation_time_s += Seconds(t0);
    if (!jacobian_ok_) return true;
    bool finite = true;
    ForEachLocalValue<false>(p_.jacobian_matrix, [&](const PetscScalar& v) {
      finite = finite && std::isfinite(PetscRealPart(v));
    });
    if (AnyRank(comm_, !finite)) {
      Finish(TerminationType::kNonFiniteValues,
             "the Jacobian has NaN or Inf entries at iteration " + std::to_string(k));
      return false;
    }
    abs_source_current_ = false;
    NCP_PETSC_CHECK(MatGetDiagonal(p_.jacobian_matrix, diag_f_));
    PhiPartials();
    if (!impl_.symmetric_newton) FillNewtonMatrix();  // else built by Symmetrize
    // grad psi = J' Phi = F'^T (c_F Phi) + c_I Phi
    NCP_PETSC_CHECK(VecPointwiseMult(work_, c_f_, phi_));
    NCP_PETSC_CHECK(MatMultTranspose(p_.jacobian_matrix, work_, grad_));
    NCP_PETSC_CHECK(VecPointwiseMult(work_, c_i_, phi_));
    NCP_PETSC_CHECK(VecAXPY(grad_, 1.0, work_));
    return true;
  }

  // c_F, c_I of every row: the partials (da, db) of phi at (A_i, B_i), the z-vector rule
  // on the degenerate set (z = 1 at the variable of every degenerate pair; DFK 1996, eq.
  // 27): za = A' z = +-z_i, zb = B' z = +-(F' z)_i.
  void PhiPartials() {
    long long degenerate = 0;
    {
      LocalRead xa(x_), fa(f_);
      LocalWrite z(z_);
      for (PetscInt i = 0; i < local_; ++i) {
        z[i] = 0.0;
        double a = 0.0, b = 0.0;
        if (!PairValues(i, xa, fa, &a, &b)) continue;
        if (internal::InDegenerateSet(function_, o_.degenerate_tolerance, a, b)) {
          z[i] = 1.0;
          ++degenerate;
        }
      }
    }
    degenerate_count_ = static_cast<int>(SumRanks(comm_, degenerate));
    if (degenerate_count_ > 0) NCP_PETSC_CHECK(MatMult(p_.jacobian_matrix, z_, f_z_));
    LocalRead xa(x_), fa(f_), z(z_);
    std::unique_ptr<LocalRead> fz(degenerate_count_ > 0 ? new LocalRead(f_z_) : nullptr);
    LocalWrite c_f(c_f_), c_i(c_i_);
    for (PetscInt i = 0; i < local_; ++i) {
      const Row row = rows_[static_cast<size_t>(i)];
      double a = 0.0, b = 0.0;
      if (!PairValues(i, xa, fa, &a, &b)) {
        c_f[i] = row == Row::kFree ? 1.0 : 0.0;
        c_i[i] = row == Row::kFixed ? 1.0 : 0.0;
        continue;
      }
      const double sign = row == Row::kLower ? 1.0 : -1.0;  // A = +-(x - bound), B = +-F
      const bool gamma = z[i] == 1.0;
      const internal::PhiPartials dp = internal::PhiDerivatives(
          function_, o_.penalized_fb_lambda, a, b, gamma, gamma ? sign * z[i] : 0.0,
          gamma ? sign * (*fz)[i] : 0.0, o_.min_tie_takes_b);
      c_i[i] = sign * dp.da;
      c_f[i] = sign * dp.db;
    }
  }

  // (A_i, B_i) of a pair row; false for an equation row.
  bool PairValues(PetscInt i, const LocalRead& xa, const LocalRead& fa, double* a,
                  double* b) const {
    const auto ii = static_cast<size_t>(i);
    if (rows_[ii] == Row::kLower) {
      *a = xa[i] - lower_[ii];
      *b = fa[i];
      return true;
    }
    if (rows_[ii] == Row::kUpper) {
      *a = upper_[ii] - xa[i];
      *b = -fa[i];
      return true;
    }
    return false;
  }

  // out = J v = c_F (F' v) + c_I v (v and out distinct, neither work2_).
  void MultNewton(Vec v, Vec out) {
    NCP_PETSC_CHECK(MatMult(p_.jacobian_matrix, v, out));
    NCP_PETSC_CHECK(VecPointwiseMult(out, c_f_, out));
    NCP_PETSC_CHECK(VecPointwiseMult(work2_, c_i_, v));
    NCP_PETSC_CHECK(VecAXPY(out, 1.0, work2_));
  }

  // out = |J| |v| = |c_F| (|F'||v|) + (|c_F F'_ii + c_I| - |c_F F'_ii|) |v|: the
  // off-diagonal entries of row i of J are c_F,i F'_ij, the diagonal c_F,i F'_ii + c_I,i
  // (v and out distinct, neither work2_).
  void MultAbsNewton(Vec v, Vec out) {
    UpdateAbsoluteSource();
    NCP_PETSC_CHECK(VecCopy(v, work2_));
    NCP_PETSC_CHECK(VecAbs(work2_));
    NCP_PETSC_CHECK(MatMult(impl_.abs_source, work2_, out));
    LocalRead abs_v(work2_), c_f(c_f_), c_i(c_i_), diag(diag_f_);
    LocalWrite o(out);
    for (PetscInt i = 0; i < local_; ++i) {
      const double cfd = c_f[i] * diag[i];
      o[i] = std::abs(c_f[i]) * PetscRealPart(o[i]) +
             (std::abs(cfd + c_i[i]) - std::abs(cfd)) * abs_v[i];
    }
  }

  // |F'| for the Jacobian of this iterate (once per Jacobian evaluation).
  void UpdateAbsoluteSource() {
    if (abs_source_current_) return;
    AbsoluteCopy(p_.jacobian_matrix, &impl_.abs_source);
    abs_source_current_ = true;
  }

  // J = diag(c_F) F' + diag(c_I).
  void FillNewtonMatrix() {
    Mat J = impl_.newton;
    NCP_PETSC_CHECK(
        MatCopy(p_.jacobian_matrix, J,
                impl_.same_pattern ? SAME_NONZERO_PATTERN : DIFFERENT_NONZERO_PATTERN));
    NCP_PETSC_CHECK(MatDiagonalScale(J, c_f_, nullptr));
    NCP_PETSC_CHECK(MatDiagonalSet(J, c_i_, ADD_VALUES));
  }

  // ---- the round-off floor of the test (Options::roundoff_ulps)
  // ------------------------- r_i = |c_F,i| (|F'||x|)_i + |c_I,i| |x_i|, the serial
  // solver's |da| |J_A||x| + |db| |J_B||x| (and |J_E||x| for equations) for these rows.
  bool WithinRoundoffFloor() {
    if (o_.roundoff_ulps == 0.0) return false;
    UpdateAbsoluteSource();
    NCP_PETSC_CHECK(VecCopy(x_, work2_));
    NCP_PETSC_CHECK(VecAbs(work2_));
    NCP_PETSC_CHECK(MatMult(impl_.abs_source, work2_, work_));  // |F'||x|
    bool within = true;
    {
      LocalRead phi(phi_), abs_fx(work_), abs_x(work2_), c_f(c_f_), c_i(c_i_);
      for (PetscInt i = 0; i < local_ && within; ++i) {
        const double r = std::abs(c_f[i]) * abs_fx[i] + std::abs(c_i[i]) * abs_x[i];
        within =
            internal::RowWithinRoundoffFloor(phi[i], o_.tolerance, o_.roundoff_ulps, r);
      }
    }
    return !AnyRank(comm_, !within);
  }

  // ---- trace, log, callback for iterate k; false when the callback stopped ------------
  bool Report(int k) {
    record_.iteration = k;
    record_.phi_inf = phi_inf_;
    record_.psi = psi_;
    record_.grad_psi_inf = have_jacobian_ && jacobian_ok_ ? NormInf(grad_) : 0.0;
    record_.degenerate_pairs = degenerate_count_;
    const bool reported = o_.keep_trace || o_.log_to_stderr || o_.callback;
    record_.time_s = reported ? Seconds(start_) : 0.0;
    if (o_.keep_trace) s_.trace.push_back(record_);
    if (o_.log_to_stderr)
      PetscFPrintf(comm_, PETSC_STDERR, "%5d %12.4e %12.4e %12.4e %10.3e %4d %4s %5d\n",
                   k, phi_inf_, psi_, record_.grad_psi_inf, record_.step_length,
                   record_.backtracks, record_.gradient_step ? "grad" : "newt",
                   degenerate_count_);
    if (o_.callback && AnyRank(comm_, !o_.callback(record_))) {
      Finish(
          TerminationType::kUserAbort,
          "the iteration callback stopped the solve at iteration " + std::to_string(k));
      return false;
    }
    return true;
  }

  // ---- step 1 and the safeguards; true when the solve ends here
  // ------------------------
  bool TestStop(int k) {
    if (converged_) {
      s_.roundoff_limited = roundoff_limited_;
      Finish(TerminationType::kConverged,
             internal::ConvergedMessage(o_, false, roundoff_limited_, phi_inf_, k));
      return true;
    }
    if (k >= o_.max_iterations) {
      Finish(TerminationType::kMaxIterations,
             internal::MaxIterationsMessage(o_, phi_inf_));
      return true;
    }
    if (OutOfTime("at iteration ", k)) return true;
    if (!jacobian_ok_) {
      Finish(TerminationType::kEvaluationFailure,
             "the Jacobian callback failed at iteration " + std::to_string(k));
      return true;
    }
    grad_inf_ = NormInf(grad_);
    if (stagnation_.Stagnated(static_cast<size_t>(k - first_k_), psi_, o_)) {
      Finish(TerminationType::kStationaryPoint,
             internal::StagnationMessage(o_, phi_inf_, grad_inf_));
      return true;
    }
    if (grad_inf_ == 0.0) {
      Finish(TerminationType::kStationaryPoint, internal::ZeroGradientMessage(phi_inf_));
      return true;
    }
    return false;
  }

  // Options::max_seconds passed on any rank? (collective only under a finite limit)
  bool OutOfTime(const char* where, int k) {
    if (!std::isfinite(o_.max_seconds)) return false;
    if (!AnyRank(comm_, Seconds(start_) > o_.max_seconds)) return false;
    Finish(TerminationType::kTimeLimit,
           internal::TimeLimitMessage(o_, where, k, phi_inf_));
    return true;
  }

  // ---- step 2: the direction d and slope_ = grad psi' d; true for d = -grad psi
  // --------
  bool ChooseDirection(int k) {
    const bool newton_solved = NewtonDirection();
    if (newton_solved) {
      slope_ = Dot(grad_, d_);
      PetscReal norm = 0.0;
      NCP_PETSC_CHECK(VecNorm(d_, NORM_2, &norm));
      if (internal::PassesDescentTest(slope_, norm, o_)) return false;
      ++s_.descent_test_failures;
    } else {
      ++s_.linear_solver_failures;
    }
    if (!o_.gradient_fallback) {
      if (!newton_solved)
        Finish(TerminationType::kLinearSolverFailure,
               "the Newton system is singular or the KSP solve (" +
                   impl_.report.ksp_type + " + " + impl_.report.pc_type +
                   ") failed at iteration " + std::to_string(k) +
                   " and gradient_fallback is off");
      return false;
    }
    NCP_PETSC_CHECK(VecCopy(grad_, d_));
    NCP_PETSC_CHECK(VecScale(d_, -1.0));
    slope_ = -Dot(grad_, grad_);
    ++s_.gradient_steps;
    return true;
  }

  // J d = -Phi (eq. 21) by the KSP; false when the KSP diverged, d is not finite or fails
  // the backward-error guard of globalization.hpp.
  bool NewtonDirection() {
    const auto t0 = Clock::now();
    NCP_PETSC_CHECK(VecCopy(phi_, work_));
    NCP_PETSC_CHECK(VecScale(work_, -1.0));
    if (impl_.symmetric_newton && !Symmetrize(work_)) {
      s_.linear_solver_time_s += Seconds(t0);
      return false;
    }
    const PetscErrorCode code = KSPSolve(impl_.ksp, work_, d_);
    KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
    PetscInt its = 0;
    if (code == 0) {
      NCP_PETSC_CHECK(KSPGetConvergedReason(impl_.ksp, &reason));
      NCP_PETSC_CHECK(KSPGetIterationNumber(impl_.ksp, &its));
      impl_.report.linear_iterations += static_cast<int>(its);
    }
    bool solved = !AnyRank(comm_, code != 0 || reason <= 0) && AllFinite(comm_, d_);
    if (solved) {
      MultNewton(d_, work_);  // J d + Phi
      NCP_PETSC_CHECK(VecAXPY(work_, 1.0, phi_));
      const double residual_inf = NormInf(work_);
      MultAbsNewton(d_, work_);  // |J||d|
      solved = internal::NewtonSolutionAccurate(residual_inf, phi_inf_, NormInf(work_));
    }
    s_.linear_solver_time_s += Seconds(t0);
    return solved;
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
    Mat S = impl_.newton;
    NCP_PETSC_CHECK(
        MatCopy(p_.jacobian_matrix, S,
                impl_.same_pattern ? SAME_NONZERO_PATTERN : DIFFERENT_NONZERO_PATTERN));
    PetscInt first = 0, last = 0;
    NCP_PETSC_CHECK(VecGetOwnershipRange(x_, &first, &last));
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
    return true;
  }

  // ---- step 3: Armijo line search (internal::ArmijoLineSearch)
  // ----------------------------
  bool LineSearch(int k, bool gradient) {
    const double reference =
        armijo_reference_.Update(static_cast<size_t>(k - first_k_), psi_);
    using Trial = internal::LineSearchTrial;
    const internal::LineSearchResult r = internal::ArmijoLineSearch(
        o_, reference, slope_,
        [&] { return OutOfTime("in the line search of iteration ", k); },
        [&](double t) {
          NCP_PETSC_CHECK(VecWAXPY(x_trial_, t, d_, x_));
          PetscBool unchanged = PETSC_FALSE;
          NCP_PETSC_CHECK(VecEqual(x_trial_, x_, &unchanged));
          if (unchanged) return Trial{Trial::kUnchanged, 0.0};
          if (!Evaluate(x_trial_, f_trial_, phi_trial_))
            return Trial{Trial::kNotEvaluable, 0.0};
          if (!AllFinite(comm_, phi_trial_)) return Trial{Trial::kNonFinite, 0.0};
          return Trial{Trial::kEvaluated, 0.5 * Dot(phi_trial_, phi_trial_)};
        });
    if (r.out_of_time) {
      s_.backtracks += r.backtracks;
      return false;
    }
    s_.backtracks += std::min(r.backtracks, o_.max_backtracks);
    step_ = r.step;
    backtracks_ = r.backtracks;
    if (!r.accepted) {
      const internal::Ending ending = internal::LineSearchFailure(
          o_, r, gradient ? "gradient" : "Newton", k, phi_inf_, grad_inf_);
      Finish(ending.termination, ending.message);
    }
    return r.accepted;
  }

  // ---- restart strategy (Options::merit_restarts): continue from mid(l, u, x^k)
  // --------
  bool Restart(int k) {
    if (!internal::MeritRestartApplies(s_.termination, restarts_left_, function_))
      return false;
    const NcpFunction stuck_function = function_;
    function_ = internal::OtherMeritFunction(function_);
    NCP_PETSC_CHECK(VecCopy(x_, x_trial_));
    {
      LocalWrite y(x_trial_);
      for (PetscInt i = 0; i < local_; ++i) {
        const auto ii = static_cast<size_t>(i);
        y[i] = std::max(lower_[ii], std::min(upper_[ii], PetscRealPart(y[i])));
      }
    }
    if (!Evaluate(x_trial_, f_trial_, phi_trial_) || !AllFinite(comm_, phi_trial_)) {
      function_ = stuck_function;
      return false;
    }
    NCP_PETSC_CHECK(VecCopy(x_trial_, x_));
    f_.Swap(f_trial_);
    phi_.Swap(phi_trial_);
    --restarts_left_;
    ++s_.merit_restarts;
    if (o_.keep_trace && !s_.trace.empty())
      s_.trace.pop_back();  // iterate k is reported anew
    finished_ = false;
    s_.termination = TerminationType::kNotSolved;
    first_k_ = k;
    if (o_.log_to_stderr)
      PetscFPrintf(comm_, PETSC_STDERR, "restart %d at iteration %d with %s\n",
                   s_.merit_restarts, k, ToString(function_));
    return true;
  }

  // ---- step 4: x^{k+1} = x^k + t d
  // -------------------------------------------------------
  void Accept(bool gradient) {
    NCP_PETSC_CHECK(VecCopy(x_trial_, x_));
    f_.Swap(f_trial_);
    phi_.Swap(phi_trial_);
    ++s_.iterations;
    PetscReal norm = 0.0;
    NCP_PETSC_CHECK(VecNorm(d_, NORM_2, &norm));
    record_.step_length = step_;
    record_.direction_norm = norm;
    record_.backtracks = backtracks_;
    record_.gradient_step = gradient;
    record_.regularized_step = false;
  }

  void Finish(TerminationType type, const std::string& message) {
    finished_ = true;
    s_.termination = type;
    s_.message = message;
    if (s_.merit_restarts > 0) s_.message += internal::RestartSuffix(s_.merit_restarts);
    s_.final_phi_inf = NormInf(phi_);
    s_.final_psi = 0.5 * Dot(phi_, phi_);
    s_.total_time_s = Seconds(start_);
  }

  Solver::Impl& impl_;
  const Options& o_;
  MPI_Comm comm_;
  const BoxMcp& p_;
  Vec x_;
  Summary& s_;
  const std::vector<Row> rows_;
  const std::vector<double> lower_, upper_;  // local, normalized (+-inf = no bound)
  const PetscInt local_, n_;
  OwnedVec f_, f_trial_, phi_, phi_trial_, grad_, d_, x_trial_, c_f_, c_i_, z_, f_z_,
      work_, work2_;
  OwnedVec fixed_values_;  // d_i of the rows the symmetrized system eliminates
  OwnedVec diag_f_;        // the diagonal of F' (0 where F' stores none)
  Clock::time_point start_;
  NcpFunction function_ = NcpFunction::kFischerBurmeister;
  int restarts_left_ = 0, first_k_ = 0;
  internal::StagnationTest stagnation_;
  internal::NonmonotoneReference armijo_reference_;
  IterationRecord record_;
  double phi_inf_ = 0.0, psi_ = 0.0, grad_inf_ = 0.0, slope_ = 0.0, step_ = 0.0;
  int backtracks_ = 0, degenerate_count_ = 0;
  bool converged_ = false, have_jacobian_ = false, jacobian_ok_ = true;
  bool roundoff_limited_ = false, finished_ = false;
  bool abs_source_current_ = false;  // impl_.abs_source is |F'| of this iterate
};

// ---------------------------------------------------------------------------------------
// The public API.

BoxMcp BoxMcp::FromFunctionPointers(ResidualFunctionPointer residual,
                                    JacobianFunctionPointer jacobian, void* context,
                                    Mat jacobian_matrix, Vec lower, Vec upper) {
  BoxMcp p;
  if (residual)
    p.residual = [residual, context](Vec x, Vec f) { return residual(x, f, context); };
  if (jacobian)
    p.jacobian = [jacobian, context](Vec x, Mat J) { return jacobian(x, J, context); };
  p.jacobian_matrix = jacobian_matrix;
  p.lower = lower;
  p.upper = upper;
  return p;
}

Solver::Solver(MPI_Comm comm, const Options& options, const std::string& options_prefix)
    : impl_(new Impl) {
  PetscBool initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (!initialized)
    throw std::invalid_argument(
        "ncp::petsc::Solver: PETSc is not initialized; call PetscInitialize "
        "before constructing the solver (and PetscFinalize after destroying it)");
  std::string error;
  if (!options.IsValid(&error))
    throw std::invalid_argument("ncp::petsc::Solver: " + error);
  if (options.regularized_direction)
    throw std::invalid_argument(
        "ncp::petsc::Solver: Options::regularized_direction = true is not "
        "available over PETSc (only the Newton and -grad psi directions)");
  if (options.linear_solver != LinearSolverType::kAuto)
    throw std::invalid_argument(
        std::string("ncp::petsc::Solver: Options::linear_solver = ") +
        ToString(options.linear_solver) +
        " names a serial backend; over PETSc the Newton systems are solved by "
        "the KSP (leave kAuto, choose with -" +
        options_prefix + "ksp_type / -" + options_prefix + "pc_type)");
  impl_->comm = comm;
  impl_->options = options;
  impl_->prefix = options_prefix;
  NCP_PETSC_CHECK(KSPCreate(comm, &impl_->ksp));
  NCP_PETSC_CHECK(KSPSetOptionsPrefix(impl_->ksp, options_prefix.c_str()));
  // Default: one direct solve by MUMPS' LU (Amestoy et al. 2001), exact up to round-off
  // like the serial backends, so that the iterates are the serial solver's.
  NCP_PETSC_CHECK(KSPSetType(impl_->ksp, KSPPREONLY));
  PC pc = nullptr;
  NCP_PETSC_CHECK(KSPGetPC(impl_->ksp, &pc));
  NCP_PETSC_CHECK(PCSetType(pc, PCLU));
  NCP_PETSC_CHECK(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  int size = 0;
  MPI_Comm_size(comm, &size);
  impl_->report.ranks = size;
}

Solver::~Solver() = default;
const Options& Solver::options() const { return impl_->options; }
KSP Solver::ksp() const { return impl_->ksp; }
const KspReport& Solver::ksp_report() const { return impl_->report; }

void Solver::Solve(const BoxMcp& problem, Vec x, Summary* summary) {
  Impl& impl = *impl_;
  const Options& o = impl.options;
  if (x == nullptr || summary == nullptr) Misuse("x and summary must not be null");
  if (!problem.residual || !problem.jacobian)
    Misuse("BoxMcp::residual and BoxMcp::jacobian must be set");
  if (problem.jacobian_matrix == nullptr) Misuse("BoxMcp::jacobian_matrix must be set");
  int compare = MPI_UNEQUAL;
  MPI_Comm_compare(PetscObjectComm(reinterpret_cast<PetscObject>(x)), impl.comm,
                   &compare);
  if (compare != MPI_IDENT && compare != MPI_CONGRUENT)
    Misuse("the start point lives on another communicator than the solver");
  if (problem.lower) CheckLayout(impl.comm, x, problem.lower, "lower");
  if (problem.upper) CheckLayout(impl.comm, x, problem.upper, "upper");
  CheckMatrixLayout(impl.comm, x, problem.jacobian_matrix);
  bool parallel = false;
  if (AnyRank(impl.comm, !IsAij(problem.jacobian_matrix, &parallel)))
    Misuse("the Jacobian matrix must be of type AIJ (MATSEQAIJ or MATMPIAIJ)");

  // Local bounds, normalized (|b| >= infinite_bound is no bound), and the row kinds.
  PetscInt n = 0, local = 0, first = 0, last = 0;
  NCP_PETSC_CHECK(VecGetSize(x, &n));
  NCP_PETSC_CHECK(VecGetLocalSize(x, &local));
  NCP_PETSC_CHECK(VecGetOwnershipRange(x, &first, &last));
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> lower(static_cast<size_t>(local), -kInf),
      upper(static_cast<size_t>(local), kInf);
  for (auto [bound, out] :
       {std::pair<Vec, std::vector<double>*>{problem.lower, &lower},
        std::pair<Vec, std::vector<double>*>{problem.upper, &upper}}) {
    if (!bound) continue;
    LocalRead a(bound);
    for (PetscInt i = 0; i < local; ++i)
      (*out)[static_cast<size_t>(i)] = NormalizeBound(a[i], o.infinite_bound);
  }
  CheckBoundsAndStart(impl.comm, first, lower, upper, x);
  std::vector<Row> rows(static_cast<size_t>(local));
  long long two_sided = LLONG_MAX;
  for (size_t i = 0; i < rows.size(); ++i) {
    const bool lo = std::isfinite(lower[i]), up = std::isfinite(upper[i]);
    rows[i] = !lo && !up                         ? Row::kFree
              : lo && up && lower[i] == upper[i] ? Row::kFixed
              : lo && up                         ? Row::kFree /* rejected below */
              : lo                               ? Row::kLower
                                                 : Row::kUpper;
    if (lo && up && lower[i] != upper[i] && two_sided == LLONG_MAX)
      two_sided = first + static_cast<long long>(i);
  }
  const long long first_two_sided = MinRanks(impl.comm, two_sided);
  if (first_two_sided != LLONG_MAX)
    Misuse("x[" + std::to_string(first_two_sided) +
           "] has two finite bounds l < u; the PETSc solver supports free, fixed, "
           "lower-bounded and "
           "upper-bounded components only (ncp::Solver handles two-sided bounds)");

  // Options::project_start_point: x0 <- mid(l, u, x0).
  long long moved = 0;
  if (o.project_start_point) {
    LocalWrite xa(x);
    for (PetscInt i = 0; i < local; ++i) {
      const auto ii = static_cast<size_t>(i);
      const double projected =
          std::max(lower[ii], std::min(upper[ii], PetscRealPart(xa[i])));
      if (projected != PetscRealPart(xa[i])) ++moved;
      xa[i] = projected;
    }
  }
  moved = SumRanks(impl.comm, moved);

  Iteration(impl, problem, x, *summary, std::move(rows), std::move(lower),
            std::move(upper), n)
      .Run();

  summary->projected_start_components = static_cast<int>(moved);
  if (moved > 0)
    summary->message +=
        " (" + std::to_string(moved) +
        " components of the start point were outside [l, u] and were projected onto it)";
}

}  // namespace ncp::petsc
