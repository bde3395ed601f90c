/// \file physics_checks.hpp
/// Closed-form checks of dynamic contact with DEFAULT solver settings, for any material,
/// time step, mass kind, dimension, step method and unit system (issue: "physically
/// meaningful convergence"). Each check writes its scene as a TOML file in the requested
/// units, runs it with contact::RunDynamics and compares with the exact answer:
///   - FreeFall:  a block released at rest h above a floor: no contact force in flight
///   above
///                1e-6 m g, first contact within one step of sqrt(2h/g);
///   - Incline:   1 degree either side of atan(mu): slides with a = g (sin - mu cos)
///   within 1%,
///                or sticks: slip after the load is on below a tenth of the block's
///                elastic shear deformation rho g sin(theta) H^2 / (2 G) (an absolute
///                length would not hold for every E and size; see Incline in the .cpp);
///   - Sliding:   a block thrown along the floor stops after v0 / (mu g) within 1%;
///   - BarImpact: an elastic bar (nu = 0) hits a wall: contact lasts 2L/c within 1%.
/// The scenes are sized from the time step so that a run takes a few hundred steps (the
/// drop height, the throw speed), which keeps every check short at any dt / dt_crit.
/// Used by tests/contact/test_physical_accuracy.cpp (a short sweep) and by the
/// contact-physics-check program (the full sweep over E, dt / dt_crit, mass and
/// dimension).
#pragma once

#include <string>
#include <vector>

#include "contact/dynamics.hpp"

namespace contact::validation {

/// A unit system: the SI value of one unit of length, time and mass. SI is {1, 1, 1},
/// mm-tonne-s is {1e-3, 1, 1e3} (forces in N, stresses in MPa). A body scaled in size by
/// s with consistent loads (same material, gravity / s, times * s) is the SI problem
/// written in the units {1 / s, 1 / s, 1 / s^3}.
struct Units {
  double length = 1.0, time = 1.0, mass = 1.0;
  std::string name = "SI";
};

/// What a check varies.
struct Case {
  int dim = 2;
  double young_modulus = 70e9;  ///< [Pa]
  double density = 2700.0;      ///< [kg/m^3]
  double dt_fraction = 0.9;     ///< dt / dt_crit
  bool lumped = true;           ///< lumped (row-sum) or consistent mass
  std::string step = "";        ///< solver.step; "" = the default
  std::string solver = "";      ///< solver.ncp_function, or "ipopt" for solver.step =
                                ///< "ipopt"; "" = the default
  std::string friction_formulation = "";  ///< solver.friction; "" = the default
  double tolerance = 0.0;                 ///< solver.tolerance; 0 = the default
  double friction = 0.3;                  ///< mu (incline, sliding)
  Units units;
  std::string Label() const;
};

/// A check's outcome; every value in SI.
struct Outcome {
  std::string check, detail;  ///< what was checked, and the measured numbers
  bool passed = false;
  DynamicStatus status = DynamicStatus::kNotRun;
  std::string message;  ///< the run's status message
  int steps = 0;
  double seconds = 0.0, newton_per_step = 0.0;
  double measured = 0.0, expected = 0.0;  ///< the main quantity and its closed form
  /// Trajectory for unit comparisons: time [s] and the mass-weighted mean displacement
  /// [m] (all components, per step).
  std::vector<double> time;
  std::vector<std::vector<double>> mean_u;
  std::vector<double> contact_slip;  ///< mean tangential (first tangent) displacement of
                                     ///< the contact nodes [m]
};

Outcome FreeFall(const Case& c);
/// degrees_from_friction_angle: theta = atan(mu) + this (e.g. +1 slides, -1 sticks).
Outcome Incline(const Case& c, double degrees_from_friction_angle);
Outcome Sliding(const Case& c);
Outcome BarImpact(const Case& c);

/// max_k |a_k - b_k| / max_k |b_k| over the two trajectories (same steps), in SI, over
/// the first `fraction` of the steps.
double TrajectoryDifference(const Outcome& a, const Outcome& b, double fraction = 1.0);

}  // namespace contact::validation
