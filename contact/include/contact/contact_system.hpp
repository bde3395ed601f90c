/// \file contact_system.hpp
/// The complementarity system of one contact solve - a static equilibrium or one central
/// difference time step - in the mixed form of ncp (thesis eq. 82, 90, 94).
///
/// Given a symmetric positive definite S (free dofs x free dofs, global frame), a vector
/// q and the candidate contact nodes, find x and the contact forces such that
///
///     S x + q = sum_c F_c                                              (equilibrium)
///     F_c = -lambda_c n_c + tau_c        (force of the obstacle on the body at node c)
///     0 <= lambda_c  perp  gap_c = s_c - n_c . (u0_c + x_c) >= 0           (Signorini)
///     |tau_c| <= g_c, tau_c = -g_c slip_c / |slip_c| when slip_c != 0      (Tresca)
///
/// with n_c the unit OUTWARD normal of the body (pointing towards the obstacle), s_c the
/// initial gap along n_c, slip_c the tangential part of x_c, and g_c >= 0 the Tresca
/// bound. Coulomb friction is obtained as in the thesis (section 4.2) by the fixed point
/// g_c = f_c lambda_c of the previous time step (or of the previous static iterate).
///
/// Instances:
///   static contact:   S = K, q = -f, u0 = 0,  x = u                   (slip = u_t)
///   time step k:      S = M / Mmax, q = dt^2 Q^{t_k} / Mmax (eq. 73, 80, 81),
///                     u0 = u^{t_k}, x = du = u^{t_{k+1}} - u^{t_k}     (slip = du_t)
/// Forces in the system are in the units of S x + q; multiply by `force_scale` (1 for
/// static, Mmax / dt^2 for a step) to get newtons. Friction is written in nodal forces
/// against f_c times the nodal normal reaction, so stresses are forces / tributary area
/// and, with the lumped boundary matrix, this equals the stress form |g_t| <= f_c p.
///
/// Unknowns (thesis eq. 92, 95): the local-frame components y = R x of every free dof
/// (normal, tangent(s) at contact nodes; R rotates each contact node's free dofs into
/// (n, t1[, t2])), except at friction nodes (g_c > 0 and a free tangent):
///   one free tangent (2D, or 3D with one axis constrained): the tangential slot holds
///   du+
///       and two unknowns (du-, tau) are appended, with y_t = du+ - du- (eq. 89);
///   two free tangents (3D): the two tangential slots hold du+, du- and (g, w1, w2) are
///       appended, with y_T = (du+ - du-) (t1, t2), friction force tau = g (t1, t2),
///       t1^2 + t2^2 = 1 (eq. 59, 66, 67). The direction is stored scaled, w = kappa t
///       with kappa = max_c g_c, and the unit row as kappa (t1^2 + t2^2 - 1), so that
///       every unknown and row is in the force or displacement units of the system (a
///       per-node g_c would blow up at nodes that barely touch). Unscaled (t of order 1
///       beside increments of order 1e-6), DFK's descent test grad psi' d <= -rho |d|^p
///       with rho = 1e-8 rejects nearly every Newton direction that turns t, and the
///       method crawls along gradient steps - a likely cause of the thesis's Jacobian
///       counts.
/// Rows: equations first (every non-normal row of R(S x + q) - tau, then t1^2 + t2^2 -
/// 1), then pairs: (lambda_c, gap_c) for all contact nodes, (du+, tau + g), (du-, g -
/// tau).
///
/// Nodes with g_c = 0 carry no friction unknowns: with g = 0, du+ and du- are not unique
/// and the Jacobian would be singular (the likely reason the thesis needed random
/// perturbations of the Newton start, section 6.4).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "ncp/problem.hpp"
#include "ncp/solver.hpp"

