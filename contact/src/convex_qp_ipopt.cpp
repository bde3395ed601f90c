#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "contact/convex_qp.hpp"
#include "text_format.hpp"
#ifdef CONTACT_WITH_IPOPT
#include "ipopt_library.hpp"
#endif

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

#ifdef CONTACT_WITH_IPOPT
/// The QP for Ipopt's C interface: variables x (unbounded), constraints g(x) = G x with
/// g_L = -inf, g_U = h. Ipopt's Lagrangian is f + lambda' g (Waechter and Biegler 2006),
/// so lambda is the KKT multiplier z >= 0 of G x <= h. Hessian (obj_factor P, the
/// constraints being linear: lower triangle) and Jacobian as triplets, C indexing.
struct QpCallbacks {
  QpCallbacks(const SparseMatrix& P_in, const Vector& q_in, const SparseMatrix& G_in)
      : P(P_in), q(q_in), G(G_in) {
    for (Eigen::Index col = 0; col < P.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(P, col); it; ++it)
        if (it.row() >= it.col()) {
          hessian_rows.push_back(static_cast<Index>(it.row()));
          hessian_cols.push_back(static_cast<Index>(it.col()));
          hessian_values.push_back(it.value());
        }
    for (Eigen::Index col = 0; col < G.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(G, col); it; ++it) {
        jacobian_rows.push_back(static_cast<Index>(it.row()));
        jacobian_cols.push_back(static_cast<Index>(it.col()));
        jacobian_values.push_back(it.value());
      }
    // CreateIpoptProblem refuses m > 0 with no Jacobian entry: one structural zero.
    if (G.rows() > 0 && jacobian_values.empty()) {
      jacobian_rows.push_back(0);
      jacobian_cols.push_back(0);
      jacobian_values.push_back(0.0);
    }
  }

  const SparseMatrix& P;
  const Vector& q;
  const SparseMatrix& G;
  std::vector<Index> hessian_rows, hessian_cols;
  std::vector<double> hessian_values;
  std::vector<Index> jacobian_rows, jacobian_cols;
  std::vector<double> jacobian_values;
  int iterations = -1;  ///< the last iteration Ipopt reported (intermediate callback)
};

QpCallbacks& Data(UserDataPtr user_data) { return *static_cast<QpCallbacks*>(user_data); }

Bool EvalF(Index n, Number* x, Bool, Number* obj, UserDataPtr user_data) {
  const QpCallbacks& qp = Data(user_data);
  const Eigen::Map<const Vector> xv(x, n);
  *obj = 0.5 * xv.dot(qp.P * xv) + qp.q.dot(xv);
  return TRUE;
}

Bool EvalGradF(Index n, Number* x, Bool, Number* grad_f, UserDataPtr user_data) {
  const QpCallbacks& qp = Data(user_data);
  const Eigen::Map<const Vector> xv(x, n);
  Eigen::Map<Vector>(grad_f, n) = qp.P * xv + qp.q;
  return TRUE;
}

Bool EvalG(Index n, Number* x, Bool, Index m, Number* g, UserDataPtr user_data) {
  const Eigen::Map<const Vector> xv(x, n);
  Eigen::Map<Vector>(g, m) = Data(user_data).G * xv;
  return TRUE;
}

Bool EvalJacG(Index, Number*, Bool, Index, Index nele_jac, Index* iRow, Index* jCol,
              Number* values, UserDataPtr user_data) {
  const QpCallbacks& qp = Data(user_data);
  if (values == nullptr) {
    std::copy(qp.jacobian_rows.begin(), qp.jacobian_rows.end(), iRow);
    std::copy(qp.jacobian_cols.begin(), qp.jacobian_cols.end(), jCol);
  } else {
    std::copy(qp.jacobian_values.begin(), qp.jacobian_values.begin() + nele_jac, values);
  }
  return TRUE;
}

