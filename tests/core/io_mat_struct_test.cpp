// .mat readers beyond plain matrices: test-system export structs, plain
// structs, channels x samples, v7.3 (HDF5) files and their hostile variants,
// and the real recordings of ../shared/realdata. The files in
// tests/data/readers/ are written by make_reader_files.py with scipy and h5py
// (independent writers); their signals are computed here again.
#include <gtest/gtest.h>
#include <matio.h>

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

/// numpy's sin and std::sin may differ by an ulp; amplitudes are at most 4.
constexpr double kLibmSin = 1e-14;

/// Channel j of make_reader_files.py: (j + 1) sin(2 pi (5 + 3 j) t).
double Signal(int j, double t) { return (j + 1) * std::sin(2.0 * M_PI * (5 + 3 * j) * t); }

std::string Reader(const std::string& name) { return DataPath("readers/" + name); }

TimeSeries Read(const std::string& path,
                const std::string& variable = "",
                double rate_Hz = 0.0,
                std::vector<std::string>* notes = nullptr) {
  DataReadOptions options;
  options.variable = variable;
  options.rate_Hz = rate_Hz;
  return ReadTimeSeries(path, options, notes);
}

void ExpectSignals(const TimeSeries& s,
                   const std::vector<int>& which,
                   double start,
                   double step,
                   double tolerance) {
  ASSERT_EQ(s.channels(), static_cast<Eigen::Index>(which.size()));
  for (Eigen::Index i = 0; i < s.samples(); ++i) {
    const double t = start + static_cast<double>(i) * step;
    ASSERT_EQ(s.time_s(i), t) << "sample " << i;  // start + i * step, as both compute it
    for (std::size_t k = 0; k < which.size(); ++k) {
      ASSERT_NEAR(s.values(i, static_cast<Eigen::Index>(k)), Signal(which[k], t), tolerance)
          << "sample " << i << ", channel " << k;
    }
  }
}

constexpr double kStart = 0.25, kStep = 1.0 / 512.0;  // make_reader_files.py's M, MSTART, MSTEP
constexpr int kSamples = 300;

TEST(ReadMatStruct, TestSystemExportSamplesByChannels) {
  std::vector<std::string> notes;
  const TimeSeries s = Read(Reader("testsystem_export.mat"), "", 0.0, &notes);  // the first struct
  EXPECT_EQ(s.channel_names, (std::vector<std::string>{"1:WING:+Z", "2:WING:-X", "3:TAIL:+Y"}));
  // The label says g but the unit transformation (factor 1/9.80665) says the
  // values are in SI: quantity_terms LENGTH^1 TIME^-2.
  EXPECT_EQ(s.units, (std::vector<std::string>(3, "m/s^2")));
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("the label 'g' is the display unit"), std::string::npos) << notes[0];
  ASSERT_EQ(s.samples(), kSamples);
  ExpectSignals(s, {0, 1, 2}, kStart, kStep, kLibmSin);
}

TEST(ReadMatStruct, TestSystemExportRowVectorAndChannelsBySamples) {
  TimeSeries s = Read(Reader("testsystem_export.mat"), "Signal_1");
  EXPECT_EQ(s.channel_names, std::vector<std::string>{"4:SHAKER:+Z"});
  EXPECT_EQ(s.units, std::vector<std::string>{"N"});
  ExpectSignals(s, {0}, kStart, kStep, kLibmSin);
  s = Read(Reader("testsystem_export.mat"), "Signal_2");  // stored 3 x 300
  EXPECT_EQ(s.units, std::vector<std::string>(3, "m/s^2"));
  ExpectSignals(s, {0, 1, 2}, kStart, kStep, kLibmSin);
}

TEST(ReadMatStruct, PlainStructWithTimeAndChannelFields) {
  std::vector<std::string> notes;
  const TimeSeries s = Read(Reader("plain_struct.mat"), "data", 0.0, &notes);
  // acc1 (300), acc2 (300 x 1), both (2 x 300: channels x samples) -> both1, both2.
  EXPECT_EQ(s.channel_names, (std::vector<std::string>{"acc1", "acc2", "both1", "both2"}));
  ExpectSignals(s, {0, 1, 1, 2}, kStart, kStep, kLibmSin);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("fields note, fs skipped"), std::string::npos) << notes[0];
}

