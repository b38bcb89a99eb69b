// The ridge's dynamic programme, one column at a time (ridge_programme.hpp).
#include "ridge_programme.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

#include "huge_pages.hpp"
#include "podid/core/error.hpp"
#include "podid/core/target_clones.hpp"
#include "ridge_cost.hpp"

namespace podid::wavelet::internal {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

int Width(Eigen::Index frequencies) {
  if (frequencies <= 255) return 1;  // 255 itself is the "restart" value
  if (frequencies <= 65535) return 2;
  return 4;
}

// The first index of the smallest entry, -1 if all are +inf: the minimum by
// a vectorised reduction (exact), then its first occurrence.
template <typename Vector>
int Argmin(const Vector& total) {
  const double value = total.minCoeff();
  if (!(value < kInf)) return -1;
  Eigen::Index k = 0;
  while (total(k) != value) ++k;
  return static_cast<int>(k);
}

}  // namespace

// low[i], arg[i] = the minimum (kMax: maximum) over k < freqs of
// cost[k * freq_stride + i] and its first arg (as a double), for i < count:
// time contiguous. Blocks of 8 times keep their extrema in two 4-lane GCC
// vectors (AVX2 registers; the AVX-512 clone uses them too) over every k: one
// load a cell. Not one 8-lane vector: GCC 12 lowers an 8-lane select that
// the target lacks (AVX2) lane by lane through the stack, and the x86-64-v3
// clone took 171 us instead of 8.5 us for 312 times x 115 frequencies on a
// Zen 3 EPYC (docs/benchmark-log.md, "The columns' extrema in AVX2 vectors").
// The SSE2 clone is scalar either way.
using V4 = double __attribute__((vector_size(32)));

template <bool kMax>
[[gnu::always_inline]] inline void ColumnExtrema(const double* cost,
                                                 Eigen::Index count,
                                                 Eigen::Index freqs,
                                                 Eigen::Index freq_stride,
                                                 double* low,
                                                 double* arg) {
  constexpr Eigen::Index kLanes = 8;
  constexpr double kStart = kMax ? -kInf : kInf;
  Eigen::Index i = 0;
  for (; i + kLanes <= count; i += kLanes) {
    V4 l0 = V4{} + kStart, l1 = l0, a0 = V4{}, a1 = V4{};
    for (Eigen::Index k = 0; k < freqs; ++k) {
      V4 c0, c1;
      std::memcpy(&c0, cost + k * freq_stride + i, sizeof c0);
      std::memcpy(&c1, cost + k * freq_stride + i + 4, sizeof c1);
      const V4 kk = V4{} + static_cast<double>(k);
      const auto better0 = kMax ? c0 > l0 : c0 < l0;
      const auto better1 = kMax ? c1 > l1 : c1 < l1;
      a0 = better0 ? kk : a0;
      a1 = better1 ? kk : a1;
      l0 = better0 ? c0 : l0;
      l1 = better1 ? c1 : l1;
    }
    std::memcpy(low + i, &l0, sizeof l0);
    std::memcpy(low + i + 4, &l1, sizeof l1);
    std::memcpy(arg + i, &a0, sizeof a0);
    std::memcpy(arg + i + 4, &a1, sizeof a1);
  }
  for (; i < count; ++i) {
    low[i] = kStart;
    arg[i] = 0.0;
    for (Eigen::Index k = 0; k < freqs; ++k) {
      const double c = cost[k * freq_stride + i];
      if (kMax ? c > low[i] : c < low[i]) {
        low[i] = c;
        arg[i] = static_cast<double>(k);
      }
    }
  }
}

PODID_CLONES_V4 void ColumnMinima(const double* cost,
                                  Eigen::Index count,
                                  Eigen::Index freqs,
                                  Eigen::Index freq_stride,
                                  double* low,
                                  double* arg) {
  ColumnExtrema<false>(cost, count, freqs, freq_stride, low, arg);
}

