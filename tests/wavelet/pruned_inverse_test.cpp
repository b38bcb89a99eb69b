// The full-rate CWT's pruned inverse FFT (wavelet/src/pruned_inverse.hpp)
// against a direct inverse DFT in long double, and the full-rate transform
// at large decimations against a direct frequency-domain evaluation.
#include "../../wavelet/src/pruned_inverse.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "../../wavelet/src/full_rate.hpp"
#include "podid/wavelet/cwt.hpp"
#include "podid/wavelet/plans.hpp"
#include "roots_of_unity.hpp"
#include "same_outputs.hpp"

namespace podid::wavelet {
namespace {

using Complex = std::complex<double>;
using internal::PrunedInverse;
using testing::ExpectSameOnThreadsAndOutputs;
using testing::RootsOfUnity;

// y_j = sum_b Y_b exp(2 pi i b j / P) at one output j, summed in long double
// with the angle reduced exactly (b j mod P in integers; w: RootsOfUnity(P)):
// an independent, slow reference.
Complex DirectInverseAt(const std::vector<Complex>& band,
                        Eigen::Index first_bin,
                        Eigen::Index j,
                        const std::vector<std::complex<long double>>& w) {
  const auto p = static_cast<Eigen::Index>(w.size());
  long double re = 0.0L, im = 0.0L;
  for (std::size_t i = 0; i < band.size(); ++i) {
    const Eigen::Index b = first_bin + static_cast<Eigen::Index>(i);
    const auto& e = w[static_cast<std::size_t>((((b % p) + p) % p) * j % p)];
    re += band[i].real() * e.real() - band[i].imag() * e.imag();
    im += band[i].real() * e.imag() + band[i].imag() * e.real();
  }
  return {static_cast<double>(re), static_cast<double>(im)};
}

// Every y_j, j < P.
std::vector<Complex> DirectInverse(const std::vector<Complex>& band,
                                   Eigen::Index first_bin,
                                   Eigen::Index p) {
  const std::vector<std::complex<long double>> w = RootsOfUnity(p);
  std::vector<Complex> y(static_cast<std::size_t>(p));
  for (Eigen::Index j = 0; j < p; ++j)
    y[static_cast<std::size_t>(j)] = DirectInverseAt(band, first_bin, j, w);
  return y;
}

// Spectrum X_0 .. X_(P/2) of a real signal (deterministic, no symmetry), and
// the band Y_b = X_b g_i, b = first + i, its filter g and L1 norm sum |Y_b|.
struct TestBand {
  std::vector<Complex> spectrum, band;
  std::vector<double> filter;
  double l1 = 0.0;
};
TestBand MakeBand(Eigen::Index p, Eigen::Index first, Eigen::Index bins) {
  TestBand t;
  t.spectrum.resize(static_cast<std::size_t>(p / 2 + 1));
  for (std::size_t b = 0; b < t.spectrum.size(); ++b) {
    t.spectrum[b] = Complex(std::cos(0.37 * b * b + 1.0), std::sin(1.3 * b) + 0.1);
  }
  t.spectrum[0] = Complex(t.spectrum[0].real(), 0.0);
  for (Eigen::Index i = 0; i < bins; ++i) {
    const Eigen::Index b = first + i;
    t.filter.push_back(0.5 + 0.4 * std::sin(0.1 * static_cast<double>(i)));
    const Complex x = b >= 0 ? t.spectrum[static_cast<std::size_t>(b)]
                             : std::conj(t.spectrum[static_cast<std::size_t>(-b)]);
    t.band.push_back(x * t.filter.back());
    t.l1 += std::abs(t.band.back());
  }
  return t;
}

TEST(PrunedInverse, EveryDecimationEqualsTheDirectInverseDft) {
  // Of the band's L1 norm sum |Y_b|: FFTW's error is O(eps log2 P) (5e-16
  // measured at D = 1, P = 5040), and a block's twiddles carry at most 8
  // roundings (the exact table value every 8th block, then a recurrence:
  // 1.7e-15 measured at D = 28). 3e-15 leaves a factor ~2 of margin and
  // catches a recurrence without the anchors (1e-14 at D = 63).
  constexpr double kRelativeTolerance = 3e-15;
  const Eigen::Index p = 5040;  // 2^4 3^2 5 7: divisors 2..63 of every kind
  PrunedInverse inverse;
  inverse.Reset(p, false);
  // Bands: negative bins, one reaching Nyquist, narrow and wide, and starts
  // that make the band wrap around the end of a block.
  const std::vector<std::pair<Eigen::Index, Eigen::Index>> bands = {
      {-40, 100}, {7, 60}, {2400, 121}, {-2519, 80}, {300, 1200}, {-1000, 2500}, {1, 1}};
  std::vector<Complex> work(static_cast<std::size_t>(PrunedInverse::WorkSize(p))),
      out(static_cast<std::size_t>(p)), column(static_cast<std::size_t>(p) + 1);
  std::vector<float> magnitude(static_cast<std::size_t>(p));
  for (const auto& [first, bins] : bands) {
    const TestBand t = MakeBand(p, first, bins);
    const double l1 = t.l1;
    const std::vector<Complex> direct = DirectInverse(t.band, first, p);
    int tried = 0;
    for (Eigen::Index d = 1; d <= PrunedInverse::kMaxDecimation; ++d) {
      if (p % d != 0 || p / d < bins) continue;
      // Every batch size G dividing D: the blocks transformed G at a time.
      for (Eigen::Index batch = 1; batch <= d; ++batch) {
        if (d % batch != 0) continue;
        ++tried;
        std::fill(out.begin(), out.end(),
                  Complex(std::nan(""), 0.0));  // every entry must be written
        inverse.Execute(t.spectrum.data(), internal::ScaleFilter::Stored(t.filter.data()), first,
                        bins, d, batch, inverse.Plan(d, batch), work.data(), out.data());
        // Outputs from 0, from inside the first group of D and from beyond
        // it, up to P - 3: a last row of blocks only partly used.
        // Into a column at either 32-byte phase, as a scalogram's columns
        // start (16-byte aligned allocations, columns of any length).
        for (const auto& [from, shift] : std::vector<std::pair<Eigen::Index, std::size_t>>{
                 {0, 0}, {0, 1}, {3, 0}, {3, 1}, {37, 0}, {37, 1}}) {
          const Eigen::Index times = p - 3 - from;
          std::fill(column.begin(), column.end(), Complex(std::nan(""), 0.0));
          inverse.Gather(out.data(), d, from, times, 1.0, column.data() + shift);
          // Nothing written outside the `times` outputs.
          for (std::size_t u = 0; u < column.size(); ++u) {
            if (u < shift || u >= shift + static_cast<std::size_t>(times)) {
              ASSERT_TRUE(std::isnan(column[u].real())) << "D " << d << " entry " << u;
            }
          }
          inverse.GatherMagnitude(out.data(), d, from, times, 1.0,
                                  reinterpret_cast<float*>(work.data()), magnitude.data());
          double worst = 0.0, worst_magnitude = 0.0;
          for (Eigen::Index j = 0; j < times; ++j) {
            const auto u = static_cast<std::size_t>(j);
            const Complex y = direct[static_cast<std::size_t>(from + j)];
            worst = std::max(worst, std::abs(column[u + shift] - y));
            worst_magnitude = std::max(worst_magnitude,
                                       std::abs(static_cast<double>(magnitude[u]) - std::abs(y)));
          }
          EXPECT_LE(worst, kRelativeTolerance * l1)
              << "band " << first << "+" << bins << " D " << d << " G " << batch << " from " << from
              << " shift " << shift;
          // float rounding: 2^-24 of |y| <= sum |Y_b|.
          EXPECT_LE(worst_magnitude, 6e-8 * l1) << "band " << first << "+" << bins << " D " << d
                                                << " G " << batch << " from " << from;
        }
      }
    }
    EXPECT_GE(tried, 1);
    const Eigen::Index chosen = PrunedInverse::Decimation(p, bins);
    EXPECT_EQ(p % chosen, 0);
    EXPECT_GE(p / chosen, bins);
  }
  // The choice: the largest power of 2 (<= 64) dividing P that leaves room
  // for the band.
  EXPECT_EQ(PrunedInverse::Decimation(p, 80), 16);
  EXPECT_EQ(PrunedInverse::Decimation(p, 400), 8);
  EXPECT_EQ(PrunedInverse::Decimation(1 << 20, 3), 64);
  EXPECT_EQ(PrunedInverse::Decimation(p, 2521), 1);
  EXPECT_EQ(PrunedInverse::Decimation(p, 2520), 2);
  // The batch: the largest divisor of D whose G M points fit kBatchPoints.
  EXPECT_EQ(PrunedInverse::Batch(p, 16), 16);
  EXPECT_EQ(PrunedInverse::Batch(102400, 16), 2);  // M = 6400: 2 x 6400 <= 16384 < 4 x 6400
  EXPECT_EQ(PrunedInverse::Batch(102400, 2), 1);
  EXPECT_EQ(PrunedInverse::Batch(102400, 1), 1);
}

TEST(PrunedInverse, SplitEqualsTheDirectInverseDft) {
  // Of the band's L1 norm, as at D = 1: FFTW's error at P / 8 points, then
  // the radix-8 step (w^(n l) by at most 3 products, 3 levels of sums, the
  // odd terms by w^(1, 2, 3) of 8): about (log2 P + 6) eps, 1.9e-15 at
  // P = 2048; measured 4e-16. Every entry of the column must be written
  // (NaN before), and none past `times`.
  constexpr double kRelativeTolerance = 3e-15;
  const Eigen::Index p = 2048, m = p / PrunedInverse::kSplitBlocks;
  ASSERT_TRUE(PrunedInverse::Splittable(p));
  EXPECT_FALSE(PrunedInverse::Splittable(2040));
  EXPECT_FALSE(PrunedInverse::Splittable(512));
  PrunedInverse inverse;
  inverse.Reset(p, false);
  const fftw_plan plan = inverse.SplitPlan();
  // Bands: below bin 0 and above, reaching Nyquist and wider than P / 2
  // (the D = 1 scales of a long record), every bin, one bin at either end.
  const std::vector<std::pair<Eigen::Index, Eigen::Index>> bands = {
      {-40, 100}, {7, 60}, {-600, 1625}, {-1023, 2048}, {1024, 1}, {-1023, 5}, {0, 1}, {-9, 9}};
  std::vector<Complex> work(static_cast<std::size_t>(PrunedInverse::WorkSize(p)));
  std::vector<Complex> column(static_cast<std::size_t>(p) + 4);
  for (const auto& [first, bins] : bands) {
    const TestBand t = MakeBand(p, first, bins);
    const std::vector<Complex> direct = DirectInverse(t.band, first, p);
    inverse.ExecuteSplit(t.spectrum.data(), internal::ScaleFilter::Stored(t.filter.data()), first,
                         bins, plan, work.data());
    for (const Eigen::Index times : {p, p - 3, 7 * m + 5, 7 * m - 1, m, Eigen::Index{100}}) {
      std::fill(column.begin(), column.end(), Complex(std::nan(""), 0.0));
      inverse.CombineSplit(work.data(), times, 0.5, column.data());
      double worst = 0.0;
      for (Eigen::Index j = 0; j < times; ++j) {
        worst = std::max(worst, std::abs(column[static_cast<std::size_t>(j)] -
                                         0.5 * direct[static_cast<std::size_t>(j)]));
      }
      EXPECT_LE(worst, 0.5 * kRelativeTolerance * t.l1)
          << "band " << first << "+" << bins << " times " << times;
      for (std::size_t j = static_cast<std::size_t>(times); j < column.size(); ++j) {
        EXPECT_TRUE(std::isnan(column[j].real())) << "written past times: " << j;
      }
    }
  }
}

TEST(PrunedInverse, SplitAtFcwtsLengthEqualsTheDirectSum) {
  // fCWT's case at 10^5 samples: P = 102400, a band from bin -5000 to
  // Nyquist (a D = 1 scale near 30 Hz at 64 Hz), at the ends of the blocks
  // of M = 12800 and between. FFTW's error at 12800 points (14 levels) plus
  // the radix-8 step: 3e-15 of sum |Y_b| (measured 1.7e-17 here: the
  // rounding errors of 57201 bins add up far below the sum of their sizes).
  constexpr double kRelativeTolerance = 3e-15;
  const Eigen::Index p = 102400, m = p / PrunedInverse::kSplitBlocks, first = -5000;
  const Eigen::Index bins = p / 2 - first + 1;
  PrunedInverse inverse;
  inverse.Reset(p, false);
  const TestBand t = MakeBand(p, first, bins);
  std::vector<Complex> work(static_cast<std::size_t>(PrunedInverse::WorkSize(p)));
  std::vector<Complex> column(static_cast<std::size_t>(p));
  inverse.ExecuteSplit(t.spectrum.data(), internal::ScaleFilter::Stored(t.filter.data()), first,
                       bins, inverse.SplitPlan(), work.data());
  inverse.CombineSplit(work.data(), p, 1.0, column.data());
  const std::vector<std::complex<long double>> w = RootsOfUnity(p);
  for (const Eigen::Index j : {Eigen::Index{0}, Eigen::Index{1}, m - 1, m, 3 * m + 77, 7 * m - 1,
                               7 * m, p - 1, Eigen::Index{12345}}) {
    EXPECT_LE(std::abs(column[static_cast<std::size_t>(j)] - DirectInverseAt(t.band, first, j, w)),
              kRelativeTolerance * t.l1)
        << "output " << j;
  }
}

TEST(PrunedInverse, FullRateCwtAtLargeDecimationsEqualsTheDirectSum) {
  // A long record of low frequencies (every scale decimated by up to 64),
  // complex and float-magnitude output, one and three threads, against
  // W_k(t_j) = sum_b X_b n(s) psi^(s w_b) exp(2 pi i b j / P) / P summed
  // directly over the same kept bins (X by a direct DFT). Rounding of FFTs of
  // a few thousand points: 1e-12 of max |W|.
  constexpr double kRelativeTolerance = 1e-12;
  const double step = 1e-3;
  const Eigen::Index n = 3000;
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * step;
    x(i) = std::cos(2 * std::numbers::pi * (5.0 * t + 2.0 * t * t)) + 0.3 * std::sin(1.7 * i);
  }
  CwtOptions o;
  o.remove_mean = false;
  o.frequencies.min_frequency_Hz = 2.0;
  o.frequencies.max_frequency_Hz = 40.0;
  o.frequencies.voices_per_octave = 2;
  CwtTransform transform(o);
  Scalogram sg;
  transform.Compute(x, step, &sg);
  const Eigen::Index p = transform.padded_length();
  // Direct spectrum of the zero-padded record.
  std::vector<Complex> spectrum(static_cast<std::size_t>(p / 2 + 1));
  const std::vector<std::complex<long double>> w = RootsOfUnity(p);
  for (Eigen::Index b = 0; b <= p / 2; ++b) {
    long double re = 0.0L, im = 0.0L;
    for (Eigen::Index m = 0; m < n; ++m) {
      const auto& e = w[static_cast<std::size_t>((p - b * m % p) % p)];  // exp(-2 pi i b m / P)
      re += x(m) * e.real();
      im += x(m) * e.imag();
    }
    spectrum[static_cast<std::size_t>(b)] = Complex(static_cast<double>(re), static_cast<double>(im));
  }
  double lo = 0.0, hi = 0.0;
  o.wavelet.Band(o.band_tolerance, &lo, &hi);
  const double bin_rad_per_s = 2.0 * std::numbers::pi / (static_cast<double>(p) * step);
  Eigen::MatrixXcd direct(n, sg.frequencies());
  for (Eigen::Index k = 0; k < sg.frequencies(); ++k) {
    const double s = sg.scales_s(k);
    const auto a = static_cast<Eigen::Index>(std::ceil(lo / (s * bin_rad_per_s)));
    const auto b = static_cast<Eigen::Index>(std::floor(hi / (s * bin_rad_per_s)));
    std::vector<Complex> band;
    for (Eigen::Index bin = a; bin <= b; ++bin) {
      const Complex value = bin >= 0 ? spectrum[static_cast<std::size_t>(bin)]
                                     : std::conj(spectrum[static_cast<std::size_t>(-bin)]);
      band.push_back(value * o.wavelet.FourierTransform(s * bin * bin_rad_per_s) /
                     static_cast<double>(p));
    }
    // The lowest scales must be decimated by far more than 2 for this test to bite.
    if (k == 0) {
      EXPECT_GE(PrunedInverse::Decimation(p, b - a + 1), 16);
    }
    const std::vector<Complex> y = DirectInverse(band, a, p);
    for (Eigen::Index j = 0; j < n; ++j) direct(j, k) = y[static_cast<std::size_t>(j)];
  }
  const double tolerance = kRelativeTolerance * direct.cwiseAbs().maxCoeff();
  EXPECT_LE((sg.coefficients - direct).cwiseAbs().maxCoeff(), tolerance);
  ExpectSameOnThreadsAndOutputs(x, step, o, sg);
}

TEST(PrunedInverse, LongRecordNearNyquistEqualsTheAnalyticImpulseResponse) {
  // P >= 65536 with bands wider than P / 2 (D = 1): the columns transformed
  // in place with Debian's FFTW's estimated plans (FullRateCwt::kInPlaceLength),
  // split into 8 inverses of P / 8 otherwise (FullRateCwt::kSplitLength). An impulse at m0 has X_b
  // = exp(-2 pi i b m0 / P) exactly, so W_k(j) = sum_b g_k(b) exp(2 pi i b (j - m0) / P) / P (g_k
  // the kept filter bins), summed here in long double at a few times. FFT rounding at ~7e4 points
  // (17 levels): 1e-12 of sum_b |g_k(b)| / P.
  constexpr double kRelativeTolerance = 1e-12;
  const double step = 1e-3;
  const Eigen::Index n = 70000, m0 = 35000;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  x(m0) = 1.0;
  CwtOptions o;
  o.remove_mean = false;
  o.frequencies.min_frequency_Hz = 300.0;
  o.frequencies.max_frequency_Hz = 490.0;
  o.frequencies.voices_per_octave = 4;
  CwtTransform transform(o);
  Scalogram sg;
  transform.Compute(x, step, &sg);
  const Eigen::Index p = transform.padded_length();
  ASSERT_GE(p, 65536);
  double lo = 0.0, hi = 0.0;
  o.wavelet.Band(o.band_tolerance, &lo, &hi);
  const double bin_rad_per_s = 2.0 * std::numbers::pi / (static_cast<double>(p) * step);
  const std::vector<std::complex<long double>> w = RootsOfUnity(p);
  const auto check = [&](const Scalogram& sg, const char* path) {
    for (Eigen::Index k = 0; k < sg.frequencies(); ++k) {
      const double s = sg.scales_s(k);
      const auto a = std::max<Eigen::Index>(
          -((p - 1) / 2), static_cast<Eigen::Index>(std::ceil(lo / (s * bin_rad_per_s))));
      const auto b = std::min<Eigen::Index>(
          p / 2, static_cast<Eigen::Index>(std::floor(hi / (s * bin_rad_per_s))));
      ASSERT_GT(b - a + 1, p / 2) << "scale " << k << " is decimated: the test needs D = 1";
      double l1 = 0.0;
      for (Eigen::Index bin = a; bin <= b; ++bin) {
        l1 +=
            std::abs(o.wavelet.FourierTransform(s * bin * bin_rad_per_s)) / static_cast<double>(p);
      }
      for (Eigen::Index j : {Eigen::Index{0}, Eigen::Index{1}, m0 - 7, m0, m0 + 1, n - 1}) {
        long double re = 0.0L, im = 0.0L;
        for (Eigen::Index bin = a; bin <= b; ++bin) {
          const long double g =
              o.wavelet.FourierTransform(s * bin * bin_rad_per_s) / static_cast<long double>(p);
          const auto& e = w[static_cast<std::size_t>((((bin * (j - m0)) % p) + p) % p)];
          re += g * e.real();
          im += g * e.imag();
        }
        const Complex direct(static_cast<double>(re), static_cast<double>(im));
        EXPECT_LE(std::abs(sg.coefficients(j, k) - direct), kRelativeTolerance * l1)
            << path << ": scale " << k << " time " << j;
      }
    }
  };
  check(sg, "as planned");
  // Three threads (a chunk per scale: each column ends its chunk and is
  // transformed in place in the thread's buffer, then copied), |W| and W as
  // float (the same in-place transform): the same numbers.
  ExpectSameOnThreadsAndOutputs(x, step, o, sg);
  // P = 73728 splits (FullRateCwt::kSplitLength): with Debian's FFTW once
  // the inverse of P / 8 is measured (in this binary's private cache), with
  // scripts/build-fftw.sh's FFTW always. The same reference, then the same
  // numbers on three threads and as |W| and complex float.
  ASSERT_TRUE(internal::FullRateCwt::MaySplit(p));
  FftLengths split;
  split.interleaved_backward = {{static_cast<int>(p / internal::PrunedInverse::kSplitBlocks), 1}};
  MeasureFftPlans(split);
  const Scalogram measured = Cwt(x, step, o);
  check(measured, "split");
  ExpectSameOnThreadsAndOutputs(x, step, o, measured);
}

}  // namespace
}  // namespace podid::wavelet
