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
  h_all_.resize(x_.size());
  v_.resize(static_cast<std::size_t>(x_.size()));
  h_.resize(static_cast<std::size_t>(x_.size()));
  xv_.resize(static_cast<std::size_t>(x_.size()));
  zn_.resize(static_cast<std::size_t>(x_.size() + 1));
  zd_.resize(static_cast<std::size_t>(x_.size() + 1));
  column_back_.resize(static_cast<std::size_t>(x_.size()));
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

void RidgeProgramme::StoreColumn(Eigen::Index j) {
  const Eigen::Index freqs = x_.size();
  unsigned char* out = back_.data() + static_cast<std::size_t>(width_ * j * freqs);
  const std::uint32_t* in = column_back_.data();
  if (width_ == 1) {
    for (Eigen::Index q = 0; q < freqs; ++q) out[q] = static_cast<unsigned char>(in[q]);
  } else if (width_ == 2) {
    for (Eigen::Index q = 0; q < freqs; ++q) {
      const std::uint16_t v = static_cast<std::uint16_t>(in[q]);
      std::memcpy(out + 2 * q, &v, 2);
    }
  } else {
    std::memcpy(out, in, 4 * static_cast<std::size_t>(freqs));
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
    std::fill(column_back_.begin(), column_back_.end(), static_cast<std::uint32_t>(none_));
    StoreColumn(j);
  } else if (lambda_ == 0.0) {
    const double floor = prev_(before);
    prev_ = column.array() + floor;
    std::fill(column_back_.begin(), column_back_.end(), static_cast<std::uint32_t>(before));
    StoreColumn(j);
  } else {
    // Intersections z = num / den (den > 0) are compared by cross-multiplying:
    // no division on the stack's dependency chain.
    h_all_ = prev_ + x2_;
    Eigen::Index top = -1;
    for (Eigen::Index p = 0; p < freqs; ++p) {
      if (!std::isfinite(prev_(p))) continue;
      const double hp = h_all_(p);
      double num = -kInf, den = 1.0;
      const double tx = x_(p);
      while (top >= 0) {
        const std::size_t t = static_cast<std::size_t>(top);
        num = hp - h_[t];
        den = 2.0 * lambda_ * (tx - xv_[t]);
        if (num * zd_[t] <= zn_[t] * den) {
          --top;
        } else {
          break;
        }
      }
      ++top;
      const std::size_t t = static_cast<std::size_t>(top);
      v_[t] = p;
      xv_[t] = tx;
      h_[t] = hp;
      zn_[t] = top == 0 ? -kInf : num;
      zd_[t] = top == 0 ? 1.0 : den;
    }
    PODID_CHECK(top >= 0);  // before >= 0: prev has a finite entry
    zn_[static_cast<std::size_t>(top + 1)] = kInf;
    zd_[static_cast<std::size_t>(top + 1)] = 1.0;
    std::size_t e = 0;
    for (Eigen::Index q = 0; q < freqs; ++q) {
      while (zn_[e + 1] < x_(q) * zd_[e + 1]) ++e;
      const Eigen::Index p = v_[e];
      const double dx = x_(q) - x_(p);
      next_(q) = cost[q * stride] + prev_(p) + lambda_ * dx * dx;
      column_back_[static_cast<std::size_t>(q)] = static_cast<std::uint32_t>(p);
    }
    std::swap(prev_, next_);
    StoreColumn(j);
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
