#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "contact/convex_qp.hpp"

// Ipopt 3.11 (Debian coinor-libipopt-dev), found through pkg-config.
#include <coin/IpIpoptApplication.hpp>
#include <coin/IpSolveStatistics.hpp>
#include <coin/IpTNLP.hpp>

#include "text_format.hpp"

namespace contact {
namespace {

using internal::Format;

std::string Shape(const SparseMatrix& A) {
  return std::to_string(A.rows()) + " x " + std::to_string(A.cols());
}

bool AllFinite(const SparseMatrix& A) {
  for (Eigen::Index k = 0; k < A.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(A, k); it; ++it)
      if (!std::isfinite(it.value())) return false;
  return true;
}

double MaxAbs(const SparseMatrix& A) {
  double result = 0.0;
  for (Eigen::Index k = 0; k < A.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(A, k); it; ++it)
      result = std::max(result, std::abs(it.value()));
  return result;
}

void ValidateProblem(const SparseMatrix& P, const Vector& q, const SparseMatrix& G,
                     const Vector& h, const Vector& x0) {
  const std::string who = "SolveConvexQpIpopt: ";
  const Eigen::Index n = q.size();
  const Eigen::Index m = h.size();
  if (n == 0) throw std::invalid_argument(who + "q must have at least 1 entry, got 0");
  if (P.rows() != n || P.cols() != n)
    throw std::invalid_argument(who + "P must be n x n = " + std::to_string(n) + " x " +
                                std::to_string(n) + " (n = q.size()), got " + Shape(P));
  if (G.rows() != m || G.cols() != n)
    throw std::invalid_argument(who + "G must be m x n = " + std::to_string(m) + " x " +
                                std::to_string(n) +
                                " (m = h.size(), n = q.size()), got " + Shape(G));
  if (x0.size() != n)
    throw std::invalid_argument(who + "x0 must have size n = " + std::to_string(n) +
                                ", got " + std::to_string(x0.size()));
  if (!AllFinite(P)) throw std::invalid_argument(who + "P has a non-finite entry");
  if (!AllFinite(G)) throw std::invalid_argument(who + "G has a non-finite entry");
  if (!q.allFinite()) throw std::invalid_argument(who + "q has a non-finite entry");
  if (!h.allFinite()) throw std::invalid_argument(who + "h has a non-finite entry");
  if (!x0.allFinite()) throw std::invalid_argument(who + "x0 has a non-finite entry");
  const SparseMatrix P_transpose = P.transpose();
  const double asymmetry = MaxAbs(SparseMatrix(P - P_transpose));
  const double scale = MaxAbs(P);
  if (asymmetry > 1e-12 * scale)
    throw std::invalid_argument(
        who + "P must be symmetric: max |P_ij - P_ji| must be <= " +
        Format(1e-12 * scale) + " (1e-12 max |P_ij|), got " + Format(asymmetry));
}

/// The QP as an Ipopt TNLP: variables x (unbounded), constraints g(x) = G x with
/// g_L = -inf, g_U = h. Ipopt's Lagrangian is f + lambda' g (Waechter and Biegler 2006),
/// so lambda is the KKT multiplier z >= 0 of G x <= h.
class QpTnlp : public Ipopt::TNLP {
 public:
  QpTnlp(const SparseMatrix& P, const Vector& q, const SparseMatrix& G, const Vector& h,
         const Vector& x0)
      : P_(P), q_(q), G_(G), h_(h), x0_(x0) {
    for (Eigen::Index col = 0; col < P.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(P, col); it; ++it)
        if (it.row() >= it.col()) {
          hessian_rows_.push_back(static_cast<Ipopt::Index>(it.row()));
          hessian_cols_.push_back(static_cast<Ipopt::Index>(it.col()));
          hessian_values_.push_back(it.value());
        }
    for (Eigen::Index col = 0; col < G.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(G, col); it; ++it) {
        jacobian_rows_.push_back(static_cast<Ipopt::Index>(it.row()));
        jacobian_cols_.push_back(static_cast<Ipopt::Index>(it.col()));
        jacobian_values_.push_back(it.value());
      }
  }

  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac_g,
                    Ipopt::Index& nnz_h_lag, IndexStyleEnum& index_style) override {
    n = static_cast<Ipopt::Index>(q_.size());
    m = static_cast<Ipopt::Index>(h_.size());
    nnz_jac_g = static_cast<Ipopt::Index>(jacobian_values_.size());
    nnz_h_lag = static_cast<Ipopt::Index>(hessian_values_.size());
    index_style = C_STYLE;
    return true;
  }

