// Universal files (UFF 58 / 58b): time responses as channels. The four-channel
// files in tests/data/readers/ are written by make_reader_files.py (struct
// packing, independent of podid); the small pyuff samples in tests/data/uff/
// are checked against values read by eye from their text; the large pyuff
// samples are read from ../shared/realdata when present.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "podid/core/io.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

using testing::DataPath;

double Signal(int j, double t) { return (j + 1) * std::sin(2.0 * M_PI * (5 + 3 * j) * t); }

constexpr int kSamples = 64;
constexpr double kStart = 0.5, kStep = 1.0 / 256.0;  // exact in the E13.5 of record 7

void ExpectFourAccelerations(const TimeSeries& s, double tolerance) {
  EXPECT_EQ(s.channel_names, (std::vector<std::string>{"1+Z", "2-Y", "3+X", "4+Z"}));
  EXPECT_EQ(s.units, std::vector<std::string>(4, "m/s^2"));
  ASSERT_EQ(s.samples(), kSamples);
  for (int i = 0; i < kSamples; ++i) {
    const double t = kStart + i * kStep;
    ASSERT_EQ(s.time_s(i), t);
    for (int j = 0; j < 4; ++j)
      ASSERT_NEAR(s.values(i, j), Signal(j, t), tolerance) << i << "," << j;
  }
}

TEST(ReadUff, FourAccelerationsBinarySingleLittleEndianWithSkippedDataSets) {
  // Single precision: half an ulp of |x| <= 4 is 2.4e-7.
  constexpr double kSingle = 2.5e-7;
  std::vector<std::string> notes;
  ExpectFourAccelerations(
      ReadUff(DataPath("readers/uff_four_accelerations_58b_le_single.uff"), &notes), kSingle);
  ASSERT_EQ(notes.size(), 2u);
  EXPECT_NE(notes[0].find(":2: data set 151 skipped"), std::string::npos) << notes[0];
  EXPECT_NE(notes[1].find("data set 58 of function type 4, complex skipped"), std::string::npos)
      << notes[1];
}

TEST(ReadUff, FourAccelerationsBinaryDoubleBigEndian) {
  constexpr double kLibmSin = 1e-14;  // the same doubles, up to numpy's sin
  ExpectFourAccelerations(ReadUff(DataPath("readers/uff_four_accelerations_58b_be_double.uff")),
                          kLibmSin);
}

TEST(ReadUff, FourAccelerationsAsciiWithShortLastLines) {
  constexpr double kE13_5 = 2.5e-5;  // 6 significant digits of |x| <= 4: half a unit is 2e-5
  ExpectFourAccelerations(ReadTimeSeries(DataPath("readers/uff_four_accelerations_58.uff")),
                          kE13_5);
}

TEST(ReadUff, PyuffSamples) {
  // binary8byte.uff: 250 doubles, node 1, scalar, unit g, 0.01 s.
  TimeSeries s = ReadUff(DataPath("uff/binary8byte.uff"));
  EXPECT_EQ(s.channel_names, std::vector<std::string>{"1S"});
  EXPECT_EQ(s.units, std::vector<std::string>{"g"});
  ASSERT_EQ(s.samples(), 250);
  EXPECT_EQ(s.time_s(1), 0.01);
  // time-history-not-all-columns-filled.uff: 13 values, the last line holds one;
  // written by HBM catman with the unit "m/s²" in UTF-8.
  s = ReadUff(DataPath("uff/time-history-not-all-columns-filled.uff"));
  ASSERT_EQ(s.samples(), 13);
  EXPECT_EQ(s.values(0, 0), -3.81956);
  EXPECT_EQ(s.values(12, 0), -5.84096);
  EXPECT_EQ(s.time_s(12), 12 * 5e-5);
  EXPECT_EQ(s.units, std::vector<std::string>{"m/s\u00b2"});
  // non_ascii_header.uff: one FRF (type 4) with a Latin-1 unit: nothing to read.
  PODID_EXPECT_THROW_WITH(ReadUff(DataPath("uff/non_ascii_header.uff")), std::invalid_argument,
                          "expected a data set 58 or 58b with a time response (function type 1), "
                          "got none (2: data set 58 of function type 4, complex skipped");
  // dataset_milestone_in_header.uff declares 2,508,876 values and holds 42.
  PODID_EXPECT_THROW_WITH(ReadUff(DataPath("uff/dataset_milestone_in_header.uff")),
                          std::invalid_argument,
                          "dataset_milestone_in_header.uff:9: expected a count whose data fits in "
                          "the 559 bytes left, got 2508876 values (a corrupt or truncated file)");
}