PODID_CLONES_V4 void ColumnMaxima(const double* power,
                                  Eigen::Index count,
                                  Eigen::Index freqs,
                                  Eigen::Index freq_stride,
                                  double* high,
                                  double* arg) {
  ColumnExtrema<true>(power, count, freqs, freq_stride, high, arg);
}

// guess[b] = 1 + floor((zn[b] / zd[b] - x0) * inverse_spacing), in [0, n]: on
// a uniform grid the first q past the boundary zn / zd (a guess, corrected by
// exact tests in Segments, so no clone's rounding changes a result). NaN: 0.
// Segments passes lambda x0 and inverse_spacing / lambda (zn / zd = lambda z).
PODID_CLONES_V4 void GuessCrossings(const double* zn,
                                    const double* zd,
                                    Eigen::Index count,
                                    double x0,
                                    double inverse_spacing,
                                    Eigen::Index n,
                                    Eigen::Index* guess) {
  const double last = static_cast<double>(n);
  for (Eigen::Index b = 0; b < count; ++b) {
    double g = (zn[b] / zd[b] - x0) * inverse_spacing + 1.0;
    g = g >= 0.0 ? g : 0.0;
    g = g <= last ? g : last;
    guess[b] = static_cast<Eigen::Index>(g);
  }
}

namespace {
// 2 max |ln f|, the longest jump in x: below 1490 (|ln f| <= 745 for any double f > 0).
double Reach(const Eigen::VectorXd& x) {
  return x.size() > 0 ? 2.0 * x.cwiseAbs().maxCoeff() : 0.0;
}
// The largest cost lambda (x_q - x_p)^2 a jump can have.
double LargestJumpCost(const Eigen::VectorXd& x, double lambda) {
  const double reach = Reach(x);
  return lambda * reach * reach;
}
}  // namespace

void CheckRidgePenalty(double penalty_s, double step_s, const Eigen::VectorXd& x) {
  if (LargestJumpCost(x, penalty_s / step_s) <= kMaxRidgeJumpCost) return;
  const double reach = Reach(x);
  ThrowInvalid("RidgeOptions.penalty_s",
               "a penalty whose largest jump cost penalty_s / step_s x (2 max |ln f|)^2 is at "
               "most " +
                   ToText(kMaxRidgeJumpCost) +
                   ": penalty_s <= " + ToText(kMaxRidgeJumpCost / (reach * reach) * step_s) +
                   " s at step " + ToText(step_s) + " s and frequencies " +
                   ToText(x.size() > 0 ? std::exp(x.minCoeff()) : 0.0) + " to " +
                   ToText(x.size() > 0 ? std::exp(x.maxCoeff()) : 0.0) + " Hz",
               ToText(penalty_s) + " s");
}

RidgeProgramme::RidgeProgramme(const Eigen::VectorXd& x, double lambda, bool maximum)
    : x_(x), lambda_(lambda), maximum_(maximum), width_(Width(x.size())) {
  PODID_CHECK(lambda >= 0.0 &&
              LargestJumpCost(x, lambda) <= kMaxRidgeJumpCost);  // CheckRidgePenalty
  none_ = (std::int64_t{1} << (8 * width_)) - 1;
  // lambda x^2 and lambda x as the envelope's intersections use them (same
  // rounding at every column).
  x2_.resize(x_.size());
  lx_.resize(x_.size());
  for (Eigen::Index p = 0; p < x_.size(); ++p) {
    x2_(p) = lambda_ * x_(p) * x_(p);
    lx_(p) = lambda_ * x_(p);
  }
  prev_.resize(x_.size());
  next_.resize(x_.size());
  first_totals_.resize(x_.size());  // PushLast copies prev_ here: no allocation then
  window_.resize(x_.size());
  v_.resize(static_cast<std::size_t>(x_.size()));
  h_.resize(static_cast<std::size_t>(x_.size()));
  xv_.resize(static_cast<std::size_t>(x_.size()));
  zn_.resize(static_cast<std::size_t>(x_.size() + 1));
  zd_.resize(static_cast<std::size_t>(x_.size() + 1));
  starts_.resize(static_cast<std::size_t>(x_.size() + 1));
  guess_.resize(static_cast<std::size_t>(x_.size() + 1));
  // Guesses only where x is within kGridSlack bins of a uniform grid (log-spaced
  // frequencies): then Segments walks at most a few bins from each.
  const Eigen::Index n = x_.size();
  const double span = n >= 2 ? x_(n - 1) - x_(0) : 0.0;
  if (span > 0.0 && std::isfinite(span)) {
    const double spacing = span / static_cast<double>(n - 1);
    double off = 0.0;
    for (Eigen::Index q = 0; q < n; ++q)
      off = std::max(off, std::abs(x_(q) - (x_(0) + static_cast<double>(q) * spacing)));
    constexpr double kGridSlack = 2.0;
    if (off <= kGridSlack * spacing) inverse_spacing_ = 1.0 / spacing;
  }
}