  bool get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u,
                       Ipopt::Index m, Ipopt::Number* g_l, Ipopt::Number* g_u) override {
    // +-1e19 are Ipopt's default nlp_upper_bound_inf / nlp_lower_bound_inf: "no bound".
    std::fill(x_l, x_l + n, -1e19);
    std::fill(x_u, x_u + n, 1e19);
    std::fill(g_l, g_l + m, -1e19);
    std::copy(h_.data(), h_.data() + m, g_u);
    return true;
  }

  bool get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* x, bool init_z,
                          Ipopt::Number*, Ipopt::Number*, Ipopt::Index, bool init_lambda,
                          Ipopt::Number*) override {
    if (init_z || init_lambda) return false;  // never requested with the options we set
    if (init_x) std::copy(x0_.data(), x0_.data() + n, x);
    return true;
  }

  bool eval_f(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Number& obj) override {
    const Eigen::Map<const Vector> xv(x, n);
    obj = 0.5 * xv.dot(P_ * xv) + q_.dot(xv);
    return true;
  }

  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool,
                   Ipopt::Number* grad_f) override {
    const Eigen::Map<const Vector> xv(x, n);
    Eigen::Map<Vector>(grad_f, n) = P_ * xv + q_;
    return true;
  }

  bool eval_g(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Index m,
              Ipopt::Number* g) override {
    const Eigen::Map<const Vector> xv(x, n);
    Eigen::Map<Vector>(g, m) = G_ * xv;
    return true;
  }

  bool eval_jac_g(Ipopt::Index, const Ipopt::Number*, bool, Ipopt::Index,
                  Ipopt::Index nele_jac, Ipopt::Index* iRow, Ipopt::Index* jCol,
                  Ipopt::Number* values) override {
    if (values == nullptr) {
      std::copy(jacobian_rows_.begin(), jacobian_rows_.end(), iRow);
      std::copy(jacobian_cols_.begin(), jacobian_cols_.end(), jCol);
    } else {
      std::copy(jacobian_values_.begin(), jacobian_values_.begin() + nele_jac, values);
    }
    return true;
  }

  /// Hessian of the Lagrangian = obj_factor P (the constraints are linear); lower
  /// triangle.
  bool eval_h(Ipopt::Index, const Ipopt::Number*, bool, Ipopt::Number obj_factor,
              Ipopt::Index, const Ipopt::Number*, bool, Ipopt::Index nele_hess,
              Ipopt::Index* iRow, Ipopt::Index* jCol, Ipopt::Number* values) override {
    if (values == nullptr) {
      std::copy(hessian_rows_.begin(), hessian_rows_.end(), iRow);
      std::copy(hessian_cols_.begin(), hessian_cols_.end(), jCol);
    } else {
      for (Ipopt::Index k = 0; k < nele_hess; ++k)
        values[k] = obj_factor * hessian_values_[k];
    }
    return true;
  }

  void finalize_solution(Ipopt::SolverReturn, Ipopt::Index n, const Ipopt::Number* x,
                         const Ipopt::Number*, const Ipopt::Number*, Ipopt::Index m,
                         const Ipopt::Number*, const Ipopt::Number* lambda, Ipopt::Number,
                         const Ipopt::IpoptData*,
                         Ipopt::IpoptCalculatedQuantities*) override {
    solution_ = Eigen::Map<const Vector>(x, n);
    multipliers_ = m > 0 ? Vector(Eigen::Map<const Vector>(lambda, m)) : Vector();
    has_solution_ = true;
  }

  bool has_solution() const { return has_solution_; }
  const Vector& solution() const { return solution_; }
  const Vector& multipliers() const { return multipliers_; }

 private:
  const SparseMatrix& P_;
  const Vector& q_;
  const SparseMatrix& G_;
  const Vector& h_;
  const Vector& x0_;
  std::vector<Ipopt::Index> hessian_rows_, hessian_cols_;
  std::vector<double> hessian_values_;
  std::vector<Ipopt::Index> jacobian_rows_, jacobian_cols_;
  std::vector<double> jacobian_values_;
  bool has_solution_ = false;
  Vector solution_;
  Vector multipliers_;
};

