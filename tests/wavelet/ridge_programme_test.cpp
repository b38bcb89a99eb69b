// The ridge's dynamic programme (internal RidgeProgramme: the lower envelope
// of parabolas per column, Felzenszwalb & Huttenlocher) against an
// independent O(n_freq^2) minimisation over every predecessor.
#include "../../wavelet/src/ridge_programme.hpp"  // internal: the dynamic programme

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "../../wavelet/src/ridge_cost.hpp"  // internal: RidgeCostOfPower
#include "podid/wavelet/cwt.hpp"             // FrequencyGrid

namespace podid::wavelet {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Column-major cost (freqs x times); the same rules as RidgeProgramme:
// total(q) = cost(q) + min_p prev(p) + lambda (x_q - x_p)^2, the smallest p
// among equal minima; a column after one with no finite total starts afresh
// (back-pointer -1); the path ends at the smallest argmin of the last column.
Eigen::VectorXi BruteForcePath(const Eigen::VectorXd& x, double lambda, const Eigen::MatrixXd& cost) {
  const Eigen::Index freqs = cost.rows(), times = cost.cols();
  Eigen::MatrixXi back = Eigen::MatrixXi::Constant(freqs, times, -1);
  std::vector<int> best(static_cast<std::size_t>(times), -1);
  Eigen::VectorXd prev(freqs), next(freqs);
  for (Eigen::Index j = 0; j < times; ++j) {
    if (j == 0 || best[static_cast<std::size_t>(j - 1)] < 0) {
      next = cost.col(j);
    } else {
      for (Eigen::Index q = 0; q < freqs; ++q) {
        double low = kInf;
        int arg = -1;
        for (Eigen::Index p = 0; p < freqs; ++p) {
          const double dx = x(q) - x(p);
          const double value = prev(p) + lambda * dx * dx;
          if (value < low) {
            low = value;
            arg = static_cast<int>(p);
          }
        }
        next(q) = cost(q, j) + low;
        back(q, j) = arg;
      }
    }
    prev = next;
    double low = kInf;
    for (Eigen::Index q = 0; q < freqs; ++q) {
      if (prev(q) < low) {
        low = prev(q);
        best[static_cast<std::size_t>(j)] = static_cast<int>(q);
      }
    }
  }
  Eigen::VectorXi path(times);
  int k = best[static_cast<std::size_t>(times - 1)];
  for (Eigen::Index j = times - 1; j >= 0; --j) {
    path(j) = k;
    if (j > 0) k = k >= 0 ? back(k, j) : best[static_cast<std::size_t>(j - 1)];
  }
  return path;
}

Eigen::VectorXi ProgrammePath(const Eigen::VectorXd& x, double lambda, const Eigen::MatrixXd& cost) {
  internal::RidgeProgramme programme(x, lambda, false);
  programme.Reset(cost.cols());
  for (Eigen::Index j = 0; j < cost.cols(); ++j) programme.Push(cost.col(j).data());
  return programme.Path();
}

// The same through PushLast: the first `pushed` columns one by one, the rest
// at once, read frequency-major (strides 1, freqs) or time-major (a transposed
// copy: strides times, 1), as the streamed ridge's two callers lay them out.
// With `powers`, `data` holds |W|^2 (freqs x times): the first columns get
// RidgeCostOfPower's costs, the rest go to PushLastPowers.
Eigen::VectorXi PushLastPath(const Eigen::VectorXd& x,
                             double lambda,
                             const Eigen::MatrixXd& data,
                             Eigen::Index pushed,
                             bool time_major,
                             Eigen::Index* cells = nullptr,
                             bool powers = false,
                             bool maximum = false) {
  internal::RidgeProgramme programme(x, lambda, maximum);
  programme.Reset(data.cols());
  Eigen::VectorXd cost(data.rows());
  for (Eigen::Index j = 0; j < pushed; ++j) {
    cost = data.col(j);
    if (powers) internal::RidgeCostOfPower(cost.data(), cost.size(), cost.data());
    programme.Push(cost.data());
  }
  const auto last = [&](const double* from, Eigen::Index count, Eigen::Index freq_stride,
                        Eigen::Index time_stride) {
    if (powers) {
      programme.PushLastPowers(from, count, freq_stride, time_stride);
    } else {
      programme.PushLast(from, count, freq_stride, time_stride);
    }
  };
  const Eigen::Index rest = data.cols() - pushed;
  if (time_major) {
    const Eigen::MatrixXd by_time = data.rightCols(rest).transpose();
    last(by_time.data(), rest, by_time.rows(), 1);
  } else {
    last(data.col(pushed).data(), rest, 1, data.rows());
  }
  if (cells != nullptr) *cells = programme.last_cells();
  return programme.Path();
}

// A ridge's cost, freqs x times: cost(k, j) = scale ((k - c_j) / width)^2 +
// slope j + noise U(0, 1), each cell forbidden (+inf) with probability
// `forbidden`; the centre c starts at start * freqs and moves by up to
// +-drift / 2 bins a column.
struct Ridge {
  double start, drift, width, scale, slope, noise, forbidden;
};
Eigen::MatrixXd DriftingRidge(std::mt19937& rng,
                              Eigen::Index freqs,
                              Eigen::Index times,
                              const Ridge& ridge) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Eigen::MatrixXd cost(freqs, times);
  double centre = ridge.start * static_cast<double>(freqs);
  for (Eigen::Index j = 0; j < times; ++j) {
    centre = std::clamp(centre + ridge.drift * (uniform(rng) - 0.5), 0.0,
                        static_cast<double>(freqs - 1));
    for (Eigen::Index k = 0; k < freqs; ++k) {
      const double d = (static_cast<double>(k) - centre) / ridge.width;
      cost(k, j) =
          ridge.scale * d * d + ridge.slope * static_cast<double>(j) + ridge.noise * uniform(rng);
      if (ridge.forbidden > 0.0 && uniform(rng) < ridge.forbidden) cost(k, j) = kInf;
    }
  }
  return cost;
}

