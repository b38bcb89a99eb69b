#pragma once
// Which scales a ridge in one block must transform (the streamed ridge,
// RidgeFrequencyOptions::screen_scales).
//
// Scale k's coefficients are sums over its band, W_k(t) = sum_b X_b psi_k(b)
// e^(i omega_b t), so |W_k(t)| <= U_k = sum_b |X_b| |psi_k(b)| at every t: a
// scale far from the signal's spectrum has a small U_k, its cost -ln|W| is at
// least -ln U_k everywhere. The scales are transformed in order of U_k,
// largest first. Once those done give, with L(t) = min(the smallest cost in
// column t so far, lb) and lb = -ln U of the next scale,
//   lb > best - sum_t L(t) + max_t L(t),
// best being the cost of a complete path through the transformed scales, no
// optimal path touches a remaining scale: one through its cell (k, t) costs
// at least sum_(t' != t) L(t') + lb > best. They are not transformed; the
// programme gets their bound as a stand-in |W|^2, which keeps that argument
// true, so its path is the one every scale's true |W| gives (test
// StreamedRidge.ScreenedScalesGiveTheUnscreenedTrackBitForBit). On the
// reference case's 1 s free decay 57 of the 115 scales (those far below and
// far above its ridge at 33-36 Hz) are left out.

#include <Eigen/Core>
#include <vector>

namespace podid::wavelet::internal {

class ScaleScreen {
 public:
  /// x: ln f of each scale's frequency; lambda: the programme's penalty
  /// per (ln f step)^2 (RidgeProgramme's).
  ScaleScreen(const Eigen::VectorXd& x, double lambda);

  /// Per scale k, filled before Start: bound[k] >= |W_k(t)| for every t
  /// (BandTransform::MagnitudeBounds).
  double* bounds() { return bound_.data(); }
  /// Starts a block of `times` columns with the bounds filled. order() is
  /// then the scales by bound, largest first (ties: lower index first).
  void Start(Eigen::Index times);
  const std::vector<int>& order() const { return order_; }

  /// Scale k transformed: its |W|^2 at the block's times (RidgePower's).
  void Add(int k, const double* power);
  /// Whether no optimal path can touch the scales order()[next..] (none of
  /// them added yet), by the test above with rounding allowances. Cheap
  /// (no logarithm) while the next bound is above some column's largest
  /// power; after a failed full test the next one waits kRetestScales scales.
  bool RestExcluded(std::size_t next);
  /// The |W|^2 the programme gets for an excluded scale k: its bound squared,
  /// raised by kFftAllowance for the FFT's rounding of W.
  double StandIn(int k) const;

  /// Relative excess of a transformed |W| over its bound allowed for the
  /// inverse FFT's rounding (a few ulp times log2 of its length) and the
  /// bound's own sum: far above both.
  static constexpr double kFftAllowance = 1e-9;
  /// Scales added between two full tests that failed: a full test costs a
  /// logarithm per time, about what transforming a scale costs.
  static constexpr std::size_t kRetestScales = 4;

 private:
  Eigen::VectorXd x_;
  double lambda_ = 0.0;
  Eigen::Index times_ = 0;
  std::size_t retest_ = 0;  // no full test before this many scales are added
  Eigen::VectorXd bound_;   // per scale
  std::vector<int> order_;
  // Per time: the largest |W|^2 added so far, its cost, and the scale
  // holding it (a double, so that Add's loop vectorises).
  Eigen::VectorXd max_power_, cost_, arg_;
};

}  // namespace podid::wavelet::internal
