// Which scales a ridge in one block must transform (scale_screen.hpp).
#include "scale_screen.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>

#include "podid/core/error.hpp"
#include "podid/core/target_clones.hpp"
#include "ridge_cost.hpp"

namespace podid::wavelet::internal {

ScaleScreen::ScaleScreen(const Eigen::VectorXd& x, double lambda)
    : x_(x), lambda_(lambda), bound_(Eigen::VectorXd::Zero(x.size())) {
  order_.resize(static_cast<std::size_t>(x_.size()));
}

void ScaleScreen::Start(Eigen::Index times) {
  PODID_CHECK(times >= 1);
  times_ = times;
  std::iota(order_.begin(), order_.end(), 0);
  std::stable_sort(order_.begin(), order_.end(),
                   [&](int a, int b) { return bound_[a] > bound_[b]; });
  max_power_.setConstant(times, -1.0);
  cost_.resize(times);
  arg_.setConstant(times, -1.0);
  retest_ = 0;
}

namespace {

// high[t], arg[t] = power[t], k where power[t] > high[t], for t < n. In GCC
// vectors of 4 (a plain loop of ?: stays scalar: GCC keeps its branches).
using V4 = double __attribute__((vector_size(32)));

PODID_CLONES_V3 void RaiseMaxima(
    const double* power, double* high, double* arg, Eigen::Index n, double k) {
  Eigen::Index t = 0;
  for (; t + 4 <= n; t += 4) {
    V4 p, h, a;
    std::memcpy(&p, power + t, sizeof p);
    std::memcpy(&h, high + t, sizeof h);
    std::memcpy(&a, arg + t, sizeof a);
    const auto above = p > h;
    h = above ? p : h;
    a = above ? V4{} + k : a;
    std::memcpy(high + t, &h, sizeof h);
    std::memcpy(arg + t, &a, sizeof a);
  }
  for (; t < n; ++t) {
    if (power[t] > high[t]) {
      high[t] = power[t];
      arg[t] = k;
    }
  }
}

}  // namespace

void ScaleScreen::Add(int k, const double* power) {
  RaiseMaxima(power, max_power_.data(), arg_.data(), times_, static_cast<double>(k));
}

double ScaleScreen::StandIn(int k) const {
  const double raised = bound_[k] * (1.0 + kFftAllowance);
  return raised * raised;
}

bool ScaleScreen::RestExcluded(std::size_t next) {
  if (next >= order_.size()) return true;
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  const double stand_in = StandIn(order_[next]);
  // lb <= max_t L(t) (the test fails) unless the stand-in is below every
  // column's largest power: a cheap first check, without logarithms.
  if (!(stand_in < max_power_.minCoeff()) || next < retest_) return false;
  retest_ = next + kRetestScales;  // if this test fails
  RidgeCostOfPower(max_power_.data(), times_, cost_.data());
  double lb = 0.0;
  RidgeCostOfPower(&stand_in, 1, &lb);
  // RidgeCostOfPower may cost a larger power up to 8 ulp of max(1, |ln|)
  // more than a smaller one (ridge_cost.hpp): each lower bound gives that
  // up, and lb twice (the remaining scales' stand-ins and true powers are
  // both at most this stand-in).
  lb -= 32.0 * kEps * std::max(1.0, std::abs(lb));
  double best = 0.0, sum_low = 0.0, max_low = -std::numeric_limits<double>::infinity(),
         magnitude = 1.0;
  for (Eigen::Index t = 0; t < times_; ++t) {
    best += cost_[t];
    if (t > 0) {
      const double dx =
          x_[static_cast<Eigen::Index>(arg_[t])] - x_[static_cast<Eigen::Index>(arg_[t - 1])];
      best += lambda_ * dx * dx;
    }
    const double low = std::min(cost_[t] - 16.0 * kEps * std::max(1.0, std::abs(cost_[t])), lb);
    sum_low += low;
    max_low = std::max(max_low, low);
    magnitude += std::abs(low);
  }
  // The programme's totals and these sums carry roundings of eps relative
  // to these magnitudes per term; 1e-9 of them is far above all of it.
  const double margin = 1e-9 * (magnitude + std::abs(best));
  return lb > best - sum_low + max_low + margin;
}

}  // namespace podid::wavelet::internal
