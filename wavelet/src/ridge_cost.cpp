// -log|W| and |W| over runs of coefficients (ridge_cost.hpp).
#include "ridge_cost.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "podid/core/target_clones.hpp"

namespace podid::wavelet::internal {

double UnitScale(const Eigen::Ref<const Eigen::MatrixXcd>& w, bool* all_finite) {
  double top = 0.0;
  bool finite = true;
  for (Eigen::Index k = 0; k < w.cols(); ++k) {
    const Eigen::Map<const Eigen::ArrayXd> parts(reinterpret_cast<const double*>(w.col(k).data()),
                                                 2 * w.rows());
    const double column_top = parts.abs().template maxCoeff<Eigen::PropagateNaN>();
    if (std::isfinite(column_top)) {
      top = std::max(top, column_top);
      continue;
    }
    finite = false;
    for (Eigen::Index i = 0; i < parts.size(); ++i) {
      if (std::isfinite(parts(i))) top = std::max(top, std::abs(parts(i)));
    }
  }
  if (all_finite != nullptr) *all_finite = finite;
  int exponent = 0;
  std::frexp(top, &exponent);
  return std::ldexp(1.0, -exponent);
}
namespace {

// ln v for v >= kRidgeCostFloor, v finite, branch-free and in integer
// selects only (GCC then vectorises loops over it): v = 2^e m with m in
// [1/sqrt 2, sqrt 2), ln m = 2 atanh(t), t = (m - 1) / (m + 1), |t| <= 0.1716;
// the series 2 t sum_k t^(2k) / (2k + 1) to k = 10 leaves a truncation below
// 0.1716^22 / 23 = 6e-19 of ln m. The floor is applied on the bit pattern
// (positive doubles order as their bits).
[[gnu::always_inline]] inline double MinusHalfLogFloored(double power) {
  constexpr std::uint64_t kFloorBits = std::bit_cast<std::uint64_t>(kRidgeCostFloor);
  constexpr std::uint64_t kMantissa = 0x000FFFFFFFFFFFFFULL;
  // sqrt(2)'s mantissa bits: a mantissa above them is reduced by a factor 2.
  constexpr std::uint64_t kSqrt2Mantissa = std::bit_cast<std::uint64_t>(std::numbers::sqrt2) & kMantissa;
  std::uint64_t bits = std::bit_cast<std::uint64_t>(power);
  bits = bits < kFloorBits ? kFloorBits : bits;
  const std::uint64_t high = (bits & kMantissa) > kSqrt2Mantissa ? 1 : 0;
  const double m = std::bit_cast<double>((bits & kMantissa) | ((1023 - high) << 52));
  // The exponent e = biased - 1023 + high as a double, without an int64
  // conversion (the 2^52 trick).
  const double e = std::bit_cast<double>(((bits >> 52) + high) | 0x4330000000000000ULL) -
                   (4503599627370496.0 + 1023.0);
  const double t = (m - 1.0) / (m + 1.0);
  const double z = t * t;
  double series = 1.0 / 21.0;
  series = series * z + 1.0 / 19.0;
  series = series * z + 1.0 / 17.0;
  series = series * z + 1.0 / 15.0;
  series = series * z + 1.0 / 13.0;
  series = series * z + 1.0 / 11.0;
  series = series * z + 1.0 / 9.0;
  series = series * z + 1.0 / 7.0;
  series = series * z + 1.0 / 5.0;
  series = series * z + 1.0 / 3.0;
  series = series * z + 1.0;
  return -0.5 * (e * std::numbers::ln2 + 2.0 * t * series);
}

// f(i, re, im) for the parts of w[i], i < n: the one loop shape each clone
// below vectorises (inlined, so the loop body is the caller's).
template <class F>
[[gnu::always_inline]] inline void ForEachParts(const std::complex<double>* w,
                                                Eigen::Index n,
                                                F f) {
  const double* __restrict parts = reinterpret_cast<const double*>(w);
  for (Eigen::Index i = 0; i < n; ++i) f(i, parts[2 * i], parts[2 * i + 1]);
}

}  // namespace

PODID_CLONES_V4 void RidgePower(const std::complex<double>* w,
                                Eigen::Index n,
                                double scale,
                                double* power) {
  double* __restrict out = power;
  ForEachParts(w, n, [out, scale](Eigen::Index i, double re, double im) {
    re *= scale;
    im *= scale;
    out[i] = re * re + im * im;
  });
}

// This file is built with -fno-math-errno (wavelet/CMakeLists.txt): with
// errno, GCC calls libm's sqrt for each NaN result and keeps the loop scalar;
// without it each clone's loop is vsqrtpd at its own width (4 or 8 lanes
// against Eigen's 2-lane SSE2 packets before: the float scalogram of fCWT's
// case spent 14 % of its time in them, docs/benchmark-log.md). Squares sum to
// >= 0 or NaN, so no errno was ever due.
PODID_CLONES_V4 void Magnitudes(const std::complex<double>* w, Eigen::Index n, double* magnitude) {
  double* __restrict out = magnitude;
  ForEachParts(
      w, n, [out](Eigen::Index i, double re, double im) { out[i] = std::sqrt(re * re + im * im); });
}

PODID_CLONES_V4 void MagnitudesToFloat(const std::complex<double>* w,
                                       Eigen::Index n,
                                       double scale,
                                       float* out) {
  float* __restrict to = out;
  ForEachParts(w, n, [to, scale](Eigen::Index i, double re, double im) {
    to[i] = static_cast<float>(std::sqrt(re * re + im * im) * scale);
  });
}

// Runs of 8 as one vector each, the tail too (padded): the ridge programme
// asks for a few cells at a time, where a scalar tail was the whole cost.
PODID_CLONES_V4 void RidgeCostOfPower(const double* power, Eigen::Index n, double* cost) {
  constexpr Eigen::Index kLanes = 8;
  Eigen::Index i = 0;
  for (; i + kLanes <= n; i += kLanes) {
    double out[kLanes];
    for (Eigen::Index l = 0; l < kLanes; ++l) out[l] = MinusHalfLogFloored(power[i + l]);
    std::copy(out, out + kLanes, cost + i);  // after the reads: cost == power allowed
  }
  if (i == n) return;
  double in[kLanes], out[kLanes];
  std::fill(in, in + kLanes, 1.0);
  std::copy(power + i, power + n, in);
  for (Eigen::Index l = 0; l < kLanes; ++l) out[l] = MinusHalfLogFloored(in[l]);
  std::copy(out, out + (n - i), cost + i);
}

void RidgeCost(const std::complex<double>* w, Eigen::Index n, double scale, double* out) {
  RidgePower(w, n, scale, out);
  RidgeCostOfPower(out, n, out);
}

}  // namespace podid::wavelet::internal
