// Conditioning (podid/core/conditioning.hpp) against scipy.signal: the script
// tests/data/conditioning/make_reference.py writes a fixed two-channel signal
// and scipy's butter + sosfiltfilt, detrend and decimate outputs; podid must
// reproduce them.
#include "podid/core/conditioning.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <limits>
#include <numbers>

#include "podid/core/io.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

using podid::testing::DataPath;
using podid::testing::ExpectMatricesNear;
using podid::testing::TempDir;

// Both sides compute the same filter in double precision with different
// pairings of poles into sections and different summation orders; the input
// is O(1) and the filters are stable with poles at |z| <= 0.99 (band-pass 16:
// the worst), so rounding stays far below 1e-9. Printed with 17 digits.
constexpr double kScipyTolerance = 1e-9;

class ConditioningScipyTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    const std::string python =
        std::system("python3 -c 'import scipy' 2>/dev/null") == 0 ? "python3" : "/usr/bin/python3";
    const std::string command =
        python + " " + DataPath("conditioning/make_reference.py") + " " + dir_->path();
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static TimeSeries Read(const std::string& name) { return ReadCsv(dir_->File(name + ".csv")); }
  static void ExpectLike(const ConditioningOptions& options, const std::string& name) {
    const TimeSeries input = Read("input");
    const TimeSeries got = ConditionRecord(input, options, "input.csv");
    const TimeSeries want = Read(name);
    EXPECT_EQ(got.channel_names, want.channel_names) << name;
    EXPECT_TRUE(ExpectMatricesNear(got.time_s, want.time_s, 1e-12)) << name;
    EXPECT_TRUE(ExpectMatricesNear(got.values, want.values, kScipyTolerance)) << name;
  }
  static TempDir* dir_;
};
TempDir* ConditioningScipyTest::dir_ = nullptr;

ConditioningOptions Filter(FilterType type, int order, double low_Hz, double high_Hz) {
  ConditioningOptions o;
  o.filter = {type, order, low_Hz, high_Hz};
  return o;
}

TEST_F(ConditioningScipyTest, LowpassOrder4) {
  ExpectLike(Filter(FilterType::kLowpass, 4, 0.0, 40.0), "lowpass4_40");
}
TEST_F(ConditioningScipyTest, HighpassOddOrder) {
  ExpectLike(Filter(FilterType::kHighpass, 3, 15.0, 0.0), "highpass3_15");
}
TEST_F(ConditioningScipyTest, Bandpass) {
  ExpectLike(Filter(FilterType::kBandpass, 4, 20.0, 100.0), "bandpass4_20_100");
}
TEST_F(ConditioningScipyTest, BandpassHighestOrder) {
  ExpectLike(Filter(FilterType::kBandpass, kMaxFilterOrder, 40.0, 90.0), "bandpass16_40_90");
}
TEST_F(ConditioningScipyTest, Detrend) {
  ConditioningOptions o;
  o.detrend = Detrend::kLinear;
  ExpectLike(o, "detrend_linear");
  o.detrend = Detrend::kConstant;
  ExpectLike(o, "detrend_constant");
}
TEST_F(ConditioningScipyTest, Decimate) {
  ConditioningOptions o;
  o.decimate = 4;
  ExpectLike(o, "decimate4");
}
TEST_F(ConditioningScipyTest, WholeChain) {
  ConditioningOptions o = Filter(FilterType::kBandpass, 4, 5.0, 100.0);
  o.channels = {"b", "a"};
  o.window_start_s = 0.2;
  o.window_end_s = 1.7;
  o.detrend = Detrend::kLinear;
  o.decimate = 2;
  ExpectLike(o, "chain");
}

// The zero-phase gain is |H|^2: a tone at the cutoff of a low-pass comes out at
// 1/2 (-6 dB) in the middle of a long record, with no phase shift.
TEST(ConditioningTest, ZeroPhaseGainAtCutoff) {
  constexpr double kRate_Hz = 1000.0, kTone_Hz = 50.0;
  // Steady state away from the edges; the residual transient of the order-4
  // filter has decayed to well below 1e-6 after 0.5 s.
  constexpr double kSteadyTolerance = 1e-6;
  TimeSeries s;
  const int n = 4000;
  s.time_s = Eigen::VectorXd::LinSpaced(n, 0.0, (n - 1) / kRate_Hz);
  s.values = (2 * std::numbers::pi * kTone_Hz * s.time_s.array()).sin().matrix();
  s.channel_names = {"x"};
  const TimeSeries y = ConditionRecord(s, Filter(FilterType::kLowpass, 4, 0.0, kTone_Hz), "tone");
  const Eigen::VectorXd middle = y.values.col(0).segment(1000, 2000);
  EXPECT_TRUE(ExpectMatricesNear(middle, (0.5 * s.values.col(0).segment(1000, 2000)).eval(),
                                 kSteadyTolerance));
}