TEST(ReadUff, Rejections) {
  PODID_EXPECT_THROW_WITH(
      ReadUff(DataPath("readers/uff_mismatched_grids.uff")), std::invalid_argument,
      "uff_mismatched_grids.uff:27: expected the grid of the first time response "
      "(line 2): 64 samples from 0.5 s every 0.00390625 s, got 32 samples from "
      "0.5 s every 0.00390625 s");
  // 10^9 values declared in 573 bytes: rejected before any allocation.
  PODID_EXPECT_THROW_WITH(ReadUff(DataPath("readers/uff_huge_count.uff")), std::invalid_argument,
                          "uff_huge_count.uff:9: expected a count whose data fits in the");
  const testing::TempDir dir;
  PODID_EXPECT_THROW_WITH(ReadUff(dir.Write("x.uff", "hello\n")), std::invalid_argument,
                          "x.uff:1: expected a data set starting with \"    -1\", got \"hello\"");
  const std::string head =
      "    -1\n    58b     1     2          11          80     0     0           0           0\n"
      "a\nb\nc\nd\ne\n"
      "    1         0    0         0 NONE               1   3 NONE               0   0\n"
      "         2        20         1  0.00000E+00  1.00000E-03  0.00000E+00\n"
      "        17    0    0    0 Time                 s\n"
      "        12    0    0    0 Acc                  m/s^2\n"
      "         0    0    0    0 NONE                 NONE\n"
      "         0    0    0    0 NONE                 NONE\n";
  // 80 bytes announced, 40 present.
  PODID_EXPECT_THROW_WITH(ReadUff(dir.Write("short.uff", head + std::string(40, '\0'))),
                          std::invalid_argument,
                          "short.uff:9: expected a count whose data fits in the 40 bytes left, got "
                          "20 values");
  // Record 7 cut after its three integers (found by podid_fuzz_uff: the
  // floats after column 30 were read with substr(30), std::out_of_range).
  const std::string record7 =
      "         2        20         1  0.00000E+00  1.00000E-03  0.00000E+00";
  std::string cut = head;
  cut.replace(cut.find(record7), record7.size(), "         2        20     1");
  PODID_EXPECT_THROW_WITH(ReadUff(dir.Write("cut.uff", cut + std::string(80, '\0'))),
                          std::invalid_argument,
                          "cut.uff:9: expected record 7: data type, count, spacing, start, "
                          "increment, got \"2        20     1\"");
  // 58b byte order 1.1e18 (found by podid_fuzz_uff: converted to int before
  // its range was checked, undefined behaviour under UBSan).
  std::string huge_order = head;
  huge_order.replace(huge_order.find("     1     2          11"), 6, " 1111111111111111111");
  PODID_EXPECT_THROW_WITH(
      ReadUff(dir.Write("order.uff", huge_order + std::string(80, '\0') + "    -1\n")),
      std::invalid_argument, "byte order 1.111111111e+18, format 2");
  // A start of 1e300 s every 1e-300 s: every time the same double (found by
  // podid_fuzz_uff in CI: the grid was built unchecked). And a grid whose end
  // overflows.
  const std::string ascii_head = [&] {
    std::string text = head;
    text.replace(text.find("58b     1     2          11          80"), 39, "58");
    return text;
  }();
  const std::string twenty(std::string(4, ' ') + "1.0 2.0 3.0 4.0 5.0\n");
  const std::string values = twenty + twenty + twenty + twenty + "    -1\n";
  std::string collapsed = ascii_head;
  collapsed.replace(collapsed.find(record7), record7.size(),
                    "         2        20         1  1.00000E+300 1.00000E-300 0.00000E+00");
  PODID_EXPECT_THROW_WITH(
      ReadUff(dir.Write("collapsed.uff", collapsed + values)), std::invalid_argument,
      "collapsed.uff:9 (record 7): expected a finite time grid whose step > 0 s is at least "
      "1.11e-13 of its largest time (double precision resolves it), got a start of 1e+300 s, a "
      "step of 1e-300 s and 20 samples (up to 1e+300 s)");
  std::string overflow = ascii_head;
  overflow.replace(overflow.find(record7), record7.size(),
                   "         2        20         1  0.00000E+00  1.00000E+307 0.00000E+00");
  PODID_EXPECT_THROW_WITH(ReadUff(dir.Write("overflow.uff", overflow + values)),
                          std::invalid_argument,
                          "overflow.uff:9 (record 7): expected a finite time grid");
  // The same file with a start of 0 s and a step of 1 ms is read.
  std::string fine = ascii_head;
  const TimeSeries read = ReadUff(dir.Write("fine.uff", fine + values));
  ASSERT_EQ(read.samples(), 20);
  EXPECT_EQ(read.time_s(19), 19 * 1e-3);
  // 58b announcing VAX floats (format 1).
  std::string vax = head;
  vax.replace(vax.find("     2          11"), 6, "     1");
  PODID_EXPECT_THROW_WITH(ReadUff(dir.Write("vax.uff", vax + std::string(80, '\0') + "    -1\n")),
                          std::invalid_argument, "format 2 (IEEE 754)");
}

