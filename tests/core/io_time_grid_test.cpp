// Time stamps as spreadsheets round them (issue 12, item 1): accepted when
// they agree with a uniform grid to their printed precision, replaced by the
// least-squares grid; a real gap or jitter is still rejected (io.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "podid/core/io.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

constexpr double kRate_Hz = 1024.0;
constexpr int kSamples = 1024;

/// A CSV whose stamps are printed with 4 significant digits (%.4g), as a
/// spreadsheet column shows 0.0009766, 0.001953, ... at 1024 Hz. `skip` drops
/// one row, `shift_s` moves the stamp of row `at`.
std::string SpreadsheetCsv(int skip = -1, int at = -1, double shift_s = 0.0) {
  std::string text = "time,x\n";
  for (int i = 0; i < kSamples; ++i) {
    if (i == skip) continue;
    char line[64];
    const double t = i / kRate_Hz + (i == at ? shift_s : 0.0);
    std::snprintf(line, sizeof line, "%.4g,%.17g\n", t, std::sin(2.0 * M_PI * 10.0 * i / kRate_Hz));
    text += line;
  }
  return text;
}

TEST(TimeGrid, SpreadsheetRoundedStampsAreAcceptedAndReplacedByTheFittedGrid) {
  const testing::TempDir dir;
  const std::string text = SpreadsheetCsv();
  ASSERT_EQ(text.substr(0, 28), "time,x\n0,0\n0.0009766,0.06132");  // the stamps
  ASSERT_NE(text.find("\n0.001953,"), std::string::npos);
  const TimeSeries s = ReadCsv(dir.Write("rounded.csv", text));
  ASSERT_EQ(s.samples(), kSamples);
  // The fitted step's error from stamps rounded by at most q = 5e-5 s is about
  // sqrt(12) q / N^1.5 = 5e-9 s, 5e-6 of the step.
  constexpr double kFittedStep = 1e-5;
  EXPECT_NEAR(s.step_s() * kRate_Hz, 1.0, kFittedStep);
  // Every time is on the fitted grid (t0 + i h), not the printed stamp.
  const double h = s.time_s(1) - s.time_s(0);
  for (int i = 0; i < kSamples; ++i) {
    ASSERT_NEAR(s.time_s(i), s.time_s(0) + i * h, 1e-12) << i;
    ASSERT_NEAR(s.time_s(i), i / kRate_Hz, 5e-5) << i;  // within the printing
  }
}

TEST(TimeGrid, AMissingSampleIsStillRejected) {
  const testing::TempDir dir;
  // Row 501 (t = 0.4883 s) missing: file line 502 holds t = 0.4893. The
  // median of steps printed to 4 digits is 0.001 s.
  PODID_EXPECT_THROW_WITH(ReadCsv(dir.Write("gap.csv", SpreadsheetCsv(500))), std::invalid_argument,
                          "gap.csv:502:1: expected a uniform time step 0.001 s (within 0.0002 s: "
                          "the stamps' rounding and 1e-06 of a step), got a step of 0.002 s");
}

TEST(TimeGrid, AJitterBeyondThePrintingIsStillRejected) {
  const testing::TempDir dir;
  // 0.4 of a step (4e-4 s) on a stamp printed to 5e-5 s: found at the step
  // into it (file line 302).
  PODID_EXPECT_THROW_WITH(ReadCsv(dir.Write("jitter.csv", SpreadsheetCsv(-1, 300, 4e-4))),
                          std::invalid_argument, "jitter.csv:302:1: expected a uniform time step");
  // 0.12 of a step (printed 0.2931 for 0.29297 s): off the fitted grid by
  // 1.3e-4 s, beyond the rounding (5e-5 s) and the fit's error bound.
  try {
    ReadCsv(dir.Write("jitter2.csv", SpreadsheetCsv(-1, 300, 1.2e-4)));
    ADD_FAILURE() << "a jitter of 0.12 steps was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_TRUE(what.find("jitter2.csv:302:1: expected a") != std::string::npos ||
                what.find("jitter2.csv:303:1: expected a") != std::string::npos)
        << what;
  }
  // Half the printing precision is within it.
  EXPECT_NO_THROW(ReadCsv(dir.Write("fine.csv", SpreadsheetCsv(-1, 300, 2e-5))));
}