double RidgeProgramme::Bytes(Eigen::Index frequencies, Eigen::Index times, bool maximum) {
  const double cells = static_cast<double>(frequencies) * static_cast<double>(times);
  // Back-pointers, best_, and PushLast's lows_, lows_at_, at_cost_, rest_, near_.
  return (maximum ? 0.0
                  : Width(frequencies) * cells +
                        (32.0 + 8.0 * (2 * kNear + 1)) * static_cast<double>(times)) +
         4.0 * static_cast<double>(times);
}

void RidgeProgramme::Reset(Eigen::Index times) {
  PODID_CHECK(times >= 1);
  times_ = times;
  pushed_ = 0;
  const std::size_t cells = maximum_ ? 0 : static_cast<std::size_t>(x_.size() * times);
  // The back-pointers and near_ are the largest buffers a long ridge touches
  // first: on huge pages a one-shot `podid cwt` of the Silverbox record
  // (131,072 times x 115 frequencies) faults 14,225 times instead of 19,336,
  // 427-433 ms of CPU instead of 462-483 ms on the VM of benchmark-log.md.
  ResizeWithHugePages(&back8_, width_ == 1 ? cells : 0);
  ResizeWithHugePages(&back16_, width_ == 2 ? cells : 0);
  ResizeWithHugePages(&back32_, width_ == 4 ? cells : 0);
  best_.resize(static_cast<std::size_t>(times));
  const std::size_t bounded = maximum_ ? 0 : static_cast<std::size_t>(times);
  lows_.resize(bounded);
  lows_at_.resize(bounded);
  at_cost_.resize(bounded);
  rest_.resize(bounded);
  ResizeWithHugePages(&near_, bounded * (2 * kNear + 1));
  near_valid_ = false;
}

std::int64_t RidgeProgramme::Back(Eigen::Index k, Eigen::Index j) const {
  const std::size_t at = static_cast<std::size_t>(j * x_.size() + k);
  const std::uint32_t value = width_ == 1 ? back8_[at] : width_ == 2 ? back16_[at] : back32_[at];
  return value == none_ ? -1 : static_cast<std::int64_t>(value);
}

void RidgeProgramme::FillColumn(Eigen::Index j, std::uint32_t value) {
  const std::size_t first = static_cast<std::size_t>(j * x_.size()), last = first + static_cast<std::size_t>(x_.size());
  if (width_ == 1) {
    std::fill(back8_.begin() + first, back8_.begin() + last, static_cast<std::uint8_t>(value));
  } else if (width_ == 2) {
    std::fill(back16_.begin() + first, back16_.begin() + last, static_cast<std::uint16_t>(value));
  } else {
    std::fill(back32_.begin() + first, back32_.begin() + last, value);
  }
}

