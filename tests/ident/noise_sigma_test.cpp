// ObjectiveOptions::noise_corrected_sigma: the measured sigma the objective
// compares with is the clean record's, not the noisy one's.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "podid/core/case_file.hpp"
#include "podid/core/noise.hpp"
#include "podid/core/simulate.hpp"
#include "podid/ident/objective.hpp"
#include "test_support.hpp"

namespace podid::ident {
namespace {

TEST(NoiseCorrectedSigmaTest, MeasuredSigmaMovesToTheCleanRecordsOne) {
  // 5 % noise (of max |x(0)|) on the reference beam's 1 s record inflates
  // sigma_1 by ~0.3 %; the correction must remove at least 3/4 of that (what
  // remains is the noise's random cross term, ~1/sqrt(N) of the correction).
  constexpr double kMinBiasRemoved = 0.75;
  CaseDocument document = CaseDocument::Load(testing::ExamplePath("beam.toml"));
  document.Set("time.duration", "1.0");
  SimulateOptions clean_options;
  clean_options.add_noise = false;
  const TimeSeries clean = Simulate(document.ToSpec(), clean_options).sensors;
  TimeSeries noisy = clean;
  AddNoise(noisy, 0.05, 7);
  ObjectiveOptions options;
  options.weightings = {{"time-free", ObjectiveWeights::Preset("time-free")}};
  const ObjectiveFunction reference(document, clean, options);
  const ObjectiveFunction raw(document, noisy, options);
  options.noise_corrected_sigma = ObjectiveOptions::SigmaNoise::kCorrected;
  const ObjectiveFunction corrected(document, noisy, options);
  const double s_clean = reference.measured_pod().singular_values[0];
  const double bias_raw = raw.measured_pod().singular_values[0] / s_clean - 1;
  const double bias_corrected = corrected.measured_pod().singular_values[0] / s_clean - 1;
  std::cout << "sigma_1 bias: raw " << bias_raw << ", corrected " << bias_corrected << "\n";
  EXPECT_GT(bias_raw, 1e-3);
  EXPECT_LT(std::abs(bias_corrected), (1 - kMinBiasRemoved) * bias_raw);
  bool noted = false;
  for (const std::string& note : corrected.notes()) noted = noted || note.find("corrected for white noise") != std::string::npos;
  EXPECT_TRUE(noted);
}

}  // namespace
}  // namespace podid::ident