const char* IpoptStatusName(Ipopt::ApplicationReturnStatus status) {
  switch (status) {
    case Ipopt::Solve_Succeeded:
      return "Solve_Succeeded";
    case Ipopt::Solved_To_Acceptable_Level:
      return "Solved_To_Acceptable_Level";
    case Ipopt::Infeasible_Problem_Detected:
      return "Infeasible_Problem_Detected";
    case Ipopt::Search_Direction_Becomes_Too_Small:
      return "Search_Direction_Becomes_Too_Small";
    case Ipopt::Diverging_Iterates:
      return "Diverging_Iterates";
    case Ipopt::User_Requested_Stop:
      return "User_Requested_Stop";
    case Ipopt::Feasible_Point_Found:
      return "Feasible_Point_Found";
    case Ipopt::Maximum_Iterations_Exceeded:
      return "Maximum_Iterations_Exceeded";
    case Ipopt::Restoration_Failed:
      return "Restoration_Failed";
    case Ipopt::Error_In_Step_Computation:
      return "Error_In_Step_Computation";
    case Ipopt::Maximum_CpuTime_Exceeded:
      return "Maximum_CpuTime_Exceeded";
    case Ipopt::Not_Enough_Degrees_Of_Freedom:
      return "Not_Enough_Degrees_Of_Freedom";
    case Ipopt::Invalid_Problem_Definition:
      return "Invalid_Problem_Definition";
    case Ipopt::Invalid_Option:
      return "Invalid_Option";
    case Ipopt::Invalid_Number_Detected:
      return "Invalid_Number_Detected";
    case Ipopt::Unrecoverable_Exception:
      return "Unrecoverable_Exception";
    case Ipopt::NonIpopt_Exception_Thrown:
      return "NonIpopt_Exception_Thrown";
    case Ipopt::Insufficient_Memory:
      return "Insufficient_Memory";
    case Ipopt::Internal_Error:
      return "Internal_Error";
  }
  return "unknown Ipopt status";
}

ConvexQpStatus ToConvexQpStatus(Ipopt::ApplicationReturnStatus status) {
  switch (status) {
    case Ipopt::Solve_Succeeded:
      return ConvexQpStatus::kSolved;
    case Ipopt::Solved_To_Acceptable_Level:
      return ConvexQpStatus::kAcceptable;
    case Ipopt::Maximum_Iterations_Exceeded:
      return ConvexQpStatus::kMaxIterations;
    case Ipopt::Maximum_CpuTime_Exceeded:
      return ConvexQpStatus::kMaxTime;
    case Ipopt::Infeasible_Problem_Detected:
      return ConvexQpStatus::kInfeasible;
    case Ipopt::Diverging_Iterates:
      return ConvexQpStatus::kUnbounded;
    case Ipopt::Search_Direction_Becomes_Too_Small:
      return ConvexQpStatus::kSmallSearchDirection;
    default:
      return ConvexQpStatus::kFailed;
  }
}

/// Recomputes the unscaled KKT residuals of result->x, result->multipliers.
void ComputeResiduals(const SparseMatrix& P, const Vector& q, const SparseMatrix& G,
                      const Vector& h, ConvexQpResult* result) {
  const Vector& x = result->x;
  const Vector& z = result->multipliers;
  const Vector Px = P * x;
  result->objective = 0.5 * x.dot(Px) + q.dot(x);
  const Vector gradient = Px + q + G.transpose() * z;
  result->stationarity = gradient.lpNorm<Eigen::Infinity>();
  const Vector slack = h - G * x;
  result->constraint_violation =
      slack.size() > 0 ? std::max(0.0, -slack.minCoeff()) : 0.0;
  result->dual_infeasibility = z.size() > 0 ? std::max(0.0, -z.minCoeff()) : 0.0;
  result->complementarity =
      z.size() > 0 ? z.cwiseProduct(slack).lpNorm<Eigen::Infinity>() : 0.0;
}

}  // namespace

bool ConvexQpOptions::IsValid(std::string* error) const {
  const auto fail = [error](const std::string& text) {
    if (error != nullptr) *error = "ConvexQpOptions: " + text;
    return false;
  };
  const auto positive = [](double value) { return std::isfinite(value) && value > 0; };
  if (!positive(tolerance))
    return fail("tolerance must be finite and > 0, got " + Format(tolerance));
  if (!positive(constraint_violation_tolerance))
    return fail("constraint_violation_tolerance must be finite and > 0, got " +
                Format(constraint_violation_tolerance));
  if (!positive(dual_infeasibility_tolerance))
    return fail("dual_infeasibility_tolerance must be finite and > 0, got " +
                Format(dual_infeasibility_tolerance));
  if (!positive(complementarity_tolerance))
    return fail("complementarity_tolerance must be finite and > 0, got " +
                Format(complementarity_tolerance));
  if (max_iterations < 0)
    return fail("max_iterations must be >= 0, got " + std::to_string(max_iterations));
  if (!positive(max_cpu_seconds))
    return fail("max_cpu_seconds must be finite and > 0, got " + Format(max_cpu_seconds));
  if (print_level < 0 || print_level > 12)
    return fail("print_level must be in [0, 12], got " + std::to_string(print_level));
  if (!(std::isfinite(bound_relax_factor) && bound_relax_factor >= 0))
    return fail("bound_relax_factor must be finite and >= 0, got " +
                Format(bound_relax_factor));
  return true;
}