namespace contact {

/// A candidate contact node in the numbering of the free (unconstrained) dofs.
struct ContactNode {
  int node = -1;  ///< mesh node id (for output only)
  int dofs[3] = {-1, -1,
                 -1};  ///< free-dof index of the x, y (, z) displacement components
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< unit outward normal of the body
  Eigen::Vector3d tangent1 = Eigen::Vector3d::Zero();  ///< unit tangent, normal x t1 = t2
  Eigen::Vector3d tangent2 = Eigen::Vector3d::Zero();  ///< 3D only
  double gap = 0.0;  ///< s_c: initial distance to the obstacle along the normal [m]
  double area =
      0.0;  ///< tributary length (2D, per unit thickness: times thickness) or area [m^2]
};

/// The rotation and the restriction maps of thesis eq. (55) on the free dofs. R rotates
/// the free components of every contact node into its frame (normal first, then the free
/// tangents), identity elsewhere; the local components y = R x split into
///   Y y: the normal component of each contact node (one row per node, in node order),
///   Z y: the tangential components (one row per free tangent),
///   X y: all other dofs,
/// so X'X + Y'Y + Z'Z = I and R is orthogonal. Throws std::invalid_argument naming the
/// node for an invalid dof, a shared dof, a non-orthonormal frame, a normal along a
/// constrained axis, or a non-finite gap.
struct RestrictionMaps {
  Eigen::SparseMatrix<double> R, X, Y, Z;
};
RestrictionMaps MakeRestrictionMaps(int dim, int num_free_dofs,
                                    const std::vector<ContactNode>& nodes);

/// ncp::Options defaults for contact solves: min_tie_takes_b = true (the pair is
/// (reaction, gap); at a tie the node is treated as closed) and a monotone line search
/// (nonmonotone_memory = 1: eq. 23 of Algorithm 1; chosen on 3D friction steps,
/// benchmarks/results/defaults/README.md).
ncp::Options ContactNcpOptions();

/// Completes the tangents of a unit normal. All components free: 2D t1 = (-n_y, n_x),
/// 3D a right-handed (n, t1, t2). With constrained components (dofs[a] = -1) the used
/// tangents span the free directions orthogonal to n and the constrained axes follow.
void CompleteContactFrame(int dim, ContactNode* node);

class ContactSystem final : public ncp::MixedProblem {
 public:
  /// dim = 2 or 3; S n x n symmetric positive definite (free dofs). The rotation of S
  /// into the contact frames is done once here. Throws std::invalid_argument on bad
  /// input.
  ContactSystem(int dim, const Eigen::SparseMatrix<double>& S,
                std::vector<ContactNode> nodes);

  /// Sets the data of one solve: q and u0 (size n) and one Tresca bound g_c >= 0 per node
  /// (empty = frictionless). Cheap: O(n); the friction unknowns follow the bounds > 0.
  void Update(const Eigen::VectorXd& q, const Eigen::VectorXd& u0,
              const Eigen::VectorXd& tresca_bound);

  /// Replaces the initial gap s_c [m] of every node (one per node, finite), e.g. after
  /// the obstacle moved; read by the next Update(). Throws std::invalid_argument on bad
  /// input.
  void SetGaps(const Eigen::VectorXd& gaps);

  /// The accuracy the solve is asked for, in system units (forces: the units of S x + q;
  /// displacements: those of x). With tol = ncp::Options::tolerance, every force row
  /// (equilibrium, normal reaction, the unit-direction row) is solved
  /// to force_floor + tol * force and every displacement row (gap, slip) to
  /// displacement_floor + tol * displacement - except the friction law of node c, solved
  /// to force_floor + tol * g_c against its own bound -, where the floors are the
  /// round-off of each row's computation (kRoundoffUlps units in the last place of the
  /// magnitudes of its terms) so that no test asks for more than double precision holds.
  /// force, displacement > 0. Until this is called, Scales() declines and ncp uses its
  /// plain absolute test.
  void SetResidualScales(double force, double displacement);
  /// Units in the last place of a row's terms that its round-off is taken to be.
  static constexpr double kRoundoffUlps = 16.0;
  bool Scales(const ncp::Vector& z0, ncp::ResidualScales* scales) override;

  int NumVariables() const override { return num_variables_; }
  int NumEquations() const override { return num_equations_; }
  int PairVariable(int j) const override {
    return pair_variable_[static_cast<size_t>(j)];
  }
  bool Evaluate(const ncp::Vector& z, ncp::Vector* E, ncp::Vector* A,
                ncp::Vector* B) override;
  /// The patterns of JE, JA, JB depend only on the set of friction nodes of the last
  /// Update(); at a fixed set, calls on the same matrices write values in place and do
  /// not allocate (tests/contact/test_no_allocation.cpp).
  bool Jacobian(const ncp::Vector& z, ncp::SparseMatrix* JE, ncp::SparseMatrix* JA,
                ncp::SparseMatrix* JB) override;

  /// Deterministic start from a guess of x (global frame) and, optionally, of the
  /// friction forces in the local tangent frame ((dim-1) x nodes, system units; e.g. the
  /// previous step's): local components, slip split into positive and negative parts.
  /// With two tangents (eq. 94) the direction t and magnitude g start from the force
  /// guess if it is at least 1e-3 g_c, else from the slip (g = -g_c, sliding), else t =
  /// t1 and g = g_c / 2: a zero magnitude would leave t in the unit-norm row only, a
  /// singular Jacobian.
  ncp::Vector StartPoint(const Eigen::VectorXd& x_guess,
                         const Eigen::MatrixXd& friction_guess = Eigen::MatrixXd()) const;

