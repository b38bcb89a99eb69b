// The ridge's dynamic programme, one column at a time (ridge_programme.hpp).
#include "ridge_programme.hpp"

#include <cmath>
#include <limits>
#include <utility>

#include "podid/core/error.hpp"

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

RidgeProgramme::RidgeProgramme(const Eigen::VectorXd& x, double lambda, bool maximum)
    : x_(x), lambda_(lambda), maximum_(maximum), width_(Width(x.size())) {
  none_ = (std::int64_t{1} << (8 * width_)) - 1;
  // lambda x^2 as the envelope's intersections use it (same rounding at every column).
  x2_.resize(x_.size());
  for (Eigen::Index p = 0; p < x_.size(); ++p) x2_(p) = lambda_ * x_(p) * x_(p);
  prev_.resize(x_.size());
  next_.resize(x_.size());
  v_.resize(static_cast<std::size_t>(x_.size()));
  h_.resize(static_cast<std::size_t>(x_.size()));
  xv_.resize(static_cast<std::size_t>(x_.size()));
  zn_.resize(static_cast<std::size_t>(x_.size() + 1));
  zd_.resize(static_cast<std::size_t>(x_.size() + 1));
}

double RidgeProgramme::Bytes(Eigen::Index frequencies, Eigen::Index times, bool maximum) {
  const double cells = static_cast<double>(frequencies) * static_cast<double>(times);
  return (maximum ? 0.0 : Width(frequencies) * cells) + 4.0 * static_cast<double>(times);
}

void RidgeProgramme::Reset(Eigen::Index times) {
  PODID_CHECK(times >= 1);
  times_ = times;
  pushed_ = 0;
  const std::size_t cells = maximum_ ? 0 : static_cast<std::size_t>(x_.size() * times);
  back8_.resize(width_ == 1 ? cells : 0);
  back16_.resize(width_ == 2 ? cells : 0);
  back32_.resize(width_ == 4 ? cells : 0);
  best_.resize(static_cast<std::size_t>(times));
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
    const std::size_t first = static_cast<std::size_t>(j * freqs);
    if (width_ == 1) {
      Relax(cost, stride, back8_.data() + first);
    } else if (width_ == 2) {
      Relax(cost, stride, back16_.data() + first);
    } else {
      Relax(cost, stride, back32_.data() + first);
    }
  }
  best_[static_cast<std::size_t>(j)] = Argmin(prev_);
}

// One column of the envelope. Intersections z = num / den (den > 0) are
// compared by cross-multiplying: no division on the stack's dependency chain.
// Raw pointers: through the members, every store to the stack would reload
// them (they may alias), 1.2x slower.
template <typename Index>
void RidgeProgramme::Relax(const double* cost, Eigen::Index stride, Index* back) {
  const Eigen::Index freqs = x_.size();
  const double* xs = x_.data();
  const double* pv = prev_.data();
  const double* x2 = x2_.data();
  Eigen::Index* v = v_.data();
  double* hs = h_.data();
  double* xv = xv_.data();
  double* zn = zn_.data();
  double* zd = zd_.data();
  const double lambda = lambda_;
  // The first finite parabola is the stack's bottom, zn = -inf: no later
  // one pops it (num * 1 <= -inf is false for finite num), so the pop loop
  // needs no bound check.
  Eigen::Index first = 0;
  while (first < freqs && !std::isfinite(pv[first])) ++first;
  PODID_CHECK(first < freqs);  // before >= 0: prev has a finite entry
  Eigen::Index top = 0;
  v[0] = first;
  xv[0] = xs[first];
  hs[0] = pv[first] + x2[first];
  zn[0] = -kInf;
  zd[0] = 1.0;
  // The top's entries also in registers: the next parabola's test does not
  // wait for the stores it just made (7 % of the programme).
  double top_h = hs[0], top_x = xv[0], top_zn = zn[0], top_zd = zd[0];
  for (Eigen::Index p = first + 1; p < freqs; ++p) {
    if (!std::isfinite(pv[p])) continue;  // forbidden or unreachable
    const double hp = pv[p] + x2[p];
    const double tx = xs[p];
    double num = hp - top_h;
    double den = 2.0 * lambda * (tx - top_x);
    while (num * top_zd <= top_zn * den) {
      --top;
      top_h = hs[top];
      top_x = xv[top];
      top_zn = zn[top];
      top_zd = zd[top];
      num = hp - top_h;
      den = 2.0 * lambda * (tx - top_x);
    }
    ++top;
    v[top] = p;
    xv[top] = top_x = tx;
    hs[top] = top_h = hp;
    zn[top] = top_zn = num;
    zd[top] = top_zd = den;
  }
  zn[top + 1] = kInf;
  zd[top + 1] = 1.0;
  double* out = next_.data();
  Eigen::Index e = 0;
  for (Eigen::Index q = 0; q < freqs; ++q) {
    const double xq = xs[q];
    while (zn[e + 1] < xq * zd[e + 1]) ++e;
    const Eigen::Index p = v[e];
    const double dx = xq - xs[p];
    out[q] = cost[q * stride] + pv[p] + lambda * dx * dx;
    back[q] = static_cast<Index>(p);
  }
  std::swap(prev_, next_);
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
