#pragma once
// The ridge's dynamic programme (podid/wavelet/ridge.hpp), fed one time
// column at a time so that a long record never needs its whole cost matrix:
// it keeps the running totals (dim n_freq) and one back-pointer per cell, 1
// byte each up to 255 frequencies, 2 up to 65535, else 4.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace podid::wavelet::internal {

/// The largest jump cost lambda (2 max |ln f|)^2 the programme accepts. A
/// column's totals exceed the last column's smallest by at most one jump and
/// one cost (|cost| < 1e3, a log-magnitude): even a path forced to jump at
/// each of 2^26 columns stays below 2^26 (1e296 + 1e3) = 6.7e303; the
/// envelope multiplies differences of totals plus lambda x^2 (below 1.4e304)
/// by 2 dx < 2^12 (|ln f| <= 745): 5.5e307, below DBL_MAX = 1.8e308. With
/// lambda in the products (2 lambda dx) they overflowed from lambda ~ 1e154
/// (podid cwt --penalty 1e152 at 5 kHz: IFs outside the grid); a penalty of
/// 1e308 s gave lambda = inf and inf or NaN in every envelope test.
inline constexpr double kMaxRidgeJumpCost = 1e296;

/// Throws std::invalid_argument (naming RidgeOptions.penalty_s) unless the
/// programme's largest jump cost lambda (2 max |ln f|)^2, lambda = penalty_s /
/// step_s, is at most kMaxRidgeJumpCost.
void CheckRidgePenalty(double penalty_s, double step_s, const Eigen::VectorXd& x);

class RidgeProgramme {
 public:
  /// x: (dim n_freq) ln f of each frequency; lambda = penalty_s / step_s
  /// (>= 0); maximum: kMaximum's path (argmin per column, no back-pointers).
  RidgeProgramme(const Eigen::VectorXd& x, double lambda, bool maximum);

  /// Bytes Reset(times) will hold (checked against budgets before allocating).
  static double Bytes(Eigen::Index frequencies, Eigen::Index times, bool maximum);
  /// Starts a path over `times` columns.
  void Reset(Eigen::Index times);
  /// Column j = the number of columns pushed so far: cost(k) = -log|W(j, k)| +
  /// any constant, finite or +inf (forbidden); an all-+inf column has no ridge.
  /// cost(k) is cost[k * stride].
  void Push(const double* cost, Eigen::Index stride = 1);
  /// Pushes the path's last `count` columns at once (none may follow; column
  /// i's cost(k) is cost[i * time_stride + k * freq_stride]). The same path as
  /// `count` Push calls, but knowing every remaining column it skips the cells
  /// no optimal path can pass: a cell's total so far plus the remaining
  /// columns' smallest costs above the cost of a cheap complete path (the
  /// columns' argmins, or a greedy walk). On a clear ridge that leaves a few
  /// per cent of the cells.
  void PushLast(const double* cost,
                Eigen::Index count,
                Eigen::Index freq_stride,
                Eigen::Index time_stride);
  /// PushLast from |W|^2: cost(k) = RidgeCostOfPower(power(k)) (ridge_cost.hpp),
  /// computed only for the cells the bounds leave (the logarithm of every cell
  /// was 8 % of an objective evaluation), so the same path as PushLast on
  /// those costs. Column i's power(k) is power[i * time_stride + k * freq_stride].
  void PushLastPowers(const double* power,
                      Eigen::Index count,
                      Eigen::Index freq_stride,
                      Eigen::Index time_stride);
  /// Cells the last PushLast computed (count x n_freq if no bound applied).
  Eigen::Index last_cells() const { return last_cells_; }
  /// The path (dim times, -1 where a column had no finite cost), after every column.
  Eigen::VectorXi Path() const;

 private:
  std::int64_t Back(Eigen::Index k, Eigen::Index j) const;
  void FillColumn(Eigen::Index j, std::uint32_t value);  // every back-pointer of column j
  // Relaxes next_ from prev_ (then swaps them). Unbounded: every finite
  // prev(p) a candidate, every q computed. Bounded (PushLast): candidates
  // p in [p_first, p_last] (the rest +inf), q in [q_first, q_last] computed
  // only if cost(q) + floor + rest <= bound, kept only if total + rest <=
  // bound (else +inf), where floor = min prev and rest = the later columns' minima.
  struct Bounds {
    Eigen::Index p_first, p_last, q_first, q_last;
    double floor, rest, bound;
  };
  // Unbounded, they return the column's first argmin (-1: no finite total),
  // found as the totals are written; bounded, -1 (PushBounded scans its survivors).
  template <bool kBounded, typename Index>
  int Relax(const double* cost, Eigen::Index stride, Index* back, const Bounds& bounds);
  template <bool kBounded>
  int RelaxInto(const double* cost, Eigen::Index stride, Eigen::Index j, const Bounds& bounds);
  // PushLast's columns: costs, or powers whose costs are computed on demand.
  struct Columns {
    const double* data;
    Eigen::Index freq_stride, time_stride;
    bool power;
  };
  // Column i's costs for k in [k_first, k_last]: at[k * stride] (the data
  // itself, or window_ filled from the powers).
  struct CostView {
    const double* at;
    Eigen::Index stride;
  };
  CostView Costs(const Columns& c, Eigen::Index i, Eigen::Index k_first, Eigen::Index k_last);
  void PushColumns(const Columns& c, Eigen::Index count);
  bool PushBounded(const Columns& c, Eigen::Index count);

  Eigen::VectorXd x_, x2_, lx_;  // x, lambda x^2, lambda x
  double lambda_;
  bool maximum_;
  int width_;  // bytes per back-pointer
  std::int64_t none_;  // the back-pointer meaning "restart": all bits set
  Eigen::Index times_ = 0, pushed_ = 0, last_cells_ = 0;
  // (freq, time) frequency-fastest, in the one of width_ bytes.
  std::vector<std::uint8_t> back8_;
  std::vector<std::uint16_t> back16_;
  std::vector<std::uint32_t> back32_;
  std::vector<int> best_;            // argmin of the totals after each column, -1: none
  Eigen::VectorXd prev_, next_;
  std::vector<Eigen::Index> v_;        // the envelope's parabolas
  std::vector<double> h_, xv_, zn_, zd_;  // their prev + lambda x^2, x; intersections zn / zd
  // Each q's parabola without a branch per q: starts_[q - q_first] = the
  // boundaries first crossed at q, found from guess_ (where x = ln f is
  // uniform to within kGridSlack bins: inverse_spacing_ > 0, else 0: no guesses).
  std::vector<Eigen::Index> starts_, guess_;
  double inverse_spacing_ = 0.0;
  void Segments(Eigen::Index top, Eigen::Index q_first, Eigen::Index q_last);
  // PushLast: a lower bound on each column's smallest cost (the smallest cost
  // itself for costs), an argmin and its cost, the sums of the later bounds.
  std::vector<double> lows_, rest_, lows_at_, at_cost_;  // lows_at_: as a double (vectorised)
  Eigen::VectorXd window_;  // PushLastPowers: a column's costs, computed from its powers
  // PushLastPowers: the costs of the cells within kNear of each column's
  // largest power, computed in one vectorised pass (one call per column
  // waited on the logarithm's latency), if near_valid_.
  static constexpr Eigen::Index kNear = 4;
  std::vector<double> near_;
  bool near_valid_ = false;
  Eigen::VectorXd
      first_totals_;  // prev_ after PushLast's first column (its fallback restarts there)
};

}  // namespace podid::wavelet::internal
