// The CWT's per-scale filters (wavelet/src/scale_filters.hpp): generated
// Gaussians against exp in long double, stored filters against the wavelet's
// own psi^.
#include "../../wavelet/src/scale_filters.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
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

// omega0 up to kMaxOmega0 = 100, bands from bin 0 (t = -omega0), as the
// transforms lay them out: from t = -omega0 the recurrences' ratios up to the
// peak, exp(omega0^2 / 2), overflowed beyond 37.68 and the values were NaN or
// 0. Now 0 exactly where t < -32 (the true value is below e^-512 of the
// peak), and from there within the tolerance above wherever t >= -8 (the
// default band, 1e-12 of the peak, reaches 7.43); further down the start's
// rounding of t (half an ulp of 32, 3.6e-15) shifts the Gaussian and costs
// |t| 3.6e-15 of a value: kTailTolerance = 1e-13 + 32 x 4e-15 = 2.3e-13.
// Both beyond the conditioning of a Gaussian at a rounded t (below), which
// the long double reference does not share, and with kFromZeroTolerance for
// the band: from t = -32 a coarse grid runs its recurrence far from an exact
// start. Measured beyond the conditioning: AVX-512 clone 6e-14; the SSE2
// clone (the sanitizer build: other roundings, no FMA) 1.2e-13 at centre
// 100, step 0.3 (132 bins from t = -32 to the peak), so 2e-13.
TEST(ScaleFilters, GeneratedFromBinZeroForEveryOmega0) {
  constexpr double kFromZeroTolerance = 2e-13;
  constexpr double kTailTolerance = 2.3e-13;
  for (double centre : {6.0, 34.0, 37.6, 37.7, 40.0, 60.0, 100.0}) {
    // Steps of 1 to 3000 bins per unit of t; bands to t = +7.5.
    for (double step : {1.0, 0.3, 1.0 / 128.0, 1.0 / 700.0, 1.0 / 3000.0}) {
      const double amplitude = 2.0 / 102400;
      const auto n = static_cast<long long>(std::ceil((centre + 7.5) / step)) + 1;
      const std::vector<double> out = Whole(amplitude, step, centre, 0, n);
      double worst_band = 0.0, worst_tail = 0.0;
      for (long long i = 0; i < n; ++i) {
        const double got = out[static_cast<std::size_t>(i)];
        ASSERT_TRUE(std::isfinite(got)) << "centre " << centre << " step " << step << " bin " << i;
        const double t = step * static_cast<double>(i) - centre;
        const double want = LongDoubleGaussian(amplitude, step, centre, i);
        if (t < -32.0) {
          ASSERT_EQ(got, 0.0) << "centre " << centre << " step " << step << " bin " << i;
          ASSERT_LT(want, amplitude * 4.5e-223);
          continue;
        }
        ASSERT_GT(want, 0.0);
        // Beyond the recurrence's own roundings, the generator's t = c b -
        // centre is a double (the reference's a long double): |dt| <= 2 eps
        // (|c b| + centre), and the Gaussian's relative change is |t dt|.
        // That conditioning grows with the centre: 1.3e-13 at t = -8 for
        // centre 100 on the SSE2 clone (1.1e-13 of it the rounded t).
        const double conditioning = std::abs(t) * 2.0 * std::numeric_limits<double>::epsilon() *
                                    (std::abs(t) + 2.0 * centre);
        const double error = std::abs(got - want) / want - conditioning;
        (t >= -8.0 ? worst_band : worst_tail) =
            std::max(t >= -8.0 ? worst_band : worst_tail, error);
      }
      EXPECT_LE(worst_band, kFromZeroTolerance) << "centre " << centre << " step " << step;
      EXPECT_LE(worst_tail, kTailTolerance) << "centre " << centre << " step " << step;
      std::printf("centre %5.1f step %.3g: %lld bins, worst %.2g (t >= -8), %.2g (t < -8) "
                  "beyond the conditioning\n",
                  centre, step, n, worst_band, worst_tail);
    }
  }
  // Any cut gives the same values (exact starts from the first kept entry).
  const double amplitude = 2.0 / 102400, step = 1.0 / 700.0, centre = 100.0;
  const long long n = 75000;
  const std::vector<double> whole = Whole(amplitude, step, centre, 0, n);
  const internal::ScaleFilter filter = internal::ScaleFilter::Gaussian(amplitude, step, centre, 0);
  double scratch[internal::ScaleFilter::kChunkBins];
  for (long long begin : {0LL, 47000LL, 47599LL, 47600LL, 47601LL, 48623LL, 48624LL, 60000LL}) {
    for (long long count : {1LL, 7LL, 130LL, 1024LL}) {
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