std::string RealData(const std::string& name) {
  const char* root = std::getenv("PODID_REALDATA");
  if (root != nullptr && *root != '\0') return std::string(root) + "/" + name;
  return (std::filesystem::path(PODID_TEST_DATA_DIR) / "../../../shared/realdata" / name).string();
}

TEST(ReadUff, RepeatedNamesAreNumberedInFileOrder) {
  // Three ASCII data sets at node 1, +Z: "1+Z", "1+Z_2", "1+Z_3" (a hash of
  // the names used; the earlier scan of every previous name made a file of
  // many small data sets quadratic).
  std::string text;
  for (int j = 0; j < 3; ++j) {
    text +=
        "    -1\n    58\nr\nNONE\nNONE\nNONE\nNONE\n"
        "    1         0    0         0 NONE               1   3 NONE               0   0\n"
        "         2         2         1  0.00000E+00  1.00000E-03  0.00000E+00\n"
        "        17    0    0    0 Time                 s\n"
        "        12    1    0    0 Acceleration         m/s^2\n"
        "         0    0    0    0 NONE                 NONE\n"
        "         0    0    0    0 NONE                 NONE\n"
        "  1.00000E+00  2.00000E+00\n    -1\n";
  }
  const testing::TempDir dir;
  const TimeSeries s = ReadUff(dir.Write("three.uff", text));
  EXPECT_EQ(s.channel_names, (std::vector<std::string>{"1+Z", "1+Z_2", "1+Z_3"}));
}

TEST(ReadUff, LargePyuffSamplesAsciiAndBinaryAgree) {
  const std::string ascii = RealData("uff/Sample_UFF58_ascii.uff");
  const std::string binary = RealData("uff/Sample_UFF58b_bin.uff");
  if (!std::filesystem::exists(ascii) || !std::filesystem::exists(binary)) {
    GTEST_SKIP() << "the shared pyuff samples are absent (../shared/realdata/uff)";
  }
  const TimeSeries a = ReadUff(ascii), b = ReadUff(binary);
  ASSERT_EQ(a.samples(), 79292);
  ASSERT_EQ(b.samples(), 79292);
  EXPECT_EQ(a.units, std::vector<std::string>{"Pa"});
  EXPECT_EQ(b.channel_names, std::vector<std::string>{"0+X"});
  EXPECT_EQ(a.time_s(1), 1.52588e-05);  // as record 7 prints it
  // The first values as the ASCII file prints them.
  EXPECT_EQ(a.values(0, 0), -1.47553e-02);
  EXPECT_EQ(a.values(5, 0), -1.53669e-02);
  // E13.5 text against single-precision binary: 6 digits of |x| < 1.
  constexpr double kE13_5 = 5e-7;
  EXPECT_LE((a.values - b.values).cwiseAbs().maxCoeff(),
            kE13_5 * a.values.cwiseAbs().maxCoeff() * 10);
}

}  // namespace
}  // namespace podid
