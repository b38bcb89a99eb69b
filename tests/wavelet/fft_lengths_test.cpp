// The FFT length choices of wavelet/src/fftw_plans.hpp (FastFftLength for a
// whole record, FastBlockLength for a block whose overlaps are thrown away)
// against a brute-force search over every integer of the allowed range.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "../../wavelet/src/fftw_plans.hpp"

namespace podid::wavelet {
namespace {

bool SevenSmooth(long long m) {
  for (long long p : {2, 3, 5, 7}) {
    while (m % p == 0) m /= p;
  }
  return m == 1;
}

// The smooth m in [n, max(n + 8, ceil(1.25 n))], m <= cap, of least cost(m)
// (ties: the shortest), by trial division of every integer.
template <class Cost>
long long BruteForce(long long n, long long cap, const Cost& cost) {
  const long long limit = std::min(cap, std::max(n + 8, (5 * n + 3) / 4));
  long long best = -1;
  double best_cost = std::numeric_limits<double>::infinity();
  for (long long m = n; m <= limit; ++m) {
    if (!SevenSmooth(m)) continue;
    const double c = cost(m);
    if (c < best_cost) {
      best_cost = c;
      best = m;
    }
  }
  return best;
}

TEST(FftLengths, WholeRecordTakesTheLeastModelledCost) {
  for (long long n = 1; n <= 5000; n += 7) {
    const long long expected =
        BruteForce(n, std::numeric_limits<long long>::max(),
                   [](long long m) { return internal::FftCostModel(m) * static_cast<double>(m); });
    ASSERT_EQ(internal::FastFftLength(n), expected) << "n = " << n;
  }
}

TEST(FftLengths, BlockTakesTheLeastCostPerKeptPointUpTo2048) {
  for (long long n = 2; n <= 3000; n += 11) {
    for (long long overlap : {0LL, n / 8, n / 4, n / 2, n - 1}) {
      const long long got = internal::FastBlockLength(n, overlap);
      if (n > 2048) {
        ASSERT_EQ(got, internal::FastFftLength(n)) << "n = " << n;
        continue;
      }
      const long long expected = BruteForce(n, 2048, [overlap](long long m) {
        return internal::FftCostModel(m) * static_cast<double>(m) /
               static_cast<double>(m - overlap);
      });
      ASSERT_EQ(got, expected) << "n = " << n << ", overlap = " << overlap;
    }
  }
}

// The Silverbox objective's ridge blocks (10-120 Hz every 2nd sample of
// 610.35 Hz, overlaps of 2 x 218 output times): 2048 points keep 1612 times
// where FastFftLength's 1792 keep 1356.
TEST(FftLengths, SilverboxRidgeBlocksArePowersOfTwo) {
  EXPECT_EQ(internal::FastFftLength(1744), 1792);
  EXPECT_EQ(internal::FastBlockLength(1744, 436), 2048);
  // 10-300 Hz at every sample (overlaps of 2 x 435): beyond 2048 points,
  // FastFftLength's choice.
  EXPECT_EQ(internal::FastBlockLength(3480, 870), internal::FastFftLength(3480));
}

}  // namespace
}  // namespace podid::wavelet