// ln f of `freqs` log-spaced frequencies from `lowest_Hz`, `voices` an octave.
Eigen::VectorXd LogFrequencies(Eigen::Index freqs, int voices, double lowest_Hz) {
  return (Eigen::VectorXd::LinSpaced(freqs, 0.0, static_cast<double>(freqs - 1)) *
          (std::log(2.0) / voices))
             .array() +
         std::log(lowest_Hz);
}

// The path's objective, sum cost + lambda sum dx^2, restarting at -1.
double PathTotal(const Eigen::VectorXd& x, double lambda, const Eigen::MatrixXd& cost, const Eigen::VectorXi& path) {
  double total = 0.0;
  for (Eigen::Index j = 0; j < cost.cols(); ++j) {
    if (path(j) < 0) continue;
    total += cost(path(j), j);
    if (j > 0 && path(j - 1) >= 0) {
      const double dx = x(path(j)) - x(path(j - 1));
      total += lambda * dx * dx;
    }
  }
  return total;
}

// Exact costs (integers, lambda a power of 2): Push's path and PushLast's
// (bounded, after a random number of pushed columns, frequency-major on even
// trials, else time-major: bounds prune no optimal cell, and exact sums keep
// every tie as Push breaks it) both equal BruteForcePath's.
::testing::AssertionResult SamePathsAsTheBruteForce(const Eigen::VectorXd& x,
                                                    double lambda,
                                                    const Eigen::MatrixXd& cost,
                                                    int trial,
                                                    std::mt19937& rng) {
  const Eigen::Index freqs = cost.rows(), times = cost.cols();
  const Eigen::VectorXi expected = BruteForcePath(x, lambda, cost);
  if (ProgrammePath(x, lambda, cost) != expected) {
    return ::testing::AssertionFailure() << "trial " << trial << ", " << freqs << " frequencies, "
                                         << times << " times, lambda " << lambda << ": Push";
  }
  const Eigen::Index pushed = static_cast<Eigen::Index>(rng() % static_cast<unsigned>(times));
  if (PushLastPath(x, lambda, cost, pushed, trial % 2 == 0) != expected) {
    return ::testing::AssertionFailure()
           << "trial " << trial << ", PushLast after " << pushed << " of " << times << " columns";
  }
  return ::testing::AssertionSuccess();
}

