// Linked with podid::pod and podid::wavelet only (tests/CMakeLists.txt): if
// either needed the case-file, .mat or beam code (podid::model), this would
// not link.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "podid/pod/pod.hpp"
#include "podid/wavelet/ridge.hpp"

namespace podid {
namespace {

TEST(LinkSplit, PodAndWaveletWithoutTheModelLibrary) {
  constexpr double kStep_s = 1e-3;
  constexpr int kSamples = 2000;
  constexpr double kFrequency_Hz = 40.0;
  Eigen::MatrixXd x(2, kSamples);
  for (int j = 0; j < kSamples; ++j) {
    const double s = std::sin(2 * std::numbers::pi * kFrequency_Hz * j * kStep_s);
    x(0, j) = s;
    x(1, j) = 0.5 * s;
  }
  const PodResult pod = ComputePod(x);
  // A rank-1 record: one nonzero mode, U_1 = (2, 1) / sqrt(5).
  constexpr double kRoundoff = 1e-12;
  EXPECT_NEAR(pod.poms(0, 0), 2.0 / std::sqrt(5.0), kRoundoff);
  wavelet::RidgeFrequencyEstimator estimator;
  const wavelet::RidgeTrack& track = estimator.Estimate(pod.time_modes.col(0), kStep_s);
  ASSERT_GT(track.InsideCoiCount(), 0);
  // A pure tone: the median ridge frequency sits on it to the log grid's
  // half spacing at 32 voices per octave, 2^(1/64) - 1 = 1.1 % (the edges of
  // the cone of influence may stray further; the wavelet tests cover them).
  std::vector<double> inside;
  for (Eigen::Index j = 0; j < track.size(); ++j) {
    if (track.inside_coi[j]) inside.push_back(track.frequency_Hz[j]);
  }
  std::nth_element(inside.begin(), inside.begin() + inside.size() / 2, inside.end());
  constexpr double kGridTolerance = 0.011;
  EXPECT_NEAR(inside[inside.size() / 2] / kFrequency_Hz, 1.0, kGridTolerance);
}

}  // namespace
}  // namespace podid