// Minimises sum_j cost(k_j, j) + lambda sum_j (x_{k_j} - x_{k_{j-1}})^2; the
// max over the previous frequency is the lower envelope of the parabolas
// prev(p) + lambda (x - x_p)^2 (Felzenszwalb & Huttenlocher 2012).
void RidgeProgramme::Push(const double* cost, Eigen::Index stride) {
  PODID_CHECK(pushed_ < times_);
  const Eigen::Index freqs = x_.size(), j = pushed_++;
  const Eigen::Map<const Eigen::VectorXd, 0, Eigen::InnerStride<>> column(cost, freqs,
                                                                        Eigen::InnerStride<>(stride));
  if (maximum_) {
    best_[static_cast<std::size_t>(j)] = Argmin(column);
    return;
  }
  const int before = j > 0 ? best_[static_cast<std::size_t>(j - 1)] : -1;
  if (before < 0) {  // nothing reachable before: start afresh
    prev_ = column;
    FillColumn(j, static_cast<std::uint32_t>(none_));
  } else if (lambda_ == 0.0) {
    const double floor = prev_(before);
    prev_ = column.array() + floor;
    FillColumn(j, static_cast<std::uint32_t>(before));
  } else {
    best_[static_cast<std::size_t>(j)] =
        RelaxInto<false>(cost, stride, j, Bounds{0, freqs - 1, 0, freqs - 1, 0.0, 0.0, kInf});
    return;
  }
  best_[static_cast<std::size_t>(j)] = Argmin(prev_);
}

void RidgeProgramme::PushLast(const double* cost,
                              Eigen::Index count,
                              Eigen::Index freq_stride,
                              Eigen::Index time_stride) {
  PushColumns(Columns{cost, freq_stride, time_stride, false}, count);
}

void RidgeProgramme::PushLastPowers(const double* power,
                                    Eigen::Index count,
                                    Eigen::Index freq_stride,
                                    Eigen::Index time_stride) {
  PushColumns(Columns{power, freq_stride, time_stride, true}, count);
}

RidgeProgramme::CostView RidgeProgramme::Costs(const Columns& c,
                                               Eigen::Index i,
                                               Eigen::Index k_first,
                                               Eigen::Index k_last) {
  const double* at = c.data + i * c.time_stride;
  if (!c.power) return {at, c.freq_stride};
  double* window = window_.data();
  // [k_first, k_last] minus the cached cells: at most two runs to compute.
  Eigen::Index runs[2][2] = {{k_first, k_last}, {1, 0}};
  if (near_valid_ && i >= 1) {
    const Eigen::Index centre = static_cast<Eigen::Index>(lows_at_[static_cast<std::size_t>(i)]);
    const Eigen::Index first = std::max(k_first, centre - kNear),
                       last = std::min(k_last, centre + kNear);
    if (first <= last) {
      const double* near = near_.data() + i * (2 * kNear + 1) + (kNear - centre);
      for (Eigen::Index k = first; k <= last; ++k) window[k] = near[k];
      runs[0][1] = first - 1;
      runs[1][0] = last + 1;
      runs[1][1] = k_last;
    }
  }
  for (const auto& run : runs) {
    if (run[0] > run[1]) continue;
    for (Eigen::Index k = run[0]; k <= run[1]; ++k) window[k] = at[k * c.freq_stride];
    RidgeCostOfPower(window + run[0], run[1] - run[0] + 1, window + run[0]);
  }
  return {window, 1};
}

void RidgeProgramme::PushColumns(const Columns& c, Eigen::Index count) {
  PODID_CHECK(count >= 1 && pushed_ + count == times_);
  near_valid_ = false;
  const Eigen::Index freqs = x_.size();
  CostView column = Costs(c, 0, 0, freqs - 1);
  Push(column.at, column.stride);
  last_cells_ = freqs;
  if (count == 1 || PushBounded(c, count)) return;
  last_cells_ = count * freqs;
  for (Eigen::Index i = 1; i < count; ++i) {
    column = Costs(c, i, 0, freqs - 1);
    Push(column.at, column.stride);
  }
}

