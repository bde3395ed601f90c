// The condensed frictional step on MPI ranks with the contact set gathered
// (StepMethod::kCondensed on ranks; docs/petsc-contact-steps.md, "The condensed step on
// ranks").
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
// the same step with W never formed (ContactSolve below): either rank 0 runs the contact
// Newton on the gathered contact unknowns while all ranks serve its products with W
// (distributed_sparse_step.hpp), or every rank runs it on the contact unknowns of the
// contact nodes it owns, with every global quantity reduced (rank_reduction.hpp).
#pragma once

#include <petscksp.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "contact/scene.hpp"
#include "distributed_body.hpp"
#include "distributed_sparse_step.hpp"
#include "step/coulomb_step.hpp"
#include "step_record.hpp"

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

/// How the step's contact problem is held and solved on ranks.
enum class ContactSolve {
  /// The condensed step: W formed on rank 0 (n_u distributed solves), rank 0 solves.
  kGatheredDense,
  /// The sparse step, W never formed, contact unknowns gathered on rank 0: rank 0 runs
  /// the serial sparse step's contact Newton; every product with W is one distributed
  /// solve with M served by all ranks (DelassusProducts).
  kGatheredOperator,
  /// The sparse step, contact unknowns where their contact nodes are owned: every rank
  /// runs the same contact Newton (ncp::fc's operator problem with RankReduction) on its
  /// own contact nodes; a product with W sets H' F on the owned dofs, solves with M, and
  /// reads H y back on the same rank - no gather, nothing of size n_u on one rank.
  kDistributed,
};

/// The sparse step's ContactSolve on ranks: kDistributed, or kGatheredOperator when the
/// PETSc options database says -contact_newton gathered. Collective (every rank reads the
/// same options). Throws std::invalid_argument naming the value otherwise.
ContactSolve SparseContactSolve();

class CondensedGatheredStep {
 public:
  /// Collective. `body` must have its mass matrix (DistributedBody's
  /// assemble_mass_matrix). nodes: rank 0: the scene's contact nodes in the serial
  /// free-dof numbering (others: ignored, may be null); m_max [kg]: the largest entry of
  /// the serial M_FF (the step scaling S = M / m_max), the same on every rank. Throws
  /// std::invalid_argument when W is not positive definite (a contact node with no mass)
  /// or a solve with M fails.
  ///
  /// solve (ContactSolve): kGatheredDense forms W; with kGatheredOperator and
  /// kDistributed (the sparse step on ranks) W is never formed and the contact Newton is
  /// the serial sparse step's (ncp::fc's operator problem, GMRES), each of its products
  /// with W one distributed solve with M. Its scaling diag(W) is taken as m_max / M_ii
  /// (exact for a lumped M; within a factor of about 2 of W_ii for a consistent one)
  /// instead of the serial step's probing. With kDistributed `nodes` is not read (each
  /// rank takes its owned contact nodes from the body).
  ///
  /// The constructor factors M and sets up the start; the contact problem's set-up (W
  /// formed, the matrix-free operator, or each rank's part of the distributed Newton)
  /// waits for SetUpContact, so that the run can check dt against dt_crit with this
  /// step's solver first (SolveMass).
  /// complete_start: the node data's u^{-1} is u^0 - dt v^0 without its acceleration
  /// term (rank 0 had no M); it is completed here as the serial prescribed start does
  /// (dynamics.cpp SetInitialState): u^{-1} += dt^2 / 2 M^-1 (f(t_0) - K u^0), by one
  /// solve with M.
  CondensedGatheredStep(MPI_Comm comm, const Scene& scene, const DistributedBody& body,
                        const std::vector<ContactNode>* nodes, double m_max,
                        ContactSolve solve = ContactSolve::kGatheredDense,
                        bool complete_start = false);
  ~CondensedGatheredStep();
  CondensedGatheredStep(const CondensedGatheredStep&) = delete;
  CondensedGatheredStep& operator=(const CondensedGatheredStep&) = delete;