TEST(RidgeProgramme, EqualsEveryPredecessorMinimisationExactlyWithTiesAndForbiddenCells) {
  // Integer positions, lambda a power of 2 and small integer costs: every
  // sum and product is exact, so the envelope's intersections decide exactly
  // as the brute force's comparisons, ties (frequent here) included: the
  // paths must be identical. Forbidden (+inf) cells, whole forbidden columns
  // (restarts) and 1- and 2-byte back-pointers (300 frequencies).
  std::mt19937 rng(11);
  for (int trial = 0; trial < 300; ++trial) {
    const Eigen::Index freqs = trial % 10 == 0 ? 300 : 1 + static_cast<Eigen::Index>(rng() % 40);
    const Eigen::Index times = 1 + static_cast<Eigen::Index>(rng() % 30);
    Eigen::VectorXd x(freqs);
    double position = static_cast<double>(rng() % 5) - 2.0;
    for (Eigen::Index k = 0; k < freqs; ++k) {
      x(k) = position;
      position += 1.0 + static_cast<double>(rng() % (trial % 2 == 0 ? 1 : 3));  // uniform or not
    }
    const double lambda = std::ldexp(1.0, static_cast<int>(rng() % 7) - 4);  // 1/16 .. 4
    Eigen::MatrixXd cost(freqs, times);
    const unsigned levels = 1 + rng() % 12;  // few levels: many ties
    const unsigned forbidden = rng() % 4;    // 0, 1/8, 1/4, 3/8 of the cells
    for (Eigen::Index j = 0; j < times; ++j) {
      const bool dead = rng() % 15 == 0;
      for (Eigen::Index k = 0; k < freqs; ++k) {
        cost(k, j) = dead || rng() % 8 < forbidden ? kInf : static_cast<double>(rng() % levels);
      }
    }
    ASSERT_TRUE(SamePathsAsTheBruteForce(x, lambda, cost, trial, rng));
  }
}

TEST(RidgeProgramme, EqualsTheBruteForceExactlyOnANearlyUniformGrid) {
  // The programme finds each q's parabola from guesses on a grid within two
  // bins of uniform (log-spaced frequencies) and corrects them by exact tests;
  // here the grid is uniform only to within a quarter of a bin (x_k = 4 k +
  // -1, 0 or 1), so guesses are often off by one and every correction runs.
  // Integers and lambda a power of 2, as above: exact sums, identical paths.
  std::mt19937 rng(29);
  for (int trial = 0; trial < 300; ++trial) {
    const Eigen::Index freqs = trial % 10 == 0 ? 300 : 2 + static_cast<Eigen::Index>(rng() % 60);
    const Eigen::Index times = 1 + static_cast<Eigen::Index>(rng() % 30);
    Eigen::VectorXd x(freqs);
    for (Eigen::Index k = 0; k < freqs; ++k)
      x(k) = 4.0 * static_cast<double>(k) + static_cast<double>(rng() % 3) - 1.0;
    const double lambda = std::ldexp(1.0, static_cast<int>(rng() % 7) - 6);  // 1/64 .. 1
    Eigen::MatrixXd cost(freqs, times);
    const unsigned levels = 1 + rng() % 40;
    const unsigned forbidden = rng() % 3;  // 0, 1/8, 1/4 of the cells
    for (Eigen::Index j = 0; j < times; ++j) {
      for (Eigen::Index k = 0; k < freqs; ++k)
        cost(k, j) = rng() % 8 < forbidden ? kInf : static_cast<double>(rng() % levels);
    }
    ASSERT_TRUE(SamePathsAsTheBruteForce(x, lambda, cost, trial, rng));
  }
}