TEST(ReadMatStruct, PlainStructWithoutTimeNeedsARate) {
  PODID_EXPECT_THROW_WITH(
      Read(Reader("plain_struct.mat"), "notime"), std::invalid_argument,
      "plain_struct.mat: notime: expected a time field ('t', 'time', "
      "'time_s', 't_s'), a scalar field 'fs' (Hz) or 'dt' (s), or a sampling step "
      "(--rate, --step), got none of them");
  const TimeSeries s = Read(Reader("plain_struct.mat"), "notime", 512.0);
  EXPECT_EQ(s.channel_names, (std::vector<std::string>{"a", "b"}));
  ASSERT_EQ(s.samples(), kSamples);
  for (int i = 0; i < kSamples; ++i) {  // t = i / rate; the values were made from t = 0.25 + ...
    ASSERT_EQ(s.time_s(i), i * kStep);
    ASSERT_NEAR(s.values(i, 1), Signal(2, kStart + i * kStep), kLibmSin);
  }
}

TEST(ReadMatStruct, PlainStructWithASamplingRateField) {
  // withfs = struct(fs = 512, x (300), y (300)): t = i / fs.
  std::vector<std::string> notes;
  const TimeSeries s = Read(Reader("plain_struct.mat"), "withfs", 0.0, &notes);
  EXPECT_EQ(s.channel_names, (std::vector<std::string>{"x", "y"}));
  ASSERT_EQ(s.samples(), kSamples);
  EXPECT_EQ(s.time_s(1), kStep);
  for (int i = 0; i < kSamples; ++i)
    ASSERT_NEAR(s.values(i, 1), Signal(1, kStart + i * kStep), kLibmSin);
  ASSERT_EQ(notes.size(), 2u);
  EXPECT_NE(notes[1].find("withfs: sampling from its field fs = 512"), std::string::npos)
      << notes[1];
}

TEST(ReadMatStruct, TimeGridsThatDoublesCannotResolveAreRejected) {
  // A sampling rate of 1e-308 Hz: 300 samples 1e308 s apart overflow.
  PODID_EXPECT_THROW_WITH(Read(Reader("plain_struct.mat"), "notime", 1e-308), std::invalid_argument,
                          "plain_struct.mat: notime (sampling step): expected a finite time grid "
                          "whose step > 0 s is at least 1.11e-13 of its largest time");
  // A test-system export starting at 1e300 s every 1e-300 s: all times equal.
  const testing::TempDir dir;
  const std::string path = dir.File("collapsed.mat");
  mat_t* mat = Mat_CreateVer(path.c_str(), nullptr, MAT_FT_MAT5);
  ASSERT_NE(mat, nullptr);
  double start = 1e300, increment = 1e-300, values[4] = {1, 2, 3, 4};
  size_t one[2] = {1, 1}, column[2] = {4, 1};
  const char* x_fields[2] = {"start_value", "increment"};
  const char* y_fields[1] = {"values"};
  const char* fields[2] = {"x_values", "y_values"};
  matvar_t* x = Mat_VarCreateStruct("x_values", 2, one, x_fields, 2);
  Mat_VarSetStructFieldByName(
      x, "start_value", 0,
      Mat_VarCreate("start_value", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, one, &start, 0));
  Mat_VarSetStructFieldByName(
      x, "increment", 0,
      Mat_VarCreate("increment", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, one, &increment, 0));
  matvar_t* y = Mat_VarCreateStruct("y_values", 2, one, y_fields, 1);
  Mat_VarSetStructFieldByName(
      y, "values", 0, Mat_VarCreate("values", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, column, values, 0));
  matvar_t* signal = Mat_VarCreateStruct("Signal_0", 2, one, fields, 2);
  Mat_VarSetStructFieldByName(signal, "x_values", 0, x);
  Mat_VarSetStructFieldByName(signal, "y_values", 0, y);
  ASSERT_EQ(Mat_VarWrite(mat, signal, MAT_COMPRESSION_NONE), 0);
  Mat_VarFree(signal);
  Mat_Close(mat);
  PODID_EXPECT_THROW_WITH(Read(path), std::invalid_argument,
                          "Signal_0.x_values: expected a finite time grid whose step > 0 s is at "
                          "least 1.11e-13 of its largest time (double precision resolves it), got "
                          "a start of 1e+300 s, a step of 1e-300 s and 4 samples (up to 1e+300 s)");
}