/// `samples` stamps i * step_s printed with printf `format` (a value column of
/// zeros); `skip` drops one row.
std::string PrintedCsv(const char* format, double step_s, int samples, int skip = -1) {
  std::string text = "t,x\n";
  for (int i = 0; i < samples; ++i) {
    if (i == skip) continue;
    char stamp[64];
    std::snprintf(stamp, sizeof stamp, format, i * step_s);
    text += std::string(stamp) + ",0\n";
  }
  return text;
}

TEST(TimeGrid, StampsPrintedToAStepMustBeExactMultiples) {
  // One decimal at 10 Hz, or sample numbers as time: the rounding of such a
  // column (half a step) would hide a missing sample, so the stamps are taken
  // as exact. Each missing sample is found at the row after it (sample i on
  // file line i + 2).
  const testing::TempDir dir;
  const TimeSeries tenths = ReadCsv(dir.Write("tenths.csv", PrintedCsv("%.1f", 0.1, 100)));
  EXPECT_EQ(tenths.samples(), 100);
  EXPECT_DOUBLE_EQ(tenths.time_s(99), 9.9);  // kept as written
  EXPECT_EQ(ReadCsv(dir.Write("numbers.csv", PrintedCsv("%.0f", 1.0, 100))).samples(), 100);
  PODID_EXPECT_THROW_WITH(ReadCsv(dir.Write("gap.csv", PrintedCsv("%.1f", 0.1, 100, 50))),
                          std::invalid_argument,
                          "gap.csv:52:1: expected a uniform time step 0.1 s exactly (the stamps' "
                          "resolution, 0.1 s, is half a step or more: rounding would hide a "
                          "missing sample), got a step of 0.2 s");
  PODID_EXPECT_THROW_WITH(ReadCsv(dir.Write("gap2.csv", PrintedCsv("%.0f", 1.0, 100, 7))),
                          std::invalid_argument,
                          "gap2.csv:9:1: expected a uniform time step 1 s exactly");
  // 6.67 Hz printed to 0.1 s: steps of 0.1 and 0.2 s, rounding or gaps alike.
  PODID_EXPECT_THROW_WITH(ReadCsv(dir.Write("coarse.csv", PrintedCsv("%.1f", 0.15, 100))),
                          std::invalid_argument, "s exactly (the stamps' resolution, 0.1 s");
}

TEST(TimeGrid, AMissingSampleIsFoundWithStampsPrintedToUnderHalfAStep) {
  // 4444 Hz printed to 1e-4 s (0.44 of a step): steps are 2 or 3 units. Row
  // 1000 missing leaves a step of 4 units (file line 1002), within the median
  // test's 4 roundings of the median (2 units) but 1.8 units from the fitted
  // step, beyond the rounding of its two stamps (1 unit).
  const testing::TempDir dir;
  EXPECT_EQ(ReadCsv(dir.Write("fine.csv", PrintedCsv("%.4f", 2.25e-4, 2000))).samples(), 2000);
  PODID_EXPECT_THROW_WITH(ReadCsv(dir.Write("gap.csv", PrintedCsv("%.4f", 2.25e-4, 2000, 1000))),
                          std::invalid_argument,
                          "gap.csv:1002:1: expected a uniform time step 0.0002251688927 s (least "
                          "squares; within 0.0001 s: the two stamps' rounding and the fit's "
                          "error), got a step of 0.0004 s");
}

TEST(TimeGrid, SubnormalStepsAreRejected) {
  // Increasing, uniform stamps 1e-320 s apart fit a grid whose rate 1 / step
  // is infinite: a transform's every frequency would inherit it (IsSamplingStep).
  const testing::TempDir dir;
  std::string text = "t,x\n";
  for (int i = 0; i < 16; ++i) {
    char line[64];
    std::snprintf(line, sizeof line, "%.17g,%d\n", i * 1e-320, i % 3);
    text += line;
  }
  PODID_EXPECT_THROW_WITH(ReadCsv(dir.Write("subnormal.csv", text)), std::invalid_argument,
                          "subnormal.csv:3:1: expected a time step whose rate 1 / step is finite, "
                          "got a step of ");
}

TEST(TimeGrid, FullPrecisionStampsAreKeptAsWritten) {
  // The reference data's %.12e stamps stay exactly as written.
  const std::string path = testing::DataPath("clean_knl50_T0.1.csv");
  const TimeSeries s = ReadCsv(path);
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  for (Eigen::Index i = 0; std::getline(in, line); ++i) {
    ASSERT_LT(i, s.samples());
    ASSERT_EQ(s.time_s(i), std::stod(line.substr(0, line.find(',')))) << i;
  }
}

}  // namespace
}  // namespace podid