template <bool kBounded>
int RidgeProgramme::RelaxInto(const double* cost,
                              Eigen::Index stride,
                              Eigen::Index j,
                              const Bounds& bounds) {
  const std::size_t first = static_cast<std::size_t>(j * x_.size());
  if (width_ == 1) return Relax<kBounded>(cost, stride, back8_.data() + first, bounds);
  if (width_ == 2) return Relax<kBounded>(cost, stride, back16_.data() + first, bounds);
  return Relax<kBounded>(cost, stride, back32_.data() + first, bounds);
}

// PushLast's columns 1..count-1 (column 0 pushed), pruned by bounds:
//  - rest_i = sum of the later columns' minimum costs, so total_i(q) + rest_i
//    is at most the cost of the best complete path through (q, i);
//  - bound = the cost of a complete path (the smaller of the columns'
//    argmins and a greedy walk), plus a rounding allowance.
// A cell whose total + rest exceeds the bound lies on no optimal path, nor
// does its predecessor on one (a predecessor's total + rest is at most its
// successor's), so the optimal path and its totals are those of Push; a
// cell not computed at all has cost + min prev + rest above the bound, and a
// column's q beyond the reach of the candidates [p_first, p_last] by
// lambda dx^2 > bound - (lowest cost + min prev + rest) has too.
// False, with the programme back after column 0, if the bounds do not apply
// (a column with no finite cost: the path restarts there) or some column
// kept no cell (impossible unless the allowance is short).
bool RidgeProgramme::PushBounded(const Columns& c, Eigen::Index count) {
  if (maximum_ || lambda_ == 0.0) return false;
  const Eigen::Index freqs = x_.size(), j0 = pushed_ - 1;
  const int start = best_[static_cast<std::size_t>(j0)];
  if (start < 0) return false;
  // The columns' minima and an argmin of each (vectorised along time when
  // time is contiguous: the streamed ridge's blocks). From powers: the
  // largest power's cost, less what RidgeCostOfPower's rounding may put
  // between it and a smaller power's (8 ulp of max(1, |ln|); twice that here).
  double* lows = lows_.data();
  double* at = lows_at_.data();
  double* exact = c.power ? at_cost_.data() : lows;  // the cost at the argmin
  if (c.time_stride == 1) {
    (c.power ? ColumnMaxima : ColumnMinima)(c.data + 1, count - 1, freqs, c.freq_stride, lows + 1,
                                            at + 1);
  } else {
    for (Eigen::Index i = 1; i < count; ++i) {
      const Eigen::Map<const Eigen::VectorXd, 0, Eigen::InnerStride<>> column(
          c.data + i * c.time_stride, freqs, Eigen::InnerStride<>(c.freq_stride));
      Eigen::Index k = 0;
      lows[i] = c.power ? column.maxCoeff(&k) : column.minCoeff(&k);
      at[i] = static_cast<double>(k);
    }
  }
  if (c.power) {
    RidgeCostOfPower(lows + 1, count - 1, exact + 1);
    constexpr double kMonotone = 16.0 * std::numeric_limits<double>::epsilon();
    for (Eigen::Index i = 1; i < count; ++i)
      lows[i] = exact[i] - kMonotone * std::max(1.0, std::abs(exact[i]));
    // The cells near each column's largest power, where a clear ridge's
    // greedy walk and bounded columns mostly read (padding: power 1).
    constexpr Eigen::Index kWidth = 2 * kNear + 1;
    double* near = near_.data();
    for (Eigen::Index i = 1; i < count; ++i) {
      const double* column = c.data + i * c.time_stride;
      const Eigen::Index centre = static_cast<Eigen::Index>(at[i]);
      for (Eigen::Index r = 0; r < kWidth; ++r) {
        const Eigen::Index k = centre - kNear + r;
        near[i * kWidth + r] = k >= 0 && k < freqs ? column[k * c.freq_stride] : 1.0;
      }
    }
    RidgeCostOfPower(near + kWidth, (count - 1) * kWidth, near + kWidth);
    near_valid_ = true;
  }
  double* rest = rest_.data();
  rest[count - 1] = 0.0;
  double magnitude = 1.0 + std::abs(prev_(start));
  for (Eigen::Index i = count - 1; i >= 1; --i) {
    if (!(lows[i] < kInf)) return false;
    rest[i - 1] = rest[i] + lows[i];
    magnitude += std::abs(lows[i]);
  }
  // Two complete paths from column 0's best: the columns' argmins, and a
  // greedy walk (each step the cheapest within 2 bins of the last, penalty included).
  const double lambda = lambda_;
  const double* xs = x_.data();
  double by_argmin = prev_(start), greedy = prev_(start);
  Eigen::Index k_argmin = start, k_greedy = start;
  for (Eigen::Index i = 1; i < count; ++i) {
    const Eigen::Index k = static_cast<Eigen::Index>(at[i]);
    const double dx = xs[k] - xs[k_argmin];
    by_argmin += exact[i] + lambda * dx * dx;
    k_argmin = k;
    const Eigen::Index k_first = std::max<Eigen::Index>(0, k_greedy - 2);
    const Eigen::Index k_last = std::min(freqs - 1, k_greedy + 2);
    const CostView cost = Costs(c, i, k_first, k_last);
    double step = kInf;
    Eigen::Index to = k_greedy;
    for (Eigen::Index k = k_first; k <= k_last; ++k) {
      const double d = xs[k] - xs[k_greedy];
      const double value = cost.at[k * cost.stride] + lambda * d * d;
      if (value < step) {
        step = value;
        to = k;
      }
    }
    greedy += step;
    k_greedy = to;
  }
  const double complete = std::min(by_argmin, greedy);
  if (!std::isfinite(complete)) return false;
  // Every total here is a sum of at most `count` + 1 terms, each of size
  // below `magnitude` (path costs and penalties alike within the complete
  // path's cost); each is rounded to eps relative: 16 count eps magnitude
  // covers the totals' and the bound's own errors several times over.
  const double bound = complete + 16.0 * static_cast<double>(count + 1) *
                                      std::numeric_limits<double>::epsilon() *
                                      (magnitude + std::abs(complete));
  first_totals_ = prev_;
  // Column 0's survivors.
  Eigen::Index p_first = freqs, p_last = -1;
  for (Eigen::Index p = 0; p < freqs; ++p) {
    if (prev_(p) + rest[0] <= bound) {
      p_first = std::min(p_first, p);
      p_last = p;
    } else {
      prev_(p) = kInf;
    }
  }
  if (p_last < 0) {  // column 0 kept no cell
    prev_ = first_totals_;
    return false;
  }
  double floor = prev_(start);
  for (Eigen::Index i = 1; i < count; ++i) {
    const Eigen::Index j = j0 + i;
    pushed_ = j + 1;
    // The reach: no q beyond lambda dx^2 > bound - (lowest cost + floor + rest).
    const double budget = bound - (lows[i] + floor + rest[i]);
    Eigen::Index q_first = p_first, q_last = p_last;
    while (q_first > 0 &&
           lambda * (xs[p_first] - xs[q_first - 1]) * (xs[p_first] - xs[q_first - 1]) <= budget)
      --q_first;
    while (q_last + 1 < freqs &&
           lambda * (xs[q_last + 1] - xs[p_last]) * (xs[q_last + 1] - xs[p_last]) <= budget)
      ++q_last;
    const CostView cost = Costs(c, i, q_first, q_last);
    RelaxInto<true>(cost.at, cost.stride, j,
                    Bounds{p_first, p_last, q_first, q_last, floor, rest[i], bound});
    last_cells_ += q_last - q_first + 1;
    // Survivors, the new floor and the column's best (first argmin).
    p_first = freqs;
    p_last = -1;
    floor = kInf;
    int best = -1;
    for (Eigen::Index q = q_first; q <= q_last; ++q) {
      const double total = prev_(q);
      if (total < kInf) {
        p_first = std::min(p_first, q);
        p_last = q;
      }
      if (total < floor) {
        floor = total;
        best = static_cast<int>(q);
      }
    }
    if (best < 0) {  // nothing kept: back to column 0, unbounded
      prev_ = first_totals_;
      pushed_ = j0 + 1;
      return false;
    }
    best_[static_cast<std::size_t>(j)] = best;
  }
  return true;
}