TEST(ReadMatStruct, ChannelSelectionAndRateChecks) {
  DataReadOptions options;
  options.channels = {"3:TAIL:+Y", "1:WING:+Z"};
  const TimeSeries s = ReadTimeSeries(Reader("testsystem_export.mat"), options);
  EXPECT_EQ(s.channel_names, options.channels);
  ExpectSignals(s, {2, 0}, kStart, kStep, kLibmSin);
  options.channels = {"9:NONE"};
  PODID_EXPECT_THROW_WITH(ReadTimeSeries(Reader("testsystem_export.mat"), options),
                          std::invalid_argument,
                          "expected a channel \"9:NONE\" (channels: 1:WING:+Z, 2:WING:-X, "
                          "3:TAIL:+Y), got none");
  options.channels.clear();
  options.rate_Hz = 500.0;  // the file says 512 Hz
  PODID_EXPECT_THROW_WITH(ReadTimeSeries(Reader("testsystem_export.mat"), options),
                          std::invalid_argument,
                          "expected a sampling step (0.002 s given) that agrees with the file's "
                          "own time, got a step of 0.001953125 s in the file");
  options.rate_Hz = 512.0;
  EXPECT_NO_THROW(ReadTimeSeries(Reader("testsystem_export.mat"), options));
  options.step_s = 1.0;
  PODID_EXPECT_THROW_WITH(ReadTimeSeries(Reader("testsystem_export.mat"), options),
                          std::invalid_argument, "expected a sampling rate or a step, got both");
}

TEST(ReadMat73, MatrixChannelsBySamplesAndStructWrittenByH5py) {
  // v73_matrix.mat: t (1 x 300), w (3 x 300: the time vector's length says
  // channels x samples), data = struct(time, a, b).
  TimeSeries s = Read(Reader("v73_matrix.mat"));
  EXPECT_EQ(s.channel_names, (std::vector<std::string>{"w1", "w2", "w3"}));
  ExpectSignals(s, {0, 1, 2}, kStart, kStep, kLibmSin);
  s = Read(Reader("v73_matrix.mat"), "data");
  EXPECT_EQ(s.channel_names, (std::vector<std::string>{"a", "b"}));
  ExpectSignals(s, {0, 2}, kStart, kStep, kLibmSin);
}

TEST(ReadMat73, NeverWrittenChunksAreRejectedBeforeReading) {
  // Issue 10 item 8: 3e8 doubles declared, none stored: took 3 GB and 120 s.
  // 5e7 passes the file-size bound (66 kB x 1032) and the memory budget: only
  // the allocated storage tells that nothing was written.
  for (const char* name : {"v73_unwritten_3e8.mat", "v73_unwritten_5e7.mat"}) {
    PODID_EXPECT_THROW_WITH(Read(Reader(name)), std::invalid_argument,
                            std::string(name) +
                                ": dataset '/w': expected data stored in the file (0 bytes "
                                "allocated hold at most 16512 elements), got");
  }
}

TEST(ReadMat73, TruncatedFileIsOneLineWithoutHdf5Diagnostics) {
  // Issue 10 item 11: HDF5 printed 15-122 lines of its error stack.
  ::testing::internal::CaptureStderr();
  PODID_EXPECT_THROW_WITH(Read(Reader("v73_truncated.mat")), std::invalid_argument,
                          "v73_truncated.mat: expected a readable MATLAB v7.3 .mat file (HDF5), "
                          "got a file HDF5 cannot open (truncated or corrupt)");
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
}

TEST(ReadMat73, StructWrittenByMatio) {
  // libmatio's own v7.3 writer: a test-system export layout at one level.
  const testing::TempDir dir;
  const std::string path = dir.File("s73.mat");
  mat_t* mat = Mat_CreateVer(path.c_str(), nullptr, MAT_FT_MAT73);
  if (mat == nullptr) GTEST_SKIP() << "libmatio built without HDF5";
  std::vector<double> t(kSamples), a(kSamples);
  for (int i = 0; i < kSamples; ++i) {
    t[i] = kStart + i * kStep;
    a[i] = Signal(0, t[i]);
  }
  size_t one[2] = {1, 1}, row[2] = {1, static_cast<size_t>(kSamples)};
  const char* fields[2] = {"Time", "acc"};
  matvar_t* s = Mat_VarCreateStruct("rec", 2, one, fields, 2);
  Mat_VarSetStructFieldByName(
      s, "Time", 0, Mat_VarCreate("Time", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, row, t.data(), 0));
  Mat_VarSetStructFieldByName(
      s, "acc", 0, Mat_VarCreate("acc", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, row, a.data(), 0));
  ASSERT_EQ(Mat_VarWrite(mat, s, MAT_COMPRESSION_ZLIB), 0);
  Mat_VarFree(s);
  Mat_Close(mat);
  const TimeSeries series = Read(path);
  EXPECT_EQ(series.channel_names, std::vector<std::string>{"acc"});
  ExpectSignals(series, {0}, kStart, kStep, 0.0);  // the same doubles
}