// The passband the ridge checks read: between the cutoffs, an open side where
// the filter has no edge; and its wording in their messages.
TEST(ConditioningTest, PassbandOfEachFilterType) {
  const double inf = std::numeric_limits<double>::infinity();
  struct Case {
    FilterType type;
    double low_Hz, high_Hz, pass_low_Hz, pass_high_Hz;
    const char* text;
  };
  for (const Case& c : {Case{FilterType::kNone, 0, 0, 0, inf, "all frequencies"},
                        Case{FilterType::kLowpass, 0, 50, 0, 50, "below 50 Hz"},
                        Case{FilterType::kHighpass, 5, 0, 5, inf, "above 5 Hz"},
                        Case{FilterType::kBandpass, 5, 80, 5, 80, "5..80 Hz"}}) {
    const FilterOptions f = Filter(c.type, 4, c.low_Hz, c.high_Hz).filter;
    EXPECT_EQ(f.PassbandLow_Hz(), c.pass_low_Hz) << c.text;
    EXPECT_EQ(f.PassbandHigh_Hz(), c.pass_high_Hz) << c.text;
    EXPECT_EQ(f.DescribePassband(), c.text);
  }
}

TEST(ConditioningTest, IdentityKeepsTheRecord) {
  TimeSeries s;
  s.time_s = Eigen::VectorXd::LinSpaced(5, 0.25, 0.29);
  s.values = Eigen::MatrixXd::Random(5, 2);
  s.channel_names = {"a", "b"};
  const TimeSeries y = ConditionRecord(s, {}, "r");
  EXPECT_EQ(y.values, s.values);
  EXPECT_EQ(y.time_s, s.time_s);
}

/// What ConditionRecord(s, o, "rec.csv") throws, or "no exception".
std::string Message(const TimeSeries& s, const ConditioningOptions& o) {
  try {
    (void)ConditionRecord(s, o, "rec.csv");
  } catch (const std::invalid_argument& e) {
    return std::string(e.what());
  }
  return std::string("no exception");
}

TEST(ConditioningTest, RejectsBadOptionsWithTheirNames) {
  TimeSeries s;
  s.time_s = Eigen::VectorXd::LinSpaced(100, 0.0, 0.099);  // 1 kHz
  s.values = Eigen::MatrixXd::Random(100, 1);
  s.channel_names = {"a"};
  auto message = [&](const ConditioningOptions& o) { return Message(s, o); };
  EXPECT_EQ(message(Filter(FilterType::kLowpass, 4, 0.0, 500.0)),
            "rec.csv: filter cutoff: expected a cutoff in (0, 500) Hz (the Nyquist frequency), got "
            "500 Hz");
  EXPECT_EQ(message(Filter(FilterType::kLowpass, 17, 0.0, 50.0)),
            "rec.csv: conditioning: filter order: expected an integer in [1, 16], got 17");
  EXPECT_EQ(message(Filter(FilterType::kBandpass, 2, 80.0, 50.0)),
            "rec.csv: conditioning: filter cutoffs: expected low < high, got 80 and 50 Hz");
  ConditioningOptions o;
  o.decimate = 1001;
  EXPECT_EQ(message(o),
            "rec.csv: conditioning: decimate: expected an integer in [1, 1000], got 1001");
  o = {};
  o.channels = {"z"};
  EXPECT_EQ(message(o), "rec.csv: channel: expected one of a, got \"z\"");
  o = {};
  o.window_start_s = 0.5;
  o.window_end_s = 0.6;
  EXPECT_EQ(message(o),
            "rec.csv: window: expected at least 4 samples of the record (0 .. 0.099 s), got 0 "
            "samples in 0.5 .. 0.6 s");
  o = Filter(FilterType::kBandpass, 16, 25.0, 50.0);  // 99 samples of padding
  o.window_start_s = 0.0;
  o.window_end_s = 0.05;
  EXPECT_EQ(message(o),
            "rec.csv: filter: expected a record of more than 99 samples (the filter's padding), "
            "got 51 samples");
}

/// `n` samples at `rate_Hz` of `value(t)`, one channel.
template <typename F>
TimeSeries Record(double rate_Hz, int n, F value) {
  TimeSeries s;
  s.time_s = Eigen::VectorXd::LinSpaced(n, 0.0, (n - 1) / rate_Hz);
  s.values = s.time_s.unaryExpr(value);
  s.channel_names = {"x"};
  return s;
}

