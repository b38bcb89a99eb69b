// InterpolateBandLimited (sub-stepping a sampled force) against band-limited
// analytic signals, and against linear interpolation.
#include "podid/core/interpolate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>

namespace podid {
namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;

/// A two-tone signal (17.3 Hz and 41.9 Hz, not periodic over the record)
/// plus a linear drift: sampled at 5 kHz for 1 s like the shared records.
double Signal(double t) { return std::sin(kTwoPi * 17.3 * t) + 0.4 * std::cos(kTwoPi * 41.9 * t + 0.3) + 2.0 * t; }

TEST(InterpolateBandLimited, KeepsTheSamplesAndHasTheFineLength) {
  // The interpolant passes through the samples: round-off of two FFTs of
  // 5120 points, ~1e-13 of the amplitude.
  constexpr double kTolerance = 1e-12;
  constexpr int kSamples = 5001, kFactor = 4;
  constexpr double kStep = 2e-4;
  Eigen::VectorXd x(kSamples);
  for (int i = 0; i < kSamples; ++i) x[i] = Signal(i * kStep);
  const Eigen::VectorXd y = InterpolateBandLimited(x, kFactor);
  ASSERT_EQ(y.size(), (kSamples - 1) * kFactor + 1);
  for (int i = 0; i < kSamples; ++i) EXPECT_NEAR(y[i * kFactor], x[i], kTolerance) << i;
  EXPECT_EQ(InterpolateBandLimited(x, 1), x);
}

TEST(InterpolateBandLimited, MatchesABandLimitedSignalBetweenTheSamples) {
  // Tones at 60 samples per period or more: the sinc interpolant's error
  // comes from the detrended record's end kinks (its spectrum decays as
  // 1 / f^2), largest near the ends. Away from the first and last 5 % it is
  // below 1e-5 of the amplitude (measured 4.9e-6); linear interpolation's
  // error there, ~ A (omega dt)^2 / 8, is 2.0e-4: 40 times more (checked >= 20).
  constexpr double kInteriorTolerance = 1e-5, kAdvantage = 20.0;
  constexpr int kSamples = 5001, kFactor = 4;
  constexpr double kStep = 2e-4;
  Eigen::VectorXd x(kSamples);
  for (int i = 0; i < kSamples; ++i) x[i] = Signal(i * kStep);
  const Eigen::VectorXd y = InterpolateBandLimited(x, kFactor);
  double sinc_error = 0.0, linear_error = 0.0;
  for (int j = kSamples * kFactor / 20; j < (kSamples - 1) * kFactor * 19 / 20; ++j) {
    const double t = j * kStep / kFactor;
    const int i = j / kFactor;
    const double s = static_cast<double>(j % kFactor) / kFactor;
    sinc_error = std::max(sinc_error, std::abs(y[j] - Signal(t)));
    linear_error = std::max(linear_error, std::abs((1 - s) * x[i] + s * x[i + 1] - Signal(t)));
  }
  std::cout << "[ figure   ] interior max error: band-limited " << sinc_error << ", linear "
            << linear_error << "\n";
  EXPECT_LE(sinc_error, kInteriorTolerance);
  EXPECT_GE(linear_error, kAdvantage * sinc_error);
}

TEST(InterpolateBandLimited, ShortInputs) {
  EXPECT_EQ(InterpolateBandLimited(Eigen::VectorXd::Constant(1, 3.0), 5), Eigen::VectorXd::Constant(1, 3.0));
  // Two samples: only the line, exactly.
  const Eigen::VectorXd y = InterpolateBandLimited((Eigen::VectorXd(2) << 1.0, 3.0).finished(), 4);
  ASSERT_EQ(y.size(), 5);
  for (int j = 0; j < 5; ++j) EXPECT_NEAR(y[j], 1.0 + 0.5 * j, 1e-15);
}

}  // namespace
}  // namespace podid