// The shortest run of q (less one) Relax gives Segments: PushLast's pruned
// columns (BM_RidgeFrequencyBandLimited) were up to 1.15x slower through it,
// Push's full ones (BM_SilverboxRidge, 115-158 cells) 1.07x faster.
constexpr Eigen::Index kSegmentedCells = 16;

// One column of the envelope. Intersections z = num / (lambda den) (den > 0)
// are compared by cross-multiplying: no division on the stack's dependency
// chain. lambda stays out of den: num ~ lambda x^2 times den = 2 lambda dx
// overflowed beyond lambda ~ 1e154 (penalty 1e152 s at 5 kHz: IFs outside
// the grid), and x_q against z as lambda x_q den.
// Raw pointers: through the members, every store to the stack would reload
// them (they may alias), 1.2x slower.
template <bool kBounded, typename Index>
int RidgeProgramme::Relax(const double* cost,
                          Eigen::Index stride,
                          Index* back,
                          const Bounds& bounds) {
  const Eigen::Index p_end = bounds.p_last + 1;
  const double* xs = x_.data();
  const double* pv = prev_.data();
  const double* x2 = x2_.data();
  const double* lx = lx_.data();
  Eigen::Index* v = v_.data();
  double* hs = h_.data();
  double* xv = xv_.data();
  double* zn = zn_.data();
  double* zd = zd_.data();
  const double lambda = lambda_;
  // The first finite parabola is the stack's bottom, zn = -inf: no later
  // one pops it (num * 1 <= -inf is false for finite num), so the pop loop
  // needs no bound check.
  Eigen::Index first = bounds.p_first;
  while (first < p_end && !std::isfinite(pv[first])) ++first;
  PODID_CHECK(first < p_end);  // before >= 0: prev has a finite entry
  Eigen::Index top = 0;
  v[0] = first;
  xv[0] = xs[first];
  hs[0] = pv[first] + x2[first];
  zn[0] = -kInf;
  zd[0] = 1.0;
  // The top's entries also in registers: the next parabola's test does not
  // wait for the stores it just made (7 % of the programme).
  double top_h = hs[0], top_x = xv[0], top_zn = zn[0], top_zd = zd[0];
  for (Eigen::Index p = first + 1; p < p_end; ++p) {
    if (!std::isfinite(pv[p])) continue;  // forbidden, unreachable or (bounded) pruned
    const double hp = pv[p] + x2[p];
    const double tx = xs[p];
    double num = hp - top_h;
    double den = 2.0 * (tx - top_x);
    while (num * top_zd <= top_zn * den) {
      --top;
      top_h = hs[top];
      top_x = xv[top];
      top_zn = zn[top];
      top_zd = zd[top];
      num = hp - top_h;
      den = 2.0 * (tx - top_x);
    }
    ++top;
    v[top] = p;
    xv[top] = top_x = tx;
    hs[top] = top_h = hp;
    zn[top] = top_zn = num;
    zd[top] = top_zd = den;
  }
  // Each q's parabola v[e]: from Segments where every q of a long run is
  // computed (Push); on short runs, and on PushLast's pruned columns (most q
  // skipped), Segments' set-up costs more than the scan advancing e past the
  // boundaries x_q has crossed (the same e).
  const bool segmented = !kBounded && bounds.q_last - bounds.q_first >= kSegmentedCells;
  if (segmented) {
    Segments(top, bounds.q_first, bounds.q_last);
  } else {
    zn[top + 1] = kInf;
    zd[top + 1] = 1.0;
  }
  const Eigen::Index* starts = starts_.data();
  double* out = next_.data();
  Eigen::Index e = 0;
  double low = kInf;  // unbounded: the first argmin, as Argmin (no second pass)
  int best = -1;
  for (Eigen::Index q = bounds.q_first; q <= bounds.q_last; ++q) {
    if (segmented) e += starts[q - bounds.q_first];
    const double c = cost[q * stride];
    if (kBounded && !(c + bounds.floor + bounds.rest <= bounds.bound)) {
      out[q] = kInf;
      continue;
    }
    const double xq = xs[q];
    if (!segmented) {
      while (zn[e + 1] < lx[q] * zd[e + 1]) ++e;
    }
    const Eigen::Index p = v[e];
    const double dx = xq - xs[p];
    const double total = c + pv[p] + lambda * dx * dx;
    out[q] = total;
    back[q] = static_cast<Index>(p);
    if constexpr (kBounded) {
      if (!(total + bounds.rest <= bounds.bound)) out[q] = kInf;
    } else if (total < low) {
      low = total;
      best = static_cast<int>(q);
    }
  }
  std::swap(prev_, next_);
  return best;
}