TEST(RidgeProgramme, HugePenaltiesGiveTheFlattestPath) {
  // Once the cheapest jump, lambda dx^2, exceeds what any path can gain
  // from all its columns (times x the range of a column's costs), the
  // optimum is the constant path k* = argmin_k sum_j cost(k, j), found here
  // by summing the costs. The envelope cross-multiplied intersections of
  // size lambda x^2 by 2 lambda dx: from lambda ~ 1e154 they overflowed and
  // the path left the grid or wandered (podid cwt --penalty 1e152 at 5 kHz).
  // Up to the largest accepted lambda, kMaxRidgeJumpCost / (2 max |x|)^2,
  // on the log grid of podid cwt's default (10-120 Hz, 32 voices), through
  // Push, PushLast and PushLastPowers (costs of powers in (1e-3, 1]).
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const Eigen::VectorXd f = FrequencyGrid::Log(10.0, 120.0, 32).Frequencies_Hz();
  const Eigen::VectorXd x = f.array().log();
  const Eigen::Index freqs = x.size(), times = 3000;
  const double reach = 2.0 * x.cwiseAbs().maxCoeff();
  const double largest = internal::kMaxRidgeJumpCost / (reach * reach) * (1.0 - 1e-15);
  Eigen::MatrixXd power(freqs, times);
  for (Eigen::Index j = 0; j < times; ++j) {
    // A drifting ridge (where a small penalty would follow it) over a floor.
    const double centre = 10.0 + 90.0 * static_cast<double>(j) / static_cast<double>(times);
    for (Eigen::Index k = 0; k < freqs; ++k) {
      const double d = (static_cast<double>(k) - centre) / 4.0;
      power(k, j) = std::max(1e-3, std::exp(-d * d) * (0.5 + 0.5 * uniform(rng)));
    }
  }
  Eigen::MatrixXd cost = power;
  for (Eigen::Index j = 0; j < times; ++j)
    internal::RidgeCostOfPower(cost.col(j).data(), freqs, cost.col(j).data());
  Eigen::Index flattest = 0;
  cost.rowwise().sum().minCoeff(&flattest);
  // The flattest path is optimal: one jump costs more than the costs' whole range.
  const double min_dx = (x.tail(freqs - 1) - x.head(freqs - 1)).minCoeff();
  const double range = cost.maxCoeff() - cost.minCoeff();
  const Eigen::VectorXi want = Eigen::VectorXi::Constant(times, static_cast<int>(flattest));
  for (double lambda : {1e150, 5e155, 1e200, largest}) {
    ASSERT_GT(lambda * min_dx * min_dx, static_cast<double>(times) * range);
    ASSERT_LE(lambda * reach * reach, internal::kMaxRidgeJumpCost);
    EXPECT_EQ(ProgrammePath(x, lambda, cost), want) << "lambda " << lambda;
    EXPECT_EQ(PushLastPath(x, lambda, cost, 1, false), want) << "lambda " << lambda;
    EXPECT_EQ(PushLastPath(x, lambda, cost, 1, true), want) << "lambda " << lambda;
    EXPECT_EQ(PushLastPath(x, lambda, power, 1, false, nullptr, true), want) << "lambda " << lambda;
  }
  // And a small penalty follows the drifting ridge (the costs are not flat).
  const Eigen::VectorXi small = ProgrammePath(x, 1.0, cost);
  EXPECT_GT(small.maxCoeff() - small.minCoeff(), 60);
}

TEST(RidgeProgramme, PushLastGivesPushsPathOnClearAndNoisyRidges) {
  // Real costs as the ridge has them: -log|W| of a drifting Gaussian ridge
  // (clear: the bounds skip most cells) plus noise of growing amplitude
  // (noisy: weak bounds, most cells computed), in both layouts. The
  // optimal cells and their totals are Push's own, so the paths are
  // identical, not merely of equal total.
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int trial = 0; trial < 60; ++trial) {
    const Eigen::Index freqs = 30 + static_cast<Eigen::Index>(rng() % 130);
    const Eigen::Index times = 50 + static_cast<Eigen::Index>(rng() % 300);
    const Eigen::VectorXd x = LogFrequencies(freqs, 24, 5.0);
    const double lambda = 1.0 + 30.0 * uniform(rng);
    const double noise = trial % 3 == 0 ? 0.0 : trial % 3 == 1 ? 0.05 : 3.0;
    const Eigen::MatrixXd cost =
        DriftingRidge(rng, freqs, times, {1.0 / 3.0, 0.3, 6.0, 0.5, 0.002, noise, 0.0});
    const Eigen::VectorXi expected = ProgrammePath(x, lambda, cost);
    for (const bool time_major : {false, true}) {
      Eigen::Index cells = 0;
      ASSERT_EQ(PushLastPath(x, lambda, cost, 0, time_major, &cells), expected)
          << "trial " << trial << ", noise " << noise << (time_major ? ", time-major" : "");
      // A clear ridge keeps its bounds (2-45 % of the cells computed here;
      // a bound short of the optimum would empty a column and fall back to all).
      if (noise == 0.0) {
        EXPECT_LT(cells, freqs * times / 2) << "trial " << trial;
      }
    }
    EXPECT_EQ(PushLastPath(x, lambda, cost, times / 2, false), expected) << "trial " << trial;
  }
}