Bool EvalH(Index, Number*, Bool, Number obj_factor, Index, Number*, Bool, Index nele_hess,
           Index* iRow, Index* jCol, Number* values, UserDataPtr user_data) {
  const QpCallbacks& qp = Data(user_data);
  if (values == nullptr) {
    std::copy(qp.hessian_rows.begin(), qp.hessian_rows.end(), iRow);
    std::copy(qp.hessian_cols.begin(), qp.hessian_cols.end(), jCol);
  } else {
    for (Index k = 0; k < nele_hess; ++k) values[k] = obj_factor * qp.hessian_values[k];
  }
  return TRUE;
}

Bool RecordIteration(Index, Index iter_count, Number, Number, Number, Number, Number,
                     Number, Number, Number, Index, UserDataPtr user_data) {
  Data(user_data).iterations = static_cast<int>(iter_count);
  return TRUE;
}

const char* IpoptStatusName(ApplicationReturnStatus status) {
  switch (status) {
    case Solve_Succeeded:
      return "Solve_Succeeded";
    case Solved_To_Acceptable_Level:
      return "Solved_To_Acceptable_Level";
    case Infeasible_Problem_Detected:
      return "Infeasible_Problem_Detected";
    case Search_Direction_Becomes_Too_Small:
      return "Search_Direction_Becomes_Too_Small";
    case Diverging_Iterates:
      return "Diverging_Iterates";
    case User_Requested_Stop:
      return "User_Requested_Stop";
    case Feasible_Point_Found:
      return "Feasible_Point_Found";
    case Maximum_Iterations_Exceeded:
      return "Maximum_Iterations_Exceeded";
    case Restoration_Failed:
      return "Restoration_Failed";
    case Error_In_Step_Computation:
      return "Error_In_Step_Computation";
    case Maximum_CpuTime_Exceeded:
      return "Maximum_CpuTime_Exceeded";
    case Not_Enough_Degrees_Of_Freedom:
      return "Not_Enough_Degrees_Of_Freedom";
    case Invalid_Problem_Definition:
      return "Invalid_Problem_Definition";
    case Invalid_Option:
      return "Invalid_Option";
    case Invalid_Number_Detected:
      return "Invalid_Number_Detected";
    case Unrecoverable_Exception:
      return "Unrecoverable_Exception";
    case NonIpopt_Exception_Thrown:
      return "NonIpopt_Exception_Thrown";
    case Insufficient_Memory:
      return "Insufficient_Memory";
    case Internal_Error:
      return "Internal_Error";
  }
  return "unknown Ipopt status";
}

ConvexQpStatus ToConvexQpStatus(ApplicationReturnStatus status) {
  switch (status) {
    case Solve_Succeeded:
      return ConvexQpStatus::kSolved;
    case Solved_To_Acceptable_Level:
      return ConvexQpStatus::kAcceptable;
    case Maximum_Iterations_Exceeded:
      return ConvexQpStatus::kMaxIterations;
    case Maximum_CpuTime_Exceeded:
      return ConvexQpStatus::kMaxTime;
    case Infeasible_Problem_Detected:
      return ConvexQpStatus::kInfeasible;
    case Diverging_Iterates:
      return ConvexQpStatus::kUnbounded;
    case Search_Direction_Becomes_Too_Small:
      return ConvexQpStatus::kSmallSearchDirection;
    default:
      return ConvexQpStatus::kFailed;
  }
}