// Where each of the envelope's top boundaries is crossed. q lies in segment e
// (parabola v_[e]) once x_q is past boundaries 1..e (zn[b] < x_q zd[b], as
// the pop test cross-multiplied, monotone in q) and not past e + 1: boundary
// b is first crossed at t_b = the first q >= t_(b-1) past it, from q_first.
// (zn / zd is lambda z: x_q is compared as lambda x_q.)
// A scan of q advancing e branched unpredictably at every q (about 40 % of
// the programme on the Silverbox's columns); from guesses the walks below
// are nearly always empty. Without guesses (x not uniform) the forward walk
// from t_(b-1) is that scan.
void RidgeProgramme::Segments(Eigen::Index top, Eigen::Index q_first, Eigen::Index q_last) {
  const Eigen::Index q_end = q_last + 1;
  const double* lx = lx_.data();
  const double* zn = zn_.data();
  const double* zd = zd_.data();
  Eigen::Index* starts = starts_.data();  // starts[q - q_first]
  std::fill(starts, starts + (q_end - q_first), Eigen::Index{0});
  Eigen::Index* guess = guess_.data();
  if (inverse_spacing_ > 0.0) {
    GuessCrossings(zn + 1, zd + 1, top, lx[0], inverse_spacing_ / lambda_, x_.size(), guess + 1);
  } else {
    std::fill(guess + 1, guess + top + 1, Eigen::Index{0});  // each walk starts at t
  }
  Eigen::Index t = q_first;
  for (Eigen::Index b = 1; b <= top; ++b) {
    const double num = zn[b], den = zd[b];
    Eigen::Index s = std::clamp(guess[b], t, q_end);
    while (s > t && num < lx[s - 1] * den) --s;
    while (s < q_end && !(num < lx[s] * den)) ++s;
    if (s == q_end) break;  // this boundary and the later ones lie beyond q_last
    t = s;
    ++starts[t - q_first];
  }
}

Eigen::VectorXi RidgeProgramme::Path() const {
  PODID_CHECK(pushed_ == times_ && times_ >= 1);
  Eigen::VectorXi path(times_);
  if (maximum_) {
    for (Eigen::Index j = 0; j < times_; ++j) path(j) = best_[static_cast<std::size_t>(j)];
    return path;
  }
  std::int64_t k = best_[static_cast<std::size_t>(times_ - 1)];
  for (Eigen::Index j = times_ - 1; j >= 0; --j) {
    path(j) = static_cast<int>(k);
    if (j > 0) k = k >= 0 ? Back(k, j) : best_[static_cast<std::size_t>(j - 1)];
  }
  return path;
}

}  // namespace podid::wavelet::internal