  /// Results at a solution z, in system units (multiply forces by force_scale).
  struct Result {
    Eigen::VectorXd x;              ///< global frame, free dofs
    Eigen::VectorXd normal_force;   ///< lambda_c >= 0 per node
    Eigen::MatrixXd tangent_force;  ///< per node: components along t1 (and t2), (dim-1) x
                                    ///< N (0 for tangents along constrained axes)
    Eigen::VectorXd gap;            ///< gap_c = s_c - n_c . (u0_c + x_c)
    Eigen::MatrixXd slip;           ///< tangential part of x_c along t1 (and t2)
  };
  Result Extract(const ncp::Vector& z) const;

  int num_friction_nodes() const { return num_friction_; }
  const std::vector<ContactNode>& nodes() const { return nodes_; }

 private:
  /// Per contact node: its local slots and friction unknowns.
  struct Layout {
    int num_free = 0;  ///< free components (1..dim): slots 0 = normal, then tangents
    int slot[3] = {-1, -1, -1};  ///< free dof holding local component a (a < num_free)
    int tangent_dim = 0;         ///< num_free - 1
    int friction = -1;           ///< friction node index k, or -1 (g_c = 0 or no tangent)
    int extra = -1;     ///< first appended unknown (1 tangent: du-, tau; 2: g, t1, t2)
    int unit_row = -1;  ///< row of t1^2 + t2^2 - 1 (2 tangents)
  };

  /// y = local components of x from the unknowns z.
  void LocalDisplacement(const ncp::Vector& z, Eigen::VectorXd* y) const;

  /// Calls emit(row, col, value) for every entry of D = dy/dz at z, in a fixed order that
  /// depends only on the layout, including entries whose value is 0 at this z.
  template <typename Emit>
  void ForEachDisplacementDerivative(const ncp::Vector& z, Emit&& emit) const;
  /// Calls emit(block, row, col, value) for every entry of JE (block 0), JA (1), JB (2)
  /// at z, given dr_ at z; fixed order as above; repeated (row, col) add up.
  template <typename Emit>
  void ForEachJacobianEntry(const ncp::Vector& z, Emit&& emit) const;
  /// Builds the patterns of D, S_local D, JE, JA, JB for the current layout.
  void BuildJacobianPatterns(const ncp::Vector& z);

  int dim_;
  int n_;                                                 // free dofs
  Eigen::SparseMatrix<double> rotation_;                  // R
  Eigen::SparseMatrix<double, Eigen::RowMajor> S_local_;  // R S R'
  Eigen::VectorXd q_local_, u0_local_;
  Eigen::VectorXd gap0_;  // s_c - n_c . u0_c per node: the gap before the increment
  double force_scale_ = 0.0, displacement_scale_ = 0.0;  // SetResidualScales (0: not set)
  double s_row_sum_ = 0.0;  // max_i sum_j |S_local_ij|: round-off of S x
  std::vector<ContactNode> nodes_;
  std::vector<Layout> layout_;
  Eigen::VectorXd bound_;  // g_c
  double direction_scale_ =
      1.0;  // kappa = max_c g_c: 3D directions are stored as w = kappa t

  // Bookkeeping.
  std::vector<int> row_kind_;  // per local dof: 0 plain, 1 normal, 2 friction tangential
  std::vector<int> equation_dofs_;  // local dofs whose row is an equation (in order)
  std::vector<int> equation_row_;   // per local dof: its row in E, or -1 (normal rows)
  Eigen::Index EquationRow(int dof) const {
    return equation_row_[static_cast<size_t>(dof)];
  }
  std::vector<int> pair_variable_;
  int num_friction_ = 0, num_variables_ = 0, num_equations_ = 0;

  mutable Eigen::VectorXd y_, r_;

  // Jacobian storage. The patterns depend only on the layout (which nodes carry friction
  // unknowns), so they are built on the first Jacobian() after Update() changed it, with
  // every entry that can be nonzero for the layout structural (explicit zeros kept, e.g.
  // t_a, slip and g in 3D); a Jacobian() call then only rewrites values in place:
  // entry k of ForEachDisplacementDerivative lands in D_.valuePtr()[d_position_[k]], the
  // k-th entry of block b of ForEachJacobianEntry adds into jacobian_position_[b][k].
  bool patterns_valid_ = false;
  Eigen::SparseMatrix<double, Eigen::RowMajor> D_;   // dy/dz, at most 3 entries per row
  Eigen::SparseMatrix<double, Eigen::RowMajor> dr_;  // d(R(Sx+q))/dz = S_local D
  Eigen::VectorXd dr_row_;  // one row of dr_, dense (zero between uses)
  std::vector<int> d_position_;
  ncp::SparseMatrix jacobian_pattern_[3];  // JE, JA, JB patterns (values unused)
  std::vector<int> jacobian_position_[3];
};

}  // namespace contact