TEST(RidgeProgramme, PushLastPowersGivesPushsPathOnTheSameCosts) {
  // PushLastPowers computes -log|W| = RidgeCostOfPower(|W|^2) only where its
  // bounds need it; Push gets every cell's, computed the same way, so the
  // paths must be identical. Clear ridges (few cells computed), noisy ones,
  // and flat ones whose powers differ by a few ulp: there RidgeCostOfPower,
  // not monotone to the last bit, may cost a larger power more, which the
  // column minima's allowance must cover. lambda = 0 and the maximum method
  // take no bounds (every column's costs computed).
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int trial = 0; trial < 90; ++trial) {
    const Eigen::Index freqs = 30 + static_cast<Eigen::Index>(rng() % 130);
    const Eigen::Index times = 50 + static_cast<Eigen::Index>(rng() % 300);
    const Eigen::VectorXd x = LogFrequencies(freqs, 32, 10.0);
    const int kind = trial % 6;  // 0 clear, 1 noisy, 2 very noisy, 3 flat, 4 lambda 0, 5 maximum
    const double lambda = kind == 4 ? 0.0 : 1.0 + 30.0 * uniform(rng);
    Eigen::MatrixXd power(freqs, times);
    if (kind == 3) {
      // 1 + m ulp, m in 0..7, and a faint ridge a few ulp above the rest.
      const Eigen::Index centre = static_cast<Eigen::Index>(rng() % static_cast<unsigned>(freqs));
      for (Eigen::Index j = 0; j < times; ++j)
        for (Eigen::Index k = 0; k < freqs; ++k)
          power(k, j) = 1.0 + static_cast<double>(rng() % 8 + (k == centre ? 6 : 0)) *
                                  std::numeric_limits<double>::epsilon();
    } else {
      const double noise = kind == 1 ? 0.05 : kind == 2 ? 3.0 : 0.0;
      const Eigen::MatrixXd cost =
          DriftingRidge(rng, freqs, times, {1.0 / 3.0, 0.3, 6.0, 0.5, 0.002, noise, 0.0});
      power = (-2.0 * cost.array()).exp().matrix();  // cost = -0.5 ln(power)
    }
    Eigen::MatrixXd cost(freqs, times);
    for (Eigen::Index j = 0; j < times; ++j)
      internal::RidgeCostOfPower(power.col(j).data(), freqs, cost.col(j).data());
    internal::RidgeProgramme reference(x, lambda, kind == 5);
    reference.Reset(times);
    for (Eigen::Index j = 0; j < times; ++j) reference.Push(cost.col(j).data());
    const Eigen::VectorXi expected = reference.Path();
    for (const bool time_major : {false, true}) {
      Eigen::Index cells = 0;
      ASSERT_EQ(PushLastPath(x, lambda, power, 0, time_major, &cells, true, kind == 5), expected)
          << "trial " << trial << ", kind " << kind << (time_major ? ", time-major" : "");
      if (kind == 0) {
        EXPECT_LT(cells, freqs * times / 2) << "trial " << trial;
      }
    }
    EXPECT_EQ(PushLastPath(x, lambda, power, times / 2, false, nullptr, true, kind == 5), expected)
        << "trial " << trial << ", kind " << kind;
  }
}

TEST(RidgeProgramme, ReachesTheBruteForceOptimumOnRandomRealCosts) {
  // Log-spaced frequencies and real costs as the ridge has them: the path's
  // objective equals the optimum within rounding (kRelative: the totals are
  // sums of a few hundred terms of order 1-10, each rounded to 1e-16
  // relative; near-ties may pick another path of the same total).
  constexpr double kRelative = 1e-12;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int trial = 0; trial < 40; ++trial) {
    const Eigen::Index freqs = 20 + static_cast<Eigen::Index>(rng() % 140), times = 200;
    const Eigen::VectorXd x = LogFrequencies(freqs, 32, 10.0);
    const double lambda = 5.0 + 30.0 * uniform(rng);
    const Eigen::MatrixXd cost =
        DriftingRidge(rng, freqs, times, {0.5, 2.0, 8.0, 1.0, 0.0, 3.0, 0.02});
    const double optimum = PathTotal(x, lambda, cost, BruteForcePath(x, lambda, cost));
    const double total = PathTotal(x, lambda, cost, ProgrammePath(x, lambda, cost));
    const double last = PathTotal(x, lambda, cost, PushLastPath(x, lambda, cost, 0, false));
    ASSERT_TRUE(std::isfinite(optimum));
    EXPECT_NEAR(total, optimum, kRelative * optimum) << "trial " << trial;
    EXPECT_NEAR(last, optimum, kRelative * optimum) << "trial " << trial << ", PushLast";
  }
}

}  // namespace
}  // namespace podid::wavelet
