// The CWT's per-scale filters (wavelet/src/scale_filters.hpp): generated
// Gaussians against exp in long double, stored filters against the wavelet's
// own psi^.
#include "../../wavelet/src/scale_filters.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace podid::wavelet {
namespace {

using internal::ScaleFilters;

// A generated value carries, since its exact start, up to 7 block steps
// (g0 about 48 roundings, rho0 and r0 9), 7 lane products (g_j about 139, r_j
// 16) and 16 steps with ratios of up to 32: about 530 roundings of 1.1e-16 at
// worst, 5.9e-14; t's own rounding adds |t| ulp(t), 7e-15 at 7.5 standard
// deviations (as for a stored filter). Seen: at most 1.9e-14.
constexpr double kGeneratedTolerance = 1e-13;

// The whole band generated, a chunk of kChunkBins at a time.
std::vector<double> Whole(
    double amplitude, double step, double centre, long long first, long long n) {
  const internal::ScaleFilter filter =
      internal::ScaleFilter::Gaussian(amplitude, step, centre, first);
  std::vector<double> out(static_cast<std::size_t>(n));
  double scratch[internal::ScaleFilter::kChunkBins];
  for (long long begin = 0; begin < n; begin += internal::ScaleFilter::kChunkBins) {
    const long long count = std::min<long long>(n - begin, internal::ScaleFilter::kChunkBins);
    const double* values = filter.Values(begin, count, scratch);
    std::copy(values, values + count, out.begin() + begin);
  }
  return out;
}

double LongDoubleGaussian(double amplitude, double step, double centre, long long bin) {
  const long double t = static_cast<long double>(step) * bin - centre;
  return static_cast<double>(amplitude * std::exp(-0.5L * t * t));
}

TEST(ScaleFilters, GeneratedGaussianWithin1e13OfEachValue) {
  struct Case {
    double amplitude, step, centre;
    long long first, n;
  };
  // Narrow and wide bands, bands from below zero, lengths that end inside a
  // restart block and inside a group of 8 lanes; each band reaches 7.5
  // standard deviations (1e-12 of the peak, the default band tolerance).
  const std::vector<Case> cases = {
      {2.0, 6.0 / 400.0, 6.0, -95, 1000},       {2.0, 6.0 / 4000.0, 6.0, -953, 9911},
      {1.0e-5, 1.3e-4, 6.0, -11000, 114000},    {3.5, 0.37, 6.0, -3, 41},
      {2.0, 6.0 / 25.0, 6.0, -5, 60},           {0.5, 1.0, 6.0, 0, 14},
      {2.0, 6.0 / 70000.0, 6.0, -16700, 173001}};
  for (const Case& c : cases) {
    const std::vector<double> out = Whole(c.amplitude, c.step, c.centre, c.first, c.n);
    double worst = 0.0;
    for (long long i = 0; i < c.n; ++i) {
      const double want = LongDoubleGaussian(c.amplitude, c.step, c.centre, c.first + i);
      ASSERT_GT(want, 0.0);
      worst = std::max(worst, std::abs(out[static_cast<std::size_t>(i)] - want) / want);
    }
    EXPECT_LE(worst, kGeneratedTolerance) << "step " << c.step << ", n " << c.n;
  }
}

// The transforms read a filter in chunks of at most kChunkBins from
// wherever their slots split the band: each chunk must give the values of
// the whole band's generation, bit for bit.
TEST(ScaleFilters, GeneratedValuesDoNotDependOnTheChunks) {
  const double amplitude = 2.0 / 102400, step = 6.0 / 9000.0, centre = 6.0;
  const long long first = -1300, n = 23001;
  const std::vector<double> whole = Whole(amplitude, step, centre, first, n);
  const internal::ScaleFilter filter =
      internal::ScaleFilter::Gaussian(amplitude, step, centre, first);
  double scratch[internal::ScaleFilter::kChunkBins];
  for (long long begin : {0LL, 1LL, 127LL, 128LL, 129LL, 1023LL, 1024LL, 5000LL, 22999LL}) {
    for (long long count : {1LL, 7LL, 8LL, 130LL, 511LL, 1000LL, 1024LL}) {
      if (begin + count > n) continue;
      const double* got = filter.Values(begin, count, scratch);
      for (long long i = 0; i < count; ++i) {
        ASSERT_EQ(got[i], whole[static_cast<std::size_t>(begin + i)]) << begin << " + " << i;
      }
    }
  }
}

// Morlet without the correction is generated; its values are psi^'s to the
// tolerance above. Everything else is stored, psi^'s values bit for bit.
TEST(ScaleFilters, GeneratedOnlyForOneGaussianAndStoredExactlyOtherwise) {
  MorletWavelet plain;
  MorletWavelet corrected;
  corrected.admissibility_correction = true;
  corrected.omega0 = 5.0;
  MorletWavelet morse;
  morse.family = WaveletFamily::kMorse;
  MorletWavelet energy;
  energy.normalisation = Normalisation::kEnergy;
  EXPECT_TRUE(ScaleFilters::Generated(plain));
  EXPECT_TRUE(ScaleFilters::Generated(energy));
  EXPECT_FALSE(ScaleFilters::Generated(corrected));
  EXPECT_FALSE(ScaleFilters::Generated(morse));
  const double bin_rad = 2.0 * 3.141592653589793 / (10240 * 0.001);
  for (const MorletWavelet& w : {plain, energy, corrected, morse}) {
    ScaleFilters filters;
    filters.Reset(w, 3);
    const double scales[3] = {0.005, 0.02, 0.2};
    const long long firsts[3] = {-40, -12, 0}, lasts[3] = {2500, 700, 60};
    for (int k = 0; k < 3; ++k)
      filters.Set(k, firsts[k], lasts[k], scales[k], 0.25 / 10240, bin_rad);
    double scratch[internal::ScaleFilter::kChunkBins];
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(filters.first(k), firsts[k]);
      ASSERT_EQ(filters.bins(k), lasts[k] - firsts[k] + 1);
      const internal::ScaleFilter filter = filters.Filter(k);
      for (long long b = firsts[k]; b <= lasts[k]; ++b) {
        const long long i = b - firsts[k];
        const double* values = filter.Values(i, 1, scratch);
        EXPECT_EQ(values == scratch, ScaleFilters::Generated(w));
        const double want = 0.25 / 10240 * w.FourierTransform(scales[k] * b * bin_rad);
        const double got = values[0];
        if (ScaleFilters::Generated(w)) {
          ASSERT_NEAR(got, want, kGeneratedTolerance * std::abs(want) + 1e-300) << "bin " << b;
        } else {
          ASSERT_EQ(got, want) << "bin " << b;
        }
      }
    }
  }
}

TEST(ScaleFilters, BytesAreTheStoredBandsOrNone) {
  MorletWavelet plain;
  MorletWavelet morse;
  morse.family = WaveletFamily::kMorse;
  EXPECT_EQ(ScaleFilters::Bytes(morse, 1000000), 8e6);
  EXPECT_EQ(ScaleFilters::Bytes(plain, 1000000), 0.0);
}

}  // namespace
}  // namespace podid::wavelet
