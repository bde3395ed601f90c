// The condensed frictional step on MPI ranks with the contact set gathered
// (StepMethod::kCondensed on ranks; docs/petsc.md, "The implicit step on ranks").
//
// The step of the serial condensed step with implicit Coulomb friction
// (contact/src/step/coulomb_fc_step.cpp, coulomb_step.hpp): with S = M / m_max (M the
// consistent or lumped mass, a parallel AIJ matrix), H the selection of the contact
// unknowns (every free component of every contact node) and W = H S^-1 H',
//     x_free = -H S^-1 q,   gap0_c = s_c - n_c . u^k_c,
//     F from the frictional contact problem (W, x_free, gap0) solved by ncp::fc,
//     du = S^-1 (H' F - q).
// The solves with M are distributed (PETSc KSP: MUMPS's Cholesky by default - CG with
// Jacobi on ranks of an executable where Ipopt's sequential MUMPS shadows the parallel
// one - or what the options database says under the prefix "mass_", e.g.
// -mass_ksp_type cg -mass_pc_type gamg); W is formed once from one distributed solve per
// contact unknown; x_free and u^k_c are gathered onto rank 0 by one VecScatter, rank 0
// solves the small contact problem with the serial step's CoulombStep (the same code and
// the same data as one process), and F is scattered back. The sparse step on ranks is
// the same step with W never formed (matrix_free; distributed_sparse_step.hpp).
#pragma once

#include <petscksp.h>

#include <memory>
#include <string>
#include <vector>

#include "contact/scene.hpp"
#include "distributed_body.hpp"
#include "distributed_sparse_step.hpp"
#include "step/coulomb_step.hpp"

namespace contact::petsc::internal {

/// With StepMethod::kAuto, the largest number of contact unknowns (free components of the
/// contact nodes) the distributed run gathers onto rank 0 for the condensed step: W is
/// dense there (8 n_u^2 bytes: 72 MB at the limit) and forming it takes n_u distributed
/// solves. Above it, kAuto runs the sparse step (W never formed); solver.step =
/// "condensed" runs the gathered step at any size.
constexpr int kMaxGatheredContactUnknowns = 3000;

/// The step a scene runs on ranks: explicit, condensed (gathered) or sparse. Rank 0,
/// after BuildSceneModel: for kAuto, the explicit step when the serial choice
/// (PredictStepCost) is explicit, else the condensed step when the contact unknowns are
/// at most kMaxGatheredContactUnknowns, else the sparse step. Throws
/// std::invalid_argument naming the friction formulation when the condensed or sparse
/// step is asked for with the lagged bound.
StepMethod ResolveDistributedStep(const Scene& scene, const SceneModel& built);

/// The number of contact unknowns of the contact nodes (free components).
int CountContactUnknowns(int dim, const std::vector<ContactNode>& nodes);

class CondensedGatheredStep {
 public:
  /// Collective. `body` must have its mass matrix (DistributedBody's
  /// assemble_mass_matrix). nodes: rank 0: the scene's contact nodes in the serial
  /// free-dof numbering (others: ignored, may be null); m_max [kg]: the largest entry of
  /// the serial M_FF (the step scaling S = M / m_max), the same on every rank. Throws
  /// std::invalid_argument when W is not positive definite (a contact node with no mass)
  /// or a solve with M fails.
  ///
  /// matrix_free (the sparse step on ranks, distributed_sparse_step.hpp): W is never
  /// formed; rank 0's contact Newton is the serial sparse step's (ncp::fc's operator
  /// problem, GMRES) and each of its products with W is one distributed solve with M in
  /// which every rank takes part (DelassusProducts). Its scaling diag(W) is taken as
  /// m_max / M_ii (exact for a lumped M; within a factor of about 2 of W_ii for a
  /// consistent one) instead of the serial step's probing.
  CondensedGatheredStep(MPI_Comm comm, const Scene& scene, const DistributedBody& body,
                        const std::vector<ContactNode>* nodes, double m_max,
                        bool matrix_free = false);
  ~CondensedGatheredStep();
  CondensedGatheredStep(const CondensedGatheredStep&) = delete;
  CondensedGatheredStep& operator=(const CondensedGatheredStep&) = delete;