  /// Step k -> k+1 (collective), u^{k+1} and K u^{k+1}; *part and *results: what the
  /// step's record needs from this rank (StepGather, StepRecorder: rank 0 sends every
  /// contact node's result, the other ranks none). recorder: rank 0's (the scales the
  /// contact problem is solved against; null elsewhere). On rank 0 fills rec's Newton
  /// counts. False, on every rank, when the contact solve or a solve with
  /// M failed; failure() says why. A non-finite increment is reported in *part.
  bool Step(long k, bool stop_requested, const StepRecorder* recorder, RankStepPart* part,
            std::vector<NodeResult>* results, StepRecord* rec);

  /// Collective: W formed on rank 0 (the condensed step) or the matrix-free operator
  /// (the solve), and rank 0's solver of the contact problem. Once, before Step.
  void SetUpContact();

  /// Collective: x = M^-1 b [global Vecs of the body's DM] by the step's solver of M (to
  /// its relative tolerance); false (failure() says why) if the solve did not converge.
  bool SolveMass(Vec b, Vec x);

  /// Collective: the energy balance's start from u^0, u^{-1}, K u^0 and M (u^0 -
  /// u^{-1}) on the ranks (EnergyBalance's constructor, its three dot products summed
  /// in rank order), the same on every rank.
  ::contact::internal::EnergyBalance StartEnergy() const;

  Vec displacement() const { return u_; }
  Vec previous_displacement() const { return u_previous_; }
  const std::string& failure() const { return failure_; }
  int num_contact_unknowns() const { return num_unknowns_; }
  /// The KSP and PC types of the solves with M, e.g. "preonly + cholesky (mumps)".
  const std::string& mass_solver() const { return mass_solver_; }
  /// Set-up [s]: the factor of M; W (n_u solves).
  double factor_seconds() const { return factor_seconds_; }
  double delassus_seconds() const { return delassus_seconds_; }
  /// Products with W the run took (the matrix-free step: one distributed solve each).
  long delassus_products() const {
    return distributed() ? owned_products_ : products_ ? products_->products() : 0;
  }
  ContactSolve contact_solve() const { return solve_; }