TEST(ConditioningTest, CutoffsWithinAFractionOfZeroOrNyquistAreRefused) {
  // At 1 kHz the cutoffs lie in [1e-5, 1 - 1e-5] x 500 Hz. 1e-9 of Nyquist
  // filtered to NaN (orders 2-8).
  const TimeSeries s = Record(1000.0, 200, [](double t) { return t; });
  auto message = [&](const ConditioningOptions& o) { return Message(s, o); };
  EXPECT_EQ(message(Filter(FilterType::kLowpass, 4, 0.0, 5e-6)),
            "rec.csv: filter cutoff: expected a cutoff in [0.005, 499.995] Hz (1e-05 of the "
            "Nyquist frequency from 0 and from it: closer, the filter loses its accuracy in double "
            "precision), got 5e-06 Hz");
  EXPECT_NE(message(Filter(FilterType::kHighpass, 2, 0.0049, 0.0)).find("got 0.0049 Hz"),
            std::string::npos);
  EXPECT_NE(message(Filter(FilterType::kBandpass, 2, 10.0, 499.999))
                .find("filter high cutoff: expected a cutoff in [0.005, 499.995] Hz"),
            std::string::npos);
}

TEST(ConditioningTest, CutoffsBelowOneOverTheDurationAreRefused) {
  // A 0.2 s record at 1 kHz: below 5 Hz the filter's response outlasts it.
  // A low-pass at 0.005 Hz on a noisy 2 s record gave a constant 3.125 for
  // data in 2.9..3.1 (the padding's odd extension of the first samples).
  const TimeSeries s = Record(1000.0, 201, [](double t) { return t; });
  EXPECT_EQ(Message(s, Filter(FilterType::kLowpass, 4, 0.0, 4.0)),
            "rec.csv: filter cutoff: expected a cutoff >= 1 / duration = 5 Hz (below, the "
            "filter's response outlasts the record and its output is set by the padding at the "
            "edges), got 4 Hz");
  EXPECT_NE(Message(s, Filter(FilterType::kBandpass, 2, 1.0, 100.0))
                .find("rec.csv: filter low cutoff: expected a cutoff >= 1 / duration = 5 Hz"),
            std::string::npos);
  EXPECT_EQ(Message(s, Filter(FilterType::kHighpass, 2, 5.0, 0.0)), "no exception");
}

TEST(ConditioningTest, TheExtremeCutoffsKeepTheirGains) {
  // At the lowest cutoff a low-pass keeps a constant (its DC gain, measured
  // up to 3.5e-7 off at Wn = 1e-5, orders 1-16: the tolerance is ~3 times
  // that; scipy's sections 1e-7) and a high-pass
  // removes it (its zeros at z = 1 are exact); at the highest, a low-pass
  // keeps it too. (A tone there is not a test of accuracy: a filter that
  // close to Nyquist rings for ~1 / (pi 1e-5) samples after the padding,
  // 4e-5 of the tone in a 4000-sample record, scipy alike.)
  constexpr double kGainTolerance = 1e-6;
  constexpr double kRate_Hz = 1000.0, kNyquist_Hz = 500.0;
  const double lowest = kMinFilterCutoffFraction * kNyquist_Hz;
  const double highest = (1.0 - kMinFilterCutoffFraction) * kNyquist_Hz;
  // 200 s: the lowest cutoff, 0.005 Hz, is 1 / duration.
  const TimeSeries constant = Record(kRate_Hz, 200001, [](double) { return 3.0; });
  for (const int order : {1, 2, 4, 8, kMaxFilterOrder}) {
    for (const double cutoff : {lowest, highest}) {
      const Eigen::VectorXd low =
          ConditionRecord(constant, Filter(FilterType::kLowpass, order, 0.0, cutoff), "c").values;
      EXPECT_LE((low.array() - 3.0).abs().maxCoeff(), 3.0 * kGainTolerance) << order;
    }
    const Eigen::VectorXd high =
        ConditionRecord(constant, Filter(FilterType::kHighpass, order, lowest, 0.0), "c").values;
    EXPECT_LE(high.cwiseAbs().maxCoeff(), 3.0 * kGainTolerance) << order;
  }
}

TEST(ConditioningTest, AnOverflowInTheFilterIsNamed) {
  // A step from -1e308 to 1e308: the order-8 low-pass overshoots by ~10 %.
  const TimeSeries s = Record(1000.0, 400, [](double t) { return t < 0.2 ? -1.7e308 : 1.7e308; });
  PODID_EXPECT_THROW_WITH(ConditionRecord(s, Filter(FilterType::kLowpass, 8, 0.0, 50.0), "big.csv"),
                          std::invalid_argument,
                          "big.csv: filter: expected finite filtered values, got an overflow "
                          "(input values of up to 1.7e+308)");
}

}  // namespace
}  // namespace podid
