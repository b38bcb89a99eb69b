// The ridge's dynamic programme, one column at a time (ridge_programme.hpp).
#include "ridge_programme.hpp"

#include <cmath>
#include <cstring>
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

template <typename Vector>
int Argmin(const Vector& total) {
  int k_best = -1;
  double value = kInf;
  for (Eigen::Index k = 0; k < total.size(); ++k) {
    if (total(k) < value) {
      value = total(k);
      k_best = static_cast<int>(k);
    }
  }
  return k_best;
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
  z_.resize(static_cast<std::size_t>(x_.size() + 1));
}

double RidgeProgramme::Bytes(Eigen::Index frequencies, Eigen::Index times, bool maximum) {
  const double cells = static_cast<double>(frequencies) * static_cast<double>(times);
  return (maximum ? 0.0 : Width(frequencies) * cells) + 4.0 * static_cast<double>(times);
}

void RidgeProgramme::Reset(Eigen::Index times) {
  PODID_CHECK(times >= 1);
  times_ = times;
  pushed_ = 0;
  if (!maximum_) back_.resize(static_cast<std::size_t>(width_ * x_.size() * times));
  best_.resize(static_cast<std::size_t>(times));
}

std::int64_t RidgeProgramme::Back(Eigen::Index k, Eigen::Index j) const {
  const std::size_t at = static_cast<std::size_t>(width_ * (j * x_.size() + k));
  std::uint32_t value = 0;
  if (width_ == 1) {
    value = back_[at];
  } else if (width_ == 2) {
    std::uint16_t v16 = 0;
    std::memcpy(&v16, &back_[at], 2);
    value = v16;
  } else {
    std::memcpy(&value, &back_[at], 4);
  }
  return value == none_ ? -1 : static_cast<std::int64_t>(value);
}

void RidgeProgramme::SetBack(Eigen::Index k, Eigen::Index j, std::int64_t value) {
  const std::size_t at = static_cast<std::size_t>(width_ * (j * x_.size() + k));
  const std::uint32_t v = value < 0 ? static_cast<std::uint32_t>(none_) : static_cast<std::uint32_t>(value);
  if (width_ == 1) {
    back_[at] = static_cast<unsigned char>(v);
  } else if (width_ == 2) {
    const std::uint16_t v16 = static_cast<std::uint16_t>(v);
    std::memcpy(&back_[at], &v16, 2);
  } else {
    std::memcpy(&back_[at], &v, 4);
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
    for (Eigen::Index q = 0; q < freqs; ++q) SetBack(q, j, -1);
  } else if (lambda_ == 0.0) {
    const double floor = prev_(before);
    prev_ = column.array() + floor;
    for (Eigen::Index q = 0; q < freqs; ++q) SetBack(q, j, before);
  } else {
    Eigen::Index top = -1;
    for (Eigen::Index p = 0; p < freqs; ++p) {
      if (!std::isfinite(prev_(p))) continue;
      const double hp = prev_(p) + x2_(p);
      double s = -kInf;
      while (top >= 0) {
        const Eigen::Index q = v_[static_cast<std::size_t>(top)];
        s = (hp - (prev_(q) + x2_(q))) / (2.0 * lambda_ * (x_(p) - x_(q)));
        if (s <= z_[static_cast<std::size_t>(top)]) {
          --top;
        } else {
          break;
        }
      }
      ++top;
      v_[static_cast<std::size_t>(top)] = p;
      z_[static_cast<std::size_t>(top)] = top == 0 ? -kInf : s;
    }
    PODID_CHECK(top >= 0);  // before >= 0: prev has a finite entry
    z_[static_cast<std::size_t>(top + 1)] = kInf;
    Eigen::Index e = 0;
    for (Eigen::Index q = 0; q < freqs; ++q) {
      while (z_[static_cast<std::size_t>(e + 1)] < x_(q)) ++e;
      const Eigen::Index p = v_[static_cast<std::size_t>(e)];
      const double dx = x_(q) - x_(p);
      next_(q) = cost[q * stride] + prev_(p) + lambda_ * dx * dx;
      SetBack(q, j, p);
    }
    std::swap(prev_, next_);
  }
  best_[static_cast<std::size_t>(j)] = Argmin(prev_);
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