const char* ToString(ConvexQpStatus status) {
  switch (status) {
    case ConvexQpStatus::kNotSolved:
      return "not solved";
    case ConvexQpStatus::kSolved:
      return "solved";
    case ConvexQpStatus::kAcceptable:
      return "solved to acceptable level";
    case ConvexQpStatus::kMaxIterations:
      return "maximum iterations";
    case ConvexQpStatus::kMaxTime:
      return "maximum CPU time";
    case ConvexQpStatus::kInfeasible:
      return "infeasible";
    case ConvexQpStatus::kUnbounded:
      return "diverging iterates (unbounded?)";
    case ConvexQpStatus::kSmallSearchDirection:
      return "search direction too small";
    case ConvexQpStatus::kFailed:
      return "failed";
  }
  return "unknown ConvexQpStatus";
}

std::string ConvexQpResult::BriefReport() const {
  std::ostringstream out;
  out.precision(3);
  out << std::scientific << "ConvexQp: " << ToString(status) << " (" << message
      << "), iterations " << iterations << ", objective " << objective
      << ", stationarity " << stationarity << ", constraint violation "
      << constraint_violation << ", complementarity " << complementarity << ", time "
      << seconds << " s";
  return out.str();
}

ConvexQpResult SolveConvexQpIpopt(const SparseMatrix& P, const Vector& q,
                                  const SparseMatrix& G, const Vector& h,
                                  const Vector& x0, const ConvexQpOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  ValidateProblem(P, q, G, h, x0);
  std::string error;
  if (!options.IsValid(&error))
    throw std::invalid_argument("SolveConvexQpIpopt: " + error);

  ConvexQpResult result;
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = new Ipopt::IpoptApplication();
  Ipopt::SmartPtr<Ipopt::OptionsList> ipopt_options = app->Options();
  bool options_accepted = true;
  options_accepted &= ipopt_options->SetStringValue("sb", "yes");
  options_accepted &= ipopt_options->SetIntegerValue("print_level", options.print_level);
  options_accepted &= ipopt_options->SetNumericValue("tol", options.tolerance);
  options_accepted &= ipopt_options->SetNumericValue(
      "constr_viol_tol", options.constraint_violation_tolerance);
  options_accepted &= ipopt_options->SetNumericValue(
      "dual_inf_tol", options.dual_infeasibility_tolerance);
  options_accepted &=
      ipopt_options->SetNumericValue("compl_inf_tol", options.complementarity_tolerance);
  options_accepted &= ipopt_options->SetIntegerValue("max_iter", options.max_iterations);
  options_accepted &=
      ipopt_options->SetNumericValue("max_cpu_time", options.max_cpu_seconds);
  options_accepted &=
      ipopt_options->SetNumericValue("bound_relax_factor", options.bound_relax_factor);
  options_accepted &= ipopt_options->SetStringValue("hessian_constant", "yes");
  options_accepted &= ipopt_options->SetStringValue("jac_c_constant", "yes");
  options_accepted &= ipopt_options->SetStringValue("jac_d_constant", "yes");
  options_accepted &= ipopt_options->SetStringValue("mehrotra_algorithm",
                                                    options.mehrotra ? "yes" : "no");
  if (!options_accepted) {
    result.status = ConvexQpStatus::kFailed;
    result.message = "Ipopt rejected an option (see its output)";
  } else if (const Ipopt::ApplicationReturnStatus init = app->Initialize();
             init != Ipopt::Solve_Succeeded) {
    result.status = ConvexQpStatus::kFailed;
    result.message = std::string("Ipopt Initialize failed: ") + IpoptStatusName(init);
  } else {
    Ipopt::SmartPtr<QpTnlp> problem = new QpTnlp(P, q, G, h, x0);
    const Ipopt::ApplicationReturnStatus status = app->OptimizeTNLP(problem);
    result.status = ToConvexQpStatus(status);
    result.message = std::string("Ipopt: ") + IpoptStatusName(status) + " (" +
                     std::to_string(static_cast<int>(status)) + ")";
    if (Ipopt::IsValid(app->Statistics()))
      result.iterations = static_cast<int>(app->Statistics()->IterationCount());
    if (problem->has_solution()) {
      result.x = problem->solution();
      result.multipliers = problem->multipliers();
    }
  }
  if (result.x.size() != q.size()) {
    // Ipopt stopped before it had an iterate: report the start point with z = 0.
    result.x = x0;
    result.multipliers = Vector::Zero(h.size());
    if (result.status == ConvexQpStatus::kSolved) result.status = ConvexQpStatus::kFailed;
  }
  ComputeResiduals(P, q, G, h, &result);
  result.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace contact
