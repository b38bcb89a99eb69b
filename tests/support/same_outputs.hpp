#pragma once
// The full-rate CWT's paths that must give the same numbers bit for bit:
// three threads (other chunks, so other columns written through the
// thread's buffer), |W| as float and W as complex float (the same transform,
// rounded once).

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <complex>

#include "podid/wavelet/cwt.hpp"

namespace podid::testing {

/// Cwt(x, step, options) on three threads, as |W| and as complex float, gives
/// `reference` (the complex output of the same options on one thread).
inline void ExpectSameOnThreadsAndOutputs(const Eigen::VectorXd& x,
                                          double step,
                                          wavelet::CwtOptions options,
                                          const wavelet::Scalogram& reference) {
  options.output = wavelet::CwtOutput::kComplex;
  options.threads = 3;
  EXPECT_TRUE(wavelet::Cwt(x, step, options).coefficients == reference.coefficients);
  options.threads = 1;
  options.output = wavelet::CwtOutput::kMagnitudeFloat;
  EXPECT_TRUE(wavelet::Cwt(x, step, options).magnitude ==
              reference.coefficients.cwiseAbs().cast<float>());
  // Each part of the complex output rounded once, and no complex double kept.
  options.output = wavelet::CwtOutput::kComplexFloat;
  const wavelet::Scalogram single = wavelet::Cwt(x, step, options);
  EXPECT_EQ(single.coefficients.size(), 0);
  EXPECT_TRUE(single.coefficients_float == reference.coefficients.cast<std::complex<float>>());
}

}  // namespace podid::testing