// --- The real recordings (../shared/realdata), when present ------------------

/// $PODID_REALDATA, else ../shared/realdata beside the repository.
std::string RealData(const std::string& name) {
  const char* root = std::getenv("PODID_REALDATA");
  if (root != nullptr && *root != '\0') return std::string(root) + "/" + name;
  return (std::filesystem::path(PODID_TEST_DATA_DIR) / "../../../shared/realdata" / name).string();
}

#define SKIP_WITHOUT(path)            \
  if (!std::filesystem::exists(path)) \
  GTEST_SKIP() << path << " is absent (the shared real recordings, see tests/data/README.md)"

TEST(ReadRealRecordings, F16TestSystemExport) {
  const std::string path = RealData("testlab/F16_Data.mat");
  SKIP_WITHOUT(path);
  const TimeSeries s = Read(path);  // Signal_0: 115 accelerations
  // Expected values printed by scipy.io.loadmat (an independent parser).
  ASSERT_EQ(s.channels(), 115);
  ASSERT_EQ(s.samples(), 108477);
  EXPECT_EQ(s.channel_names[0], "4:DP_RIGHT:-Z");
  EXPECT_EQ(s.channel_names[66], "70:RMIS MS:1004:+Z");
  EXPECT_EQ(s.channel_names[114], "120:LWNG:0012:+Z");
  EXPECT_EQ(s.units[0], "m/s^2");  // labelled g, stored in SI (factor 0.10197)
  EXPECT_EQ(s.time_s(0), 0.08489286132855342);
  EXPECT_EQ(s.time_s(1), 0.08489286132855342 + 0.0025);
  EXPECT_EQ(s.values(0, 66), 0.000814028564453125);
  EXPECT_EQ(s.values(54321, 66), -0.3992331268310547);
  EXPECT_EQ(s.values(54321, 102), -0.4101506864013672);
  // Column sums (numpy: 0.35115755749512534, 1.0137648379516686): summation order.
  constexpr double kSumOrder = 1e-9;
  EXPECT_NEAR(s.values.col(66).sum(), 0.35115755749512534, kSumOrder);
  EXPECT_NEAR(s.values.col(102).sum(), 1.0137648379516686, kSumOrder);
  const TimeSeries force = Read(path, "Signal_1");
  EXPECT_EQ(force.channel_names, std::vector<std::string>{"3:DP_RIGHT:+Z"});
  EXPECT_EQ(force.units, std::vector<std::string>{"N"});
  EXPECT_EQ(force.values(12345, 0), 14.0447535891318);
}

TEST(ReadRealRecordings, SilverboxWithoutTimeVector) {
  const std::string path = RealData("silverbox/SNLS80mV.mat");
  SKIP_WITHOUT(path);
  PODID_EXPECT_THROW_WITH(Read(path), std::invalid_argument,
                          "expected a time vector variable ('t' or 'time') or a sampling step");
  DataReadOptions options;
  options.rate_Hz = 610.3515625;  // 10^7 / 2^14
  options.channels = {"V1", "V2"};
  const TimeSeries s = ReadTimeSeries(path, options);
  ASSERT_EQ(s.samples(), 131072);
  EXPECT_EQ(s.time_s(1), 1.0 / 610.3515625);
  EXPECT_EQ(s.values(0, 0), 0.005775621745857643);  // scipy.io.loadmat
  EXPECT_EQ(s.values(100000, 0), 0.008113887013919885);
  EXPECT_EQ(s.values(100000, 1), 0.0864050852532906);
}

}  // namespace
}  // namespace podid
