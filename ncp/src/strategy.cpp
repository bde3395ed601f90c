// The hybrid default (Options::hybrid); see strategy.hpp.

#include "strategy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ncp {

const char* ToString(SwitchReason reason) {
  switch (reason) {
    case SwitchReason::kStuck:
      return "stuck";
    case SwitchReason::kSlowProgress:
      return "slow-progress";
    case SwitchReason::kBudget:
      return "budget";
  }
  return "unknown";
}

namespace internal {

void StrategySchedule::Reset(const Options& o) {
  const Strategy requested{o.ncp_function, o.regularized_direction};
  const Strategy order[] = {
      {NcpFunction::kPenalizedFischerBurmeister, false},
      {NcpFunction::kMin, false},
      {NcpFunction::kFischerBurmeister, true},
      {NcpFunction::kPenalizedFischerBurmeister, true},
  };
  size_ = 0;
  index_ = 0;
  list_[static_cast<size_t>(size_++)] = requested;
  if (!o.hybrid) return;
  for (const Strategy& s : order)
    if (!SameStrategy(s, requested)) list_[static_cast<size_t>(size_++)] = s;
}

bool StrategySchedule::Advance(const Strategy& now) {
  for (int next = index_ + 1; next < size_; ++next) {
    if (SameStrategy(list_[static_cast<size_t>(next)], now)) continue;
    index_ = next;
    return true;
  }
  return false;
}

void StrategyProgress::Reset(const Options& o, int n) {
  ResetRecord(o, n);
  best_x_.resize(n);
}

void StrategyProgress::ResetRecord(const Options& o, int n) {
  ring_.assign(static_cast<size_t>(o.hybrid_window) + 1, 0.0);
  const double budget = std::max(static_cast<double>(o.hybrid_window),
                                 std::ceil(o.hybrid_budget_per_unknown * n));
  budget_ = budget >= static_cast<double>(std::numeric_limits<int>::max())
                ? std::numeric_limits<int>::max()
                : static_cast<int>(budget);
}

void StrategyProgress::Observe(size_t kk, double psi, const Vector& x, int k) {
  if (Record(kk, psi, k)) best_x_ = x;
}

bool StrategyProgress::Record(size_t kk, double psi, int k) {
  const bool best = kk == 0 || psi < best_psi_;
  if (best) {
    best_psi_ = psi;
    best_k_ = k;
  }
  ring_[kk % ring_.size()] = best_psi_;
  return best;
}

bool StrategyProgress::ShouldLeave(size_t kk, int spent, const Options& o,
                                   SwitchReason* reason) const {
  if (spent >= budget_) {
    *reason = SwitchReason::kBudget;
    return true;
  }
  const size_t window = ring_.size() - 1;
  if (window == 0 || kk < window) return false;
  const double best_window_ago = ring_[(kk + 1) % ring_.size()];  // at kk - window
  if (best_psi_ <= o.hybrid_decrease * best_window_ago) return false;
  *reason = SwitchReason::kSlowProgress;
  return true;
}

std::string StrategyName(const Strategy& s) {
  return std::string(ToString(s.ncp_function)) + (s.regularized_direction ? "+lm" : "");
}

std::string StrategySwitchSuffix(const std::vector<StrategySwitch>& switches) {
  if (switches.empty()) return std::string();
  std::string out = " (strategies: " + StrategyName(switches.front().from_strategy);
  for (const StrategySwitch& s : switches)
    out += " -> " + StrategyName(s.to_strategy) + " at iteration " +
           std::to_string(s.iteration) + ", " + ToString(s.reason);
  return out + ")";
}

}  // namespace internal
}  // namespace ncp