 private:
  void CreateMassSolver();
  void BuildContactScatter(const std::vector<ContactNode>* nodes);
  void FormDelassus();
  // The matrix-free form: rank 0's CoulombStep on DelassusProducts, diag(W) ~ m_max /
  // M_ii.
  void SetUpOperator();
  // kDistributed: this rank's owned contact nodes (numbered on its contact unknowns, in
  // the serial node order) and its part of the contact Newton (CoulombStep with
  // RankReduction), diag(W) ~ m_max / M_ii as SetUpOperator.
  void SetUpDistributed();
  bool distributed() const { return solve_ == ContactSolve::kDistributed; }
  // kDistributed: the owned contact unknowns of a global Vec; *x = W F on them
  // (collective: H' F on the owned dofs, one solve with S, H y read back), NaN entries if
  // the solve failed.
  void ReadOwned(Vec from, Eigen::VectorXd* to) const;
  void WriteOwned(const Eigen::VectorXd& from, Vec to);
  void MultiplyOwned(const Eigen::VectorXd& F, Eigen::VectorXd* x);
  // Collective: contact_ <- W contact_ (rank 0's entries; H' scattered to the owners, one
  // solve with S, H gathered); false (failure_ set) if the solve did not converge.
  bool MultiplyW();
  // Rank 0: coulomb_ = make() unless `error` is set already (make's exception into it),
  // the contact buffers sized; then every rank throws rank 0's error (collective).
  void SetUpContactSolver(
      const std::function<std::unique_ptr<::contact::internal::CoulombStep>()>& make,
      std::string error);
  // The fc settings of the serial step (coulomb_fc_step.cpp FcOptions).
  ncp::fc::Options FcOptions() const;
  void SetInitialState(bool complete_start);
  // x = S^-1 b = m_max M^-1 b; false (failure_ set) if the KSP did not converge.
  // step_force: the step's force scale F [N] (an iterative solve to a thousandth of its
  // force accuracy), 0 for the set-up's solves and the sparse step's products with W
  // (to rtol).
  bool SolveS(Vec b, Vec x, double step_force);
  // x = M^-1 b, as SolveS without the scaling.
  bool SolveM(Vec b, Vec x, double step_force);
  // Q^k, q, and this rank's maxima of the step's scales into part (dynamics.cpp
  // LoadStep).
  void LoadStep(double factor, RankStepPart* part);
  // Global -> contact_ and, with `to`, rank 0's Eigen vector of the contact unknowns
  // (collective).
  void GatherContact(Vec from, Eigen::VectorXd* to);
  // Rank 0: to <- contact_ (no-op on the other ranks).
  void ReadContact(Eigen::VectorXd* to) const;
  // Rank 0's contact_ -> the global Vec `to`, zero off the contact unknowns (collective).
  void ScatterContact(Vec to);
  // Rank 0 (kDistributed: every rank, its nodes): gap0 from u^k_c; the penetration of
  // u^k [m].
  double SetGaps();
  // Rank 0 (kDistributed: every rank, its part): the contact problem of the step from
  // x_free and gap0, against the step's scales F [N] and D [m]; F into force_.
  bool SolveContact(double force, double displacement, StepRecord* rec);
  // u^{k+1}, M du, K u^{k+1}, r and this rank's sums and maxima (dynamics.cpp
  // MeasureStep); the state moved on to the next step.
  void Advance(double factor, RankStepPart* part);
  // Rank 0: every contact node's result and r, u^{k+1}, u^{k-1} at its unknowns
  // (collective: the gathers).
  void Results(std::vector<NodeResult>* results);

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
  std::vector<Vec*> Vectors() {
    return {&u_, &u_previous_, &u_next_, &du_,  &Ku_, &Mdu_previous_, &Q_, &f_free_,
            &q_, &y_,          &rhs_,    &Mdu_, &r_};
  }
  // u^k, u^{k-1}, u^{k+1} [m]; du: the last increment [m]; Ku = K u^k [N]; Mdu_previous
  // = M (u^k - u^{k-1}) [kg m]; Q^k, f_F [N]; q (system units); y = S^-1 q; rhs = H' F -
  // q; Mdu of the new step; r = M du / dt^2 + Q^k [N].
  Vec u_ = nullptr, u_previous_ = nullptr, u_next_ = nullptr, du_ = nullptr,
      Ku_ = nullptr, Mdu_previous_ = nullptr, Q_ = nullptr, f_free_ = nullptr,
      q_ = nullptr, y_ = nullptr, rhs_ = nullptr, Mdu_ = nullptr, r_ = nullptr;
  std::vector<char> contact_dof_;  // per owned entry: a dof of a contact node
  // Rank 0 (kDistributed: every rank, its owned ones): the contact nodes numbered on the
  // contact unknowns, their gaps s_c, the serial step's solver of the contact problem and
  // its buffers.
  ContactSolve solve_;
  std::vector<ContactNode> nodes_;
  // kDistributed: per node of nodes_ its index in the serial order; per contact unknown
  // its index in the owned part of the global Vecs; the products with W; why the last
  // failed product failed.
  std::vector<int> node_index_;
  std::vector<PetscInt> owned_unknowns_;
  long owned_products_ = 0;
  std::string product_failure_;
  std::unique_ptr<::contact::internal::CoulombStep> coulomb_;
  // Every rank: the products with W while rank 0 solves the contact problem (the
  // sparse step's; the condensed step's Run only brackets rank 0's solve).
  std::unique_ptr<DelassusProducts> products_;
  Eigen::VectorXd x_free_, u_contact_, gap0_, r_contact_, u_next_contact_,
      u_previous_contact_, force_, product_in_;
  ContactSystem::Result contact_result_;
  double tolerance_ = 0.0;
  PetscReal rtol_ = 0.0;  // the KSP's relative tolerance (1e-12 or the options')
  PetscInt max_its_ = 0;
};

}  // namespace contact::petsc::internal
