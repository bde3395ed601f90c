// Semismooth Newton on one step's ContactSystem, shared by the Newton-based step methods
// (full_step.cpp, condensed_step.cpp): the start from the previous step's friction forces
// and the restart without them.
#pragma once

#include <Eigen/Core>
#include <stdexcept>
#include <string>

#include "contact/contact_system.hpp"
#include "ncp/solver.hpp"
#include "step/step_method.hpp"

namespace contact::internal {

class NewtonStep {
 public:
  /// friction: the run has a friction coefficient > 0 (the friction forces of every
  /// solved step are kept as the start of the next).
  NewtonStep(const ncp::Options& options, bool friction)
      : solver_(options), friction_(friction) {}

  /// Solves `system` (Update()d and scaled) from the guess x of its unknowns x; *z gets
  /// the solution. With friction, the start from the previous friction forces can sit
  /// next to the degenerate point of thesis eq. (94) (a friction force much smaller than
  /// its bound leaves the direction t nearly undetermined; seen in Table 3 at step 29): a
  /// failed solve is retried once from the start without the force guess (direction from
  /// the slip, or t1 with g_c / 2), counted in StepOutcome::friction_restarts.
  StepOutcome Solve(ContactSystem* system, const Eigen::VectorXd& guess, ncp::Vector* z);

  /// Keeps the friction forces of a solved step (local frames, system units) for the
  /// next.
  void KeepFriction(const ContactSystem::Result& result) {
    if (friction_) friction_previous_ = result.tangent_force;
  }
  /// The kept friction forces ((dim-1) x nodes; empty before the first solved step).
  const Eigen::MatrixXd& kept_friction() const { return friction_previous_; }
  /// Restores kept_friction() of a checkpoint: empty, or rows x nodes of this system.
  /// Throws std::invalid_argument otherwise.
  void RestoreFriction(const Eigen::MatrixXd& friction, Eigen::Index rows,
                       Eigen::Index nodes) {
    if (friction.size() != 0 &&
        (!friction_ || friction.rows() != rows || friction.cols() != nodes))
      throw std::invalid_argument(
          "the warm start (previous friction forces) is " +
          std::to_string(friction.rows()) + " x " + std::to_string(friction.cols()) +
          ", this run keeps " +
          (friction_ ? std::to_string(rows) + " x " + std::to_string(nodes)
                     : std::string("none")));
    friction_previous_ = friction;
  }

 private:
  ncp::Solver solver_;
  bool friction_;
  Eigen::MatrixXd friction_previous_;  // (dim-1) x nodes; empty before the first step
};

}  // namespace contact::internal
