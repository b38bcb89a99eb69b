// The full-rate CWT's overlap-save blocks (wavelet/src/blocked_scales.hpp):
// the grouping's invariants, and long records against a direct convolution
// with the P-periodic kernel summed from its band in long double.
#include "../../wavelet/src/blocked_scales.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "podid/wavelet/cwt.hpp"
#include "roots_of_unity.hpp"
#include "same_outputs.hpp"

namespace podid::wavelet {
namespace {

using Complex = std::complex<double>;
using internal::BlockedScales;

TEST(BlockedScales, GroupsOnlyCompactScalesOfLongRecords) {
  const Eigen::Index p = 102400, times = 100000;
  // Decimations 1, 2 (two scales), 16, a scale cut at Nyquist and one whose
  // support outgrows the longest block.
  const std::vector<BlockedScales::Scale> scales = {
      {.decimation = 1, .inside = true, .support = 35.0},
      {.decimation = 2, .inside = true, .support = 50.5},
      {.decimation = 2, .inside = true, .support = 69.2},
      {.decimation = 16, .inside = true, .support = 455.0},
      {.decimation = 1, .inside = false, .support = 20.0},
      {.decimation = 64, .inside = true, .support = 2048.0}};
  const BlockedScales::Grouping grouping = BlockedScales::Plan(p, times, scales);
  ASSERT_EQ(grouping.group.size(), scales.size());
  EXPECT_EQ(grouping.group[4], -1);                 // not compact in time
  EXPECT_EQ(grouping.group[5], -1);                 // 4 H > the longest block
  EXPECT_EQ(grouping.group[1], grouping.group[2]);  // one grid per decimation
  for (std::size_t k = 0; k < 4; ++k) {
    ASSERT_GE(grouping.group[k], 0) << "scale " << k;
    const BlockedScales::Group& g = grouping.groups[static_cast<std::size_t>(grouping.group[k])];
    EXPECT_EQ(g.decimation, scales[k].decimation);
    // The overlap covers the group's largest support, half a block at most.
    EXPECT_GE(static_cast<double>(g.overlap), scales[k].support);
    EXPECT_LE(4 * g.overlap, g.length);
    EXPECT_EQ(g.hop, g.length - 2 * g.overlap);
    // The blocks cover every output time, the last one partly.
    EXPECT_GE(g.blocks * g.hop, times);
    EXPECT_LT((g.blocks - 1) * g.hop, times);
    // A block's inverse decimated no further than the group's bands allow.
    EXPECT_GE(g.inner, 1);
    EXPECT_LE(g.inner, g.decimation);
    EXPECT_EQ(g.length % g.inner, 0);
  }
  // The octave at D = 16 inverted as D' > 1 shorter inverses, D = 1 not.
  const BlockedScales::Group& wide = grouping.groups[static_cast<std::size_t>(grouping.group[0])];
  const BlockedScales::Group& narrow = grouping.groups[static_cast<std::size_t>(grouping.group[3])];
  EXPECT_EQ(wide.inner, 1);
  EXPECT_GT(narrow.inner, 1);
  // A scale's own D': L / D' holds its band, at most the group's; a band
  // that Execute does not take (reaching -L / 2) keeps D' = 1.
  const Eigen::Index l = narrow.length;
  EXPECT_EQ(BlockedScales::InnerDecimation(narrow, -3, l / narrow.inner), narrow.inner);
  EXPECT_EQ(BlockedScales::InnerDecimation(narrow, -3, l / narrow.inner + 1), narrow.inner / 2);
  EXPECT_EQ(BlockedScales::InnerDecimation(narrow, -l / 2, 4), 1);
  EXPECT_EQ(BlockedScales::InnerDecimation(narrow, l / 2 - 2, 4), 1);
  EXPECT_EQ(grouping.groups[static_cast<std::size_t>(grouping.group[2])].overlap, 70);
  // A record whose inverses stay in cache is not blocked.
  const BlockedScales::Grouping short_record =
      BlockedScales::Plan(BlockedScales::kMinPaddedLength - 1, 60000, scales);
  EXPECT_TRUE(short_record.groups.empty());
  EXPECT_EQ(std::count(short_record.group.begin(), short_record.group.end(), -1),
            static_cast<long>(scales.size()));
}

// W_k(j) = sum_t x(j - t) k(t), t within the kernel's support R, with the
// P-periodic padded sequence x (the record, then zeros or its periodic
// repetition) and k(t) = sum_b g_k(b) exp(2 pi i b t / P) / P over the kept
// bins of scale k, summed in long double with the angle reduced exactly.
struct RecordCase {
  Padding padding;
  WaveletFamily family;
  bool admissibility_correction;  // Morlet's stored (not generated) filters
};
// The case's name in the test's label (not its bytes).
void PrintTo(const RecordCase& c, std::ostream* os) {
  *os << (c.padding == Padding::kZero ? "zero" : "periodic") << " padding, "
      << (c.family == WaveletFamily::kMorse ? "Morse" : "Morlet")
      << (c.admissibility_correction ? " with the admissibility correction" : "");
}
class BlockedScalesRecord : public ::testing::TestWithParam<RecordCase> {};

TEST_P(BlockedScalesRecord, EqualsTheDirectConvolution) {
  // FFT rounding of the blocks (2048-8192 points) is about 1e-15 of sum
  // |x| |k|; the kernel's periodisation by L instead of P differs by its
  // tail beyond the overlap, below band_tolerance (1e-12) of its peak; the
  // reference drops the kernel beyond 1e-13 of its peak. Measured, with
  // the narrow bands' blocks inverted as D' > 1 shorter inverses: 2.0e-13
  // of max |W| for Morlet (either padding), 1.65e-13 with its admissibility
  // correction (stored filters), 6.9e-14 for Morse (2.2e-13, 1.8e-13 and
  // 6.9e-14 with one inverse of L a block). 1e-11 leaves a margin of 50 and
  // catches an overlap 10 % short (2.7e-11; 20 % short: 3.4e-9).
  constexpr double kRelativeTolerance = 1e-11;
  const double step = 1e-3;
  const Eigen::Index n = 70000;
  Eigen::VectorXd x(n);
  unsigned state = 12345u;  // a deterministic broadband record
  for (Eigen::Index m = 0; m < n; ++m) {
    state = state * 1664525u + 1013904223u;
    const double noise = static_cast<double>(state >> 8) / 16777216.0 - 0.5;
    x(m) = std::cos(2.0 * std::numbers::pi * 37.0 * static_cast<double>(m) * step) + noise;
  }
  CwtOptions o;
  o.padding = GetParam().padding;
  o.wavelet.family = GetParam().family;
  o.wavelet.admissibility_correction = GetParam().admissibility_correction;
  o.remove_mean = false;
  // 12-180 Hz at fs 1 kHz: every band inside (-500, 500) Hz, decimations 2-16.
  o.frequencies.min_frequency_Hz = 12.0;
  o.frequencies.max_frequency_Hz = 180.0;
  o.frequencies.voices_per_octave = 2;
  CwtTransform transform(o);
  Scalogram sg;
  transform.Compute(x, step, &sg);
  const Eigen::Index p = transform.padded_length();
  ASSERT_GE(p, BlockedScales::kMinPaddedLength);
  // The layout blocks these scales: it plans a forward FFT of a block length.
  const std::vector<int> forward = transform.Lengths(n, step).complex_forward;
  EXPECT_TRUE(std::any_of(forward.begin(), forward.end(),
                          [](int l) { return l == 2048 || l == 4096 || l == 8192; }));
  // ... and some of them as D' > 1 inverses of L / D' (m x D' = L).
  const std::vector<std::pair<int, int>> inverses = transform.Lengths(n, step).interleaved_backward;
  EXPECT_TRUE(std::any_of(inverses.begin(), inverses.end(), [](const std::pair<int, int>& mg) {
    const int l = mg.first * mg.second;
    return mg.second > 1 && (l == 2048 || l == 4096 || l == 8192);
  }));

  const std::vector<std::complex<long double>> w = testing::RootsOfUnity(p);
  const auto padded = [&](Eigen::Index i) {
    i = ((i % p) + p) % p;
    return i < n ? x(i) : 0.0;
  };
  double lo = 0.0, hi = 0.0;
  o.wavelet.Band(o.band_tolerance, &lo, &hi);
  const double bin_rad_per_s = 2.0 * std::numbers::pi / (static_cast<double>(p) * step);
  double worst = 0.0, peak = 0.0;
  for (Eigen::Index k = 0; k < sg.frequencies(); ++k) {
    const double s = sg.scales_s(k);
    const auto a = static_cast<Eigen::Index>(std::ceil(lo / (s * bin_rad_per_s)));
    const auto b = static_cast<Eigen::Index>(std::floor(hi / (s * bin_rad_per_s)));
    ASSERT_TRUE(a > -((p - 1) / 2) && b < p / 2) << "scale " << k << " reaches Nyquist";
    // The reference kernel's radius R: Morlet's Gaussian envelope exp(-t^2 /
    // 2 s^2) is below 1e-13 of its peak beyond 7.74 s; Morse's decays more
    // slowly: 3 x the transform's support (1.5 x 7.43 s) gives 6.9e-14 of max
    // |W|, where 2 x left the reference itself 3.2e-8 short.
    const double radius = GetParam().family == WaveletFamily::kMorse ? 3.0 * 1.5 * 7.43 : 7.74;
    const auto r = static_cast<Eigen::Index>(std::ceil(radius * s / step)) + 1;
    std::vector<Complex> kernel(static_cast<std::size_t>(2 * r + 1));
    for (Eigen::Index t = -r; t <= r; ++t) {
      std::complex<long double> sum = 0.0L;
      for (Eigen::Index bin = a; bin <= b; ++bin) {
        const long double g =
            o.wavelet.FourierTransform(s * bin * bin_rad_per_s) / static_cast<long double>(p);
        sum += g * w[static_cast<std::size_t>((((bin * t) % p) + p) % p)];
      }
      kernel[static_cast<std::size_t>(t + r)] =
          Complex(static_cast<double>(sum.real()), static_cast<double>(sum.imag()));
    }
    // Every 5th output time (each block boundary within 2 samples) and the
    // last ones.
    for (Eigen::Index j = 0; j < n; j += (j >= n - 20 ? 1 : 5)) {
      std::complex<long double> sum = 0.0L;
      for (Eigen::Index t = -r; t <= r; ++t) {
        sum += static_cast<long double>(padded(j - t)) *
               std::complex<long double>(kernel[static_cast<std::size_t>(t + r)]);
      }
      const Complex direct(static_cast<double>(sum.real()), static_cast<double>(sum.imag()));
      worst = std::max(worst, std::abs(sg.coefficients(j, k) - direct));
      peak = std::max(peak, std::abs(direct));
    }
  }
  EXPECT_LE(worst, kRelativeTolerance * peak) << "worst " << worst / peak << " of max |W|";

  // Three threads, |W| and W as float: the same blocks, the same numbers.
  testing::ExpectSameOnThreadsAndOutputs(x, step, o, sg);
}

INSTANTIATE_TEST_SUITE_P(
    Records,
    BlockedScalesRecord,
    ::testing::Values(RecordCase{Padding::kZero, WaveletFamily::kMorlet, false},
                      RecordCase{Padding::kPeriodic, WaveletFamily::kMorlet, false},
                      RecordCase{Padding::kZero, WaveletFamily::kMorlet, true},
                      RecordCase{Padding::kZero, WaveletFamily::kMorse, false}),
    [](const ::testing::TestParamInfo<RecordCase>& info) {
      const RecordCase& c = info.param;
      return std::string(c.padding == Padding::kZero ? "Zero" : "Periodic") +
             (c.family == WaveletFamily::kMorse ? "Morse" : "Morlet") +
             (c.admissibility_correction ? "Admissible" : "");
    });

}  // namespace
}  // namespace podid::wavelet
