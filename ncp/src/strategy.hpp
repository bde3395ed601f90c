// The hybrid default (Options::hybrid): the sequence of strategies and the progress test
// that decides when the current one is left for the next. Solver::Iteration (solver.cpp)
// asks these after every iterate; nothing here evaluates the problem.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "ncp/solver.hpp"

namespace ncp::internal {

inline bool SameStrategy(const Strategy& a, const Strategy& b) {
  return a.ncp_function == b.ncp_function &&
         a.regularized_direction == b.regularized_direction;
}

/// The strategies of Options::hybrid in order: the requested one, then penalized FB, min,
/// FB with the Levenberg-Marquardt direction, penalized FB with it (each once).
class StrategySchedule {
 public:
  void Reset(const Options& o);
  const Strategy& current() const { return list_[static_cast<size_t>(index_)]; }
  /// Moves to the next strategy that differs from `now` (the merit restarts may have
  /// changed the function within a strategy); false when none is left.
  bool Advance(const Strategy& now);

 private:
  std::array<Strategy, 5> list_{};
  int size_ = 0, index_ = 0;
};

/// The progress of one strategy (one merit function): the smallest psi and the point
/// where it was reached, and whether the strategy should be left for slow progress or its
/// budget.
class StrategyProgress {
 public:
  /// Sizes the window and the best point for n unknowns (no allocation when they fit).
  void Reset(const Options& o, int n);
  /// Records psi(x^k) and x^k at kk iterations since the merit function was last changed
  /// (kk = 0 starts a new record).
  void Observe(size_t kk, double psi, const Vector& x, int k);
  /// For a caller that keeps the best point itself (ncp::petsc, distributed x): Reset
  /// without the best point, and Observe without x, returning true when x^k is the new
  /// best point (the caller then keeps a copy of x^k).
  void ResetRecord(const Options& o, int n);
  bool Record(size_t kk, double psi, int k);
  /// Slow progress (Options::hybrid_window, hybrid_decrease) at kk iterations since the
  /// merit function changed, or the budget used at `spent` iterations since the strategy
  /// began; false when neither (then *reason is untouched).
  bool ShouldLeave(size_t kk, int spent, const Options& o, SwitchReason* reason) const;

  const Vector& best_x() const { return best_x_; }
  double best_psi() const { return best_psi_; }
  int best_iteration() const { return best_k_; }
  /// The Summary record of a switch at iteration k from `from` to `to`, with the best
  /// iterate the next strategy starts from.
  StrategySwitch SwitchRecord(int k, const Strategy& from, const Strategy& to,
                              SwitchReason reason) const {
    StrategySwitch record;
    record.iteration = k;
    record.from_strategy = from;
    record.to_strategy = to;
    record.reason = reason;
    record.best_iteration = best_k_;
    record.best_psi = best_psi_;
    return record;
  }

 private:
  std::vector<double> ring_;  // smallest psi so far, at kk mod (window + 1)
  Vector best_x_;
  double best_psi_ = 0.0;
  int best_k_ = 0;
  int budget_ = 0;
};

/// " (strategies: fb -> min at iteration 30, slow progress -> ...)" for Summary::message.
std::string StrategySwitchSuffix(const std::vector<StrategySwitch>& switches);
/// "fb", "fb+lm", ...
std::string StrategyName(const Strategy& s);

}  // namespace ncp::internal