/// Sets the options, runs Ipopt from x0 and fills result's status, message, iterations,
/// x and z (x0 and z = 0 where Ipopt stopped before it had an iterate).
void SolveWithIpopt(const internal::IpoptLibrary& ipopt, const SparseMatrix& P,
                    const Vector& q, const SparseMatrix& G, const Vector& h,
                    const Vector& x0, const ConvexQpOptions& options,
                    ConvexQpResult* result) {
  const auto n = static_cast<Index>(q.size());
  const auto m = static_cast<Index>(h.size());
  QpCallbacks qp(P, q, G);
  // +-1e19 are Ipopt's default nlp_upper_bound_inf / nlp_lower_bound_inf: "no bound".
  std::vector<Number> x_lower(n, -1e19), x_upper(n, 1e19), g_lower(m, -1e19);
  std::vector<Number> g_upper(h.data(), h.data() + m);
  const std::unique_ptr<IpoptProblemInfo, decltype(ipopt.free_problem)> problem(
      ipopt.create_problem(n, x_lower.data(), x_upper.data(), m, g_lower.data(),
                           g_upper.data(), static_cast<Index>(qp.jacobian_values.size()),
                           static_cast<Index>(qp.hessian_values.size()), /*C style*/ 0,
                           EvalF, EvalG, EvalGradF, EvalJacG, EvalH),
      ipopt.free_problem);
  if (!problem) {
    result->status = ConvexQpStatus::kFailed;
    result->message = "Ipopt refused the problem (CreateIpoptProblem)";
    return;
  }
  // The C interface takes char*: keyword and value copied into strings it may not keep.
  const auto text = [&](std::string keyword, std::string value) {
    return ipopt.add_string_option(problem.get(), keyword.data(), value.data()) != FALSE;
  };
  const auto number = [&](std::string keyword, double value) {
    return ipopt.add_number_option(problem.get(), keyword.data(), value) != FALSE;
  };
  const auto integer = [&](std::string keyword, int value) {
    return ipopt.add_integer_option(problem.get(), keyword.data(), value) != FALSE;
  };
  bool options_accepted = true;
  options_accepted &= text("sb", "yes");
  options_accepted &= integer("print_level", options.print_level);
  options_accepted &= number("tol", options.tolerance);
  options_accepted &= number("constr_viol_tol", options.constraint_violation_tolerance);
  options_accepted &= number("dual_inf_tol", options.dual_infeasibility_tolerance);
  options_accepted &= number("compl_inf_tol", options.complementarity_tolerance);
  options_accepted &= integer("max_iter", options.max_iterations);
  options_accepted &= number("max_cpu_time", options.max_cpu_seconds);
  options_accepted &= number("bound_relax_factor", options.bound_relax_factor);
  options_accepted &= text("hessian_constant", "yes");
  options_accepted &= text("jac_c_constant", "yes");
  options_accepted &= text("jac_d_constant", "yes");
  options_accepted &= text("mehrotra_algorithm", options.mehrotra ? "yes" : "no");
  if (!options_accepted) {
    result->status = ConvexQpStatus::kFailed;
    result->message = "Ipopt rejected an option (see its output)";
    return;
  }
  ipopt.set_intermediate_callback(problem.get(), RecordIteration);
  Vector x = x0;
  Vector z = Vector::Zero(m);
  const ApplicationReturnStatus status =
      ipopt.solve(problem.get(), x.data(), nullptr, nullptr, m > 0 ? z.data() : nullptr,
                  nullptr, nullptr, &qp);
  result->status = ToConvexQpStatus(status);
  result->message = std::string("Ipopt: ") + IpoptStatusName(status) + " (" +
                    std::to_string(static_cast<int>(status)) + ")";
  result->iterations = qp.iterations;
  result->x = std::move(x);
  result->multipliers = std::move(z);
}

#endif  // CONTACT_WITH_IPOPT

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

bool BuiltWithIpopt() {
#ifdef CONTACT_WITH_IPOPT
  return true;
#else
  return false;
#endif
}

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
#ifdef CONTACT_WITH_IPOPT
  const internal::IpoptLibrary& ipopt = internal::LoadIpopt();
  if (!ipopt.error.empty()) {
    result.status = ConvexQpStatus::kFailed;
    result.message = ipopt.error;
  } else {
    SolveWithIpopt(ipopt, P, q, G, h, x0, options, &result);
  }
#else
  result.status = ConvexQpStatus::kFailed;
  result.message = kWithoutIpopt;
#endif
  if (result.x.size() != q.size()) {
    // Ipopt could not be run: report the start point with z = 0.
    result.x = x0;
    result.multipliers = Vector::Zero(h.size());
  }
  ComputeResiduals(P, q, G, h, &result);
  result.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace contact
