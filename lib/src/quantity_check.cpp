#include "podid/core/quantity_check.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "fftw_util.hpp"
#include "podid/core/error.hpp"

namespace podid {
namespace {

// Power per bin 0..n/2, summed over channels (Hann window, mean removed).
Eigen::VectorXd Power(const TimeSeries& s, Eigen::Index n) {
  Eigen::VectorXd power = Eigen::VectorXd::Zero(n / 2 + 1);
  auto x = internal::FftwAllocate<double>(static_cast<std::size_t>(n));
  auto spectrum = internal::FftwAllocate<fftw_complex>(static_cast<std::size_t>(n / 2 + 1));
  const auto fft = internal::FftwRealPlan::Forward(n, x.get(), spectrum.get());
  for (Eigen::Index c = 0; c < s.channels(); ++c) {
    const double mean = s.values.col(c).head(n).mean();
    for (Eigen::Index i = 0; i < n; ++i) {
      const double hann =
          0.5 - 0.5 * std::cos(2 * std::numbers::pi * i / static_cast<double>(n - 1));
      x[i] = hann * (s.values(i, c) - mean);
    }
    fft.Execute();
    for (Eigen::Index k = 0; k <= n / 2; ++k) {
      power[k] += spectrum[k][0] * spectrum[k][0] + spectrum[k][1] * spectrum[k][1];
    }
  }
  return power;
}

int Order(SensorQuantity q) {
  return q == SensorQuantity::kDisplacement ? 0 : q == SensorQuantity::kVelocity ? 1 : 2;
}

}  // namespace

const char* ToString(SensorQuantity quantity) {
  switch (quantity) {
    case SensorQuantity::kDisplacement:
      return "displacement";
    case SensorQuantity::kVelocity:
      return "velocity";
    case SensorQuantity::kAcceleration:
      return "acceleration";
  }
  return "?";
}

QuantityCheck CheckMeasuredQuantity(const TimeSeries& measured,
                                    const TimeSeries& simulated,
                                    SensorQuantity declared) {
  QuantityCheck check;
  check.likely = declared;
  PODID_CHECK(measured.channels() == simulated.channels());
  const Eigen::Index n = std::min(measured.samples(), simulated.samples());
  // Too short for a spectrum, or longer than one FFT: not determined.
  if (n < 16 || n > internal::FftwRealPlan::kMaxLength || measured.channels() == 0) return check;
  const Eigen::VectorXd pm = Power(measured, n), ps = Power(simulated, n);
  const double max_m = pm.tail(pm.size() - 1).maxCoeff(), max_s = ps.tail(ps.size() - 1).maxCoeff();
  if (!(max_m > 0.0) || !(max_s > 0.0) || !std::isfinite(max_m) || !std::isfinite(max_s))
    return check;
  const double df = 1.0 / (static_cast<double>(n) * measured.step_s());
  // White measurement noise adds a flat floor to the measured spectrum only,
  // which lifts the weak (higher) modes' peaks and bends the ratio upwards
  // (a displacement record with 10 % noise read as f^0.56, "velocity"). The
  // median bin estimates the floor (a lightly damped structure's lines hold
  // few bins); it is taken out, and a peak less than kPeakOverFloor above it
  // is not used.
  constexpr double kPeakOverFloor = 10.0;
  std::vector<double> sorted(pm.data() + 1, pm.data() + pm.size());
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double floor = sorted[sorted.size() / 2];
  // The simulated spectrum's peaks (its modes): a bin that is the largest
  // within +-max(3, k / 20) bins, with more than 1e-8 of the peak power on
  // both sides. At a peak the ratio is the mode's w^k; between peaks both
  // spectra are the same peaks' leakage, whose ratio is flat.
  // Both ends of the window never decrease with k, so one pass keeps its
  // maximum: a queue of candidates (indices of decreasing power), O(n) in
  // all instead of O(n r) (9.5 s of a 10^6-sample `podid identify`).
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  check.low_Hz = std::numeric_limits<double>::infinity();
  const Eigen::Index last = ps.size() - 1;
  std::vector<Eigen::Index> candidates;
  candidates.reserve(static_cast<std::size_t>(last));
  std::size_t head = 0;
  Eigen::Index next = 1;  // the first index not yet queued
  for (Eigen::Index k = 2; k < last; ++k) {
    const Eigen::Index r = std::max<Eigen::Index>(3, k / 20);
    const Eigen::Index lo = std::max<Eigen::Index>(1, k - r), hi = std::min(last, k + r);
    for (; next <= hi; ++next) {
      while (candidates.size() > head && ps[candidates.back()] <= ps[next]) candidates.pop_back();
      candidates.push_back(next);
    }
    while (candidates[head] < lo) ++head;
    if (ps[k] < ps[candidates[head]]) continue;
    if (!(ps[k] > 1e-8 * max_s && pm[k] > 1e-8 * max_m && pm[k] > kPeakOverFloor * floor)) continue;
    const double f = static_cast<double>(k) * df;
    const double x = std::log10(f), y = 0.5 * std::log10((pm[k] - floor) / ps[k]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    ++check.bins;
    check.low_Hz = std::min(check.low_Hz, f);
    check.high_Hz = std::max(check.high_Hz, f);
  }
  const double count = check.bins;
  const double spread = count > 0 ? sxx / count - (sx / count) * (sx / count) : 0.0;
  if (check.bins < kQuantityCheckMinPeaks || !(check.high_Hz >= 1.5 * check.low_Hz) ||
      !(spread > 0)) {
    return check;
  }
  check.determined = true;
  check.exponent = (sxy / count - (sx / count) * (sy / count)) / spread;
  if (std::abs(check.exponent) < 0.5) return check;
  check.mismatch = true;
  const int order =
      std::clamp(Order(declared) + static_cast<int>(std::lround(check.exponent)), 0, 2);
  check.likely = order == 0   ? SensorQuantity::kDisplacement
                 : order == 1 ? SensorQuantity::kVelocity
                              : SensorQuantity::kAcceleration;
  check.message =
      "the measured/simulated amplitude ratio grows as f^" + ToShortText(check.exponent) + " (" +
      ToShortText(20 * check.exponent) + " dB/decade over " + ToShortText(check.low_Hz) + ".." +
      ToShortText(check.high_Hz) +
      " Hz; f^0 when the quantities agree): the record "
      "looks like " +
      ToString(check.likely) + " while [sensors] quantity = \"" + ToString(declared) + "\"";
  return check;
}

}  // namespace podid