  /// Step k -> k+1 (collective). On rank 0 fills *rec (contact force sums, Newton
  /// counts) and *contact (system units). False, on every rank, when the contact solve
  /// or a solve with M failed or a value is not finite; failure() says why.
  bool Step(long k, StepRecord* rec, ContactSystem::Result* contact);

  Vec displacement() const { return u_; }
  const std::string& failure() const { return failure_; }
  int num_contact_unknowns() const { return num_unknowns_; }
  /// The KSP and PC types of the solves with M, e.g. "preonly + cholesky (mumps)".
  const std::string& mass_solver() const { return mass_solver_; }
  /// Set-up [s]: the factor of M; W (n_u solves).
  double factor_seconds() const { return factor_seconds_; }
  double delassus_seconds() const { return delassus_seconds_; }
  /// Products with W the run took (the matrix-free step: one distributed solve each).
  long delassus_products() const { return products_ ? products_->products() : 0; }

 private:
  void CreateMassSolver();
  void BuildContactScatter(const std::vector<ContactNode>* nodes);
  void FormDelassus();
  // The matrix-free form: rank 0's CoulombStep on DelassusProducts, diag(W) ~ m_max /
  // M_ii.
  void SetUpOperator();
  // Collective: contact_ <- W contact_ (rank 0's entries; H' scattered to the owners, one
  // solve with S, H gathered); false (failure_ set) if the solve did not converge.
  bool MultiplyW();
  // The fc settings of the serial step (coulomb_fc_step.cpp FcOptions).
  ncp::fc::Options FcOptions() const;
  void SetInitialState();
  // x = S^-1 b = m_max M^-1 b; false (failure_ set) if the KSP did not converge.
  bool SolveS(Vec b, Vec x);
  // Rank 0: the contact problem of the step from the gathered x_free and u^k_c.
  bool SolveContact(const double maxima[3], StepRecord* rec,
                    ContactSystem::Result* contact);

  MPI_Comm comm_;
  int rank_;
  const Scene& scene_;
  const DistributedBody& body_;
  int dim_;
  double dt_, m_max_, force_scale_;
  int num_unknowns_ = 0;
  std::string failure_, mass_solver_;
  double factor_seconds_ = 0, delassus_seconds_ = 0;
  KSP ksp_ = nullptr;
  // Global -> rank 0's sequential Vec of the contact unknowns (in the serial order of H).
  VecScatter to_contact_ = nullptr;
  Vec contact_ = nullptr;  // rank 0: n_u entries; elsewhere 0
  // u^k [m]; du: the last increment u^k - u^{k-1} [m]; Ku [N]; Mdu_previous = M du
  // [kg m]; f_F [N]; q (system units); y = S^-1 q; rhs = H' F - q; Mdu of the new step.
  Vec u_ = nullptr, du_ = nullptr, Ku_ = nullptr, Mdu_previous_ = nullptr,
      f_free_ = nullptr, q_ = nullptr, y_ = nullptr, rhs_ = nullptr, Mdu_ = nullptr;
  // Rank 0: the contact nodes numbered on the contact unknowns, their gaps s_c, the
  // serial step's solver of the contact problem and its buffers.
  std::vector<ContactNode> nodes_;
  std::unique_ptr<::contact::internal::CoulombStep> coulomb_;
  // Every rank: the products with W while rank 0 solves the contact problem.
  std::unique_ptr<DelassusProducts> products_;
  Eigen::VectorXd x_free_, u_contact_, gap0_;
  double contact_force_max_ = 0.0;  // |r^k|_inf of the previous step [N]
  double tolerance_ = 0.0;
};

}  // namespace contact::petsc::internal
