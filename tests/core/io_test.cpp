// Time-series files: CSV (reference data, rejections with file:line:column,
// size), MATLAB .mat through libmatio, and atomic writes.
#include "podid/core/io.hpp"

#include <gtest/gtest.h>
#include <matio.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "temp_dir.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

using testing::DataPath;
using testing::ReadText;
using testing::TempDir;

// --- CSV: reading the reference data --------------------------------------

TEST(ReadCsv, ReadsTheReferenceData) {
  const TimeSeries series = ReadCsv(DataPath("clean_knl50_T0.1.csv"));
  EXPECT_EQ(series.samples(), 501);
  EXPECT_EQ(series.channels(), 6);
  EXPECT_EQ(series.channel_names, (std::vector<std::string>{"w1", "w2", "w3", "w4", "w5", "w6"}));
  // The file's first and last rows, parsed from their decimal text: exact.
  EXPECT_EQ(series.time_s(0), 0.0);
  EXPECT_EQ(series.time_s(500), 0.1);
  EXPECT_EQ(series.values(0, 0), 4.726045480145e-05);
  EXPECT_EQ(series.values(0, 5), 1.200971557307e-03);
  EXPECT_EQ(series.values(1, 5), 1.192622367168e-03);
  // Uniform step: 2e-4 s up to the 13-digit rounding of the file.
  constexpr double kStepTolerance = 1e-15;
  EXPECT_NEAR(series.step_s(), 2e-4, kStepTolerance);
  EXPECT_EQ(ReadCsv(DataPath("measured_knl50_T1.0.csv")).samples(), 5001);
}

TEST(WriteCsv, RoundTripIsByteIdenticalToTheReferenceFiles) {
  const TempDir dir;
  for (const char* name :
       {"clean_knl50_T0.1.csv", "measured_knl50_T0.1.csv", "measured_knl50_T1.0.csv"}) {
    const TimeSeries series = ReadCsv(DataPath(name));
    const std::string out = dir.File(name);
    WriteCsv(out, series);
    EXPECT_EQ(ReadText(out), ReadText(DataPath(name))) << name;
    const TimeSeries again = ReadCsv(out);
    EXPECT_EQ(again.values, series.values);
    EXPECT_EQ(again.time_s, series.time_s);
  }
}

TEST(WriteCsv, FormatIsPrintfPercentDotTwelveE) {
  const TempDir dir;
  TimeSeries series;
  series.time_s = Eigen::Vector2d(0.0, 0.5);
  series.channel_names = {"a", "b"};
  series.values.resize(2, 2);
  series.values << -0.0, 1.0 / 3.0, -1e-300, 123456789.0;
  WriteCsv(dir.File("x.csv"), series);
  std::string expected = "t,a,b\n";
  char line[256];
  for (int i = 0; i < 2; ++i) {
    std::snprintf(line, sizeof(line), "%.12e,%.12e,%.12e\n", series.time_s(i), series.values(i, 0),
                  series.values(i, 1));
    expected += line;
  }
  EXPECT_EQ(ReadText(dir.File("x.csv")), expected);
}

TEST(WriteCsv, RejectsInconsistentSeriesBeforeWriting) {
  const TempDir dir;
  TimeSeries series;
  series.time_s = Eigen::Vector3d(0, 1, 2);
  series.channel_names = {"w1"};
  series.values = Eigen::MatrixXd::Zero(2, 1);
  PODID_EXPECT_THROW_WITH(WriteCsv(dir.File("x.csv"), series), std::invalid_argument,
                          "expected 2 times (one per sample), got 3");
  series.time_s = Eigen::Vector2d(0, 1);
  series.channel_names = {"w\t1"};  // ReadCsv refuses control characters in names
  PODID_EXPECT_THROW_WITH(WriteCsv(dir.File("x.csv"), series), std::invalid_argument,
                          "expected channel names without control characters, not empty, got "
                          "\"w\\t1\"");
  series.channel_names = {""};
  PODID_EXPECT_THROW_WITH(WriteCsv(dir.File("x.csv"), series), std::invalid_argument,
                          "expected channel names without control characters, not empty");
  series.channel_names = {"t"};  // the header "t,t" would not read back
  PODID_EXPECT_THROW_WITH(WriteCsv(dir.File("x.csv"), series), std::invalid_argument,
                          "expected distinct channel names other than \"t\", got \"t\" twice");
  series.channel_names = {};
  PODID_EXPECT_THROW_WITH(WriteCsv(dir.File("x.csv"), series), std::invalid_argument,
                          "expected 1 channel names, got 0");
  EXPECT_TRUE(dir.Entries().empty());
}

TEST(WriteCsv, WritesOnlyLinesReadCsvReadsBack) {
  // 50,000 channels of "-1.000000000000e+00,": a 1,000,018-byte row that was
  // written, and then refused by ReadCsv ("a line of at most 1048576 bytes").
  const TempDir dir;
  constexpr Eigen::Index kWide = 50000;
  TimeSeries series;
  series.time_s = Eigen::Vector2d(0, 0.5);
  series.channel_names.resize(kWide);
  for (Eigen::Index j = 0; j < kWide; ++j) series.channel_names[j] = "c" + std::to_string(j);
  // Both rows print 18 + 50,000 x 19 = 950,018 bytes: under the bound, though
  // the widest cells (21 bytes) would not be, so each row's length is checked.
  series.values = Eigen::MatrixXd::Constant(2, kWide, 1.0);
  const std::string path = dir.File("wide.csv");
  WriteCsv(path, series);
  const TimeSeries back = ReadCsv(path);
  EXPECT_EQ(back.values, series.values);
  EXPECT_EQ(back.channel_names, series.channel_names);
  // Negative values with three-digit exponents: 21 bytes a cell, and the
  // second row's 1,050,018 bytes pass the bound (1,048,576).
  series.values.row(1).setConstant(-1e-100);
  PODID_EXPECT_THROW_WITH(WriteCsv(path, series), std::invalid_argument,
                          "expected lines of at most 1048576 bytes (kMaxCsvLineBytes, what ReadCsv "
                          "reads back), got line 3 of 1050018 bytes (50000 channels)");
  EXPECT_EQ(ReadCsv(path).values, Eigen::MatrixXd::Constant(2, kWide, 1.0));  // untouched
  // A header alone too long: 2 channels of 600,000-byte names, refused
  // before any file is created (the values would fit).
  series.channel_names = {std::string(600000, 'a'), std::string(600000, 'b')};
  series.values = Eigen::MatrixXd::Zero(2, 2);
  PODID_EXPECT_THROW_WITH(WriteCsv(dir.File("long.csv"), series), std::invalid_argument,
                          "got a header of 1200003 bytes (2 channels)");
  EXPECT_EQ(dir.Entries().size(), 1u);
}

TEST(ReadCsv, AcceptsCrlfSpacesAndBlankLines) {
  const TempDir dir;
  const auto path = dir.Write("a.csv", "time, w1 ,w2\r\n0, 1,+2\r\n\r\n0.1 ,3, 4e0\r\n");
  const TimeSeries series = ReadCsv(path);
  EXPECT_EQ(series.channel_names, (std::vector<std::string>{"w1", "w2"}));
  EXPECT_EQ(series.values, (Eigen::Matrix2d() << 1, 2, 3, 4).finished());
  EXPECT_EQ(series.time_s, Eigen::Vector2d(0, 0.1));
}

TEST(WriteCsv, NamesThatReadBackOnlyQuotedAreQuoted) {
  // Names with a comma, a quote, outer blanks or the look of a number were
  // refused ("w,1") or written so that ReadCsv split, trimmed or refused them.
  const TempDir dir;
  TimeSeries series;
  series.time_s = Eigen::Vector2d(0, 0.5);
  series.channel_names = {"w1", "a,b", "say \"hi\"", " padded ", "1", "nan", "1+X"};
  series.values = Eigen::MatrixXd::Zero(2, 7);
  series.values.row(1).setLinSpaced(1.0, 7.0);
  const std::string path = dir.File("names.csv");
  WriteCsv(path, series);
  const std::string text = ReadText(path);
  EXPECT_EQ(text.substr(0, text.find('\n')),
            "t,w1,\"a,b\",\"say \"\"hi\"\"\",\" padded \",\"1\",\"nan\",1+X");
  const TimeSeries back = ReadCsv(path);
  EXPECT_EQ(back.channel_names, series.channel_names);
  EXPECT_EQ(back.values, series.values);
  EXPECT_EQ(back.time_s, series.time_s);
}

TEST(ReadCsv, AcceptsQuotedNamesAsRWritesThem) {
  // R's write.csv(x, row.names = FALSE) quotes every name of the header; the
  // first name "t" was refused ("expected a header line whose first name is").
  const TempDir dir;
  const TimeSeries series =
      ReadCsv(dir.Write("r.csv", "\"t\",\"w1\", \"acc, x\" ,\"12\"\n0,1,2,3\n0.5,4,5,6\n"));
  EXPECT_EQ(series.channel_names, (std::vector<std::string>{"w1", "acc, x", "12"}));
  EXPECT_EQ(series.values, (Eigen::Matrix<double, 2, 3>() << 1, 2, 3, 4, 5, 6).finished());
  EXPECT_EQ(series.time_s, Eigen::Vector2d(0, 0.5));
}

TEST(ReadCsv, AcceptsAUtf8ByteOrderMark) {
  // Spreadsheets start a UTF-8 CSV with EF BB BF; it was read as part of the
  // first name ("expected a header line whose first name is \"t\"").
  const TempDir dir;
  const TimeSeries series = ReadCsv(dir.Write("bom.csv", "\xEF\xBB\xBFt,w1\n0,1\n0.5,2\n"));
  EXPECT_EQ(series.channel_names, std::vector<std::string>{"w1"});
  EXPECT_EQ(series.time_s, Eigen::Vector2d(0, 0.5));
  // Columns in messages still count its bytes: "x" starts at byte 4.
  PODID_EXPECT_THROW_WITH(ReadCsv(dir.Write("bom2.csv", "\xEF\xBB\xBFx,w1\n0,1\n")),
                          std::invalid_argument,
                          "bom2.csv:1:4: expected a header line whose first name is");
}

// --- CSV: each rejection names file:line:column ------------------------------

class ReadCsvRejects : public ::testing::Test {
 protected:
  std::string Write(const std::string& text) { return dir_.Write("bad.csv", text); }
  const TempDir dir_;
};

#define EXPECT_CSV_ERROR(text, needle)                                 \
  PODID_EXPECT_THROW_WITH(ReadCsv(Write(text)), std::invalid_argument, \
                          dir_.File("bad.csv") + std::string(needle))

TEST_F(ReadCsvRejects, NonNumericCell) {
  EXPECT_CSV_ERROR("t,w1,w2\n0,1,2\n0.1,abc,2\n",
                   ":3:5: expected a number in column w1, got \"abc\"");
  EXPECT_CSV_ERROR("t,w1,w2\n0,1,2\n0.1,1.5x,2\n",
                   ":3:5: expected a number in column w1, got \"1.5x\"");
  EXPECT_CSV_ERROR("t,w1,w2\n0,1,2\n0.1,,2\n",
                   ":3:5: expected a number in column w1, got an empty cell");
  EXPECT_CSV_ERROR("t,w1,w2\n0,1,2\n0.1,1 2,2\n",
                   ":3:5: expected a number in column w1, got \"1 2\"");
}

TEST_F(ReadCsvRejects, RaggedRows) {
  EXPECT_CSV_ERROR("t,w1,w2\n0,1,2\n0.1,1\n",
                   ":3:6: expected 3 cells as in the header, got 2 cells (a ragged row)");
  EXPECT_CSV_ERROR("t,w1,w2\n0,1,2,3\n0.1,1,2\n",
                   ":2:6: expected 3 cells as in the header, got more cells (a ragged row)");
}

TEST_F(ReadCsvRejects, NanAndInf) {
  EXPECT_CSV_ERROR("t,w1\n0,nan\n0.1,1\n",
                   ":2:3: expected a finite number in column w1, got \"nan\"");
  EXPECT_CSV_ERROR("t,w1\n0,1\n0.1,-inf\n",
                   ":3:5: expected a finite number in column w1, got \"-inf\"");
  EXPECT_CSV_ERROR("t,w1\n0,1\n0.1,1e999\n",
                   ":3:5: expected a finite number in column w1, got \"1e999\"");
  EXPECT_CSV_ERROR("t,w1\ninf,1\n0.1,1\n",
                   ":2:1: expected a finite number in column t, got \"inf\"");
}

TEST_F(ReadCsvRejects, FewerThanTwoSamples) {
  EXPECT_CSV_ERROR("t,w1\n0,1\n", ":3:1: expected at least 2 samples, got 1");
  EXPECT_CSV_ERROR("t,w1\n", ":2:1: expected at least 2 samples, got 0");
}

TEST_F(ReadCsvRejects, MissingHeader) {
  EXPECT_CSV_ERROR("0,1,2\n0.1,1,2\n",
                   ":1:1: expected a header line such as \"t,w1,w2\", got a row of numbers (the "
                   "header is missing)");
  EXPECT_CSV_ERROR("", ":1:1: expected a header line such as \"t,w1,w2\", got an empty file");
  EXPECT_CSV_ERROR("x,w1\n0,1\n0.1,2\n",
                   ":1:1: expected a header line whose first name is \"t\" or \"time\", got \"x\"");
  EXPECT_CSV_ERROR("t,w1,,w3\n",
                   ":1:6: expected a header line such as \"t,w1,w2\", got an empty column name");
  EXPECT_CSV_ERROR("t,w1,w1\n", ":1:6: expected distinct column names, got \"w1\" twice");
  EXPECT_CSV_ERROR("t,w1,\"w1\"\n", ":1:6: expected distinct column names, got \"w1\" twice");
  EXPECT_CSV_ERROR("t,\"w1\n0,1\n",
                   ":1:3: expected a closing quote '\"' for the column name opened here, got the "
                   "end of the line");
  EXPECT_CSV_ERROR("t,\"w1\"x,w2\n0,1,2\n",
                   ":1:7: expected a comma or the end of the line after a quoted column name, got "
                   "\"x\"");
  EXPECT_CSV_ERROR("t,\"\",w2\n",
                   ":1:3: expected a header line such as \"t,w1,w2\", got an empty "
                   "column name");
  EXPECT_CSV_ERROR("t,\"a\tb\"\n", ":1:3: expected column names without control characters");
  EXPECT_CSV_ERROR("t\n0\n1\n", ":1:2: expected a time column and at least one channel");
}

TEST_F(ReadCsvRejects, TimeNotIncreasingOrNotUniform) {
  EXPECT_CSV_ERROR("t,w1\n0,1\n0,1\n", ":3:1: expected an increasing time (after t = 0), got 0");
  EXPECT_CSV_ERROR("t,w1\n0,1\n0.1,1\n0.05,1\n",
                   ":4:1: expected an increasing time (after t = 0.1), got 0.05");
  // A missing sample (io.hpp: steps against the median step, within the
  // stamps' printed rounding and 1e-6 of a step).
  EXPECT_CSV_ERROR("t,w1\n0,1\n0.10,1\n0.20,1\n0.40,1\n",
                   ":5:1: expected a uniform time step 0.1 s (within 0.02 s: the stamps' "
                   "rounding and 1e-06 of a step), got a step of 0.2 s");
  // 1.0000005 is within its rounding (5e-8) and 1e-6 of a step; in a column
  // printed to 5 decimals, a step off by 5 units of the last digit is not
  // (allowed: the two stamps' rounding and twice the column's, 4 units).
  EXPECT_NO_THROW(ReadCsv(Write("t,w1\n0,1\n1,1\n2.0000005,1\n")));
  EXPECT_CSV_ERROR("t,w1\n0,1\n1,1\n2.00005,1\n", ":4:1: expected a uniform time step 1 s");
}

TEST_F(ReadCsvRejects, OverlongLineWithoutReadingIt) {
  std::string text = "t,w1\n0,";
  text.append(10u << 20, '1');  // a 10 MB line
  text += "\n";
  EXPECT_CSV_ERROR(text, ":2:1: expected a line of at most 1048576 bytes, got a longer line");
  std::string header(2u << 20, 'w');
  EXPECT_CSV_ERROR("t," + header, ":1:1: expected a line of at most 1048576 bytes");
}

TEST(ReadCsv, MissingFile) {
  PODID_EXPECT_THROW_WITH(ReadCsv("/nonexistent/x.csv"), std::invalid_argument,
                          "/nonexistent/x.csv: expected a readable CSV file, got \"No such file or "
                          "directory\"");
}

TEST(ReadCsv, LargeFileIsFast) {
  // 50 000 rows x 64 columns (~60 MB): streamed, from_chars. The issue's
  // 10^6-row file is measured by hand (see the report): about 20x this one.
  constexpr int kRows = 50000;
  constexpr int kColumns = 64;
  const TempDir dir;
  TimeSeries series;
  series.time_s = Eigen::VectorXd::LinSpaced(kRows, 0.0, (kRows - 1) * 1e-3);
  series.values = Eigen::MatrixXd::Random(kRows, kColumns - 1);
  for (int j = 1; j < kColumns; ++j) series.channel_names.push_back("c" + std::to_string(j));
  WriteCsv(dir.File("big.csv"), series);
  const auto start = std::chrono::steady_clock::now();
  const TimeSeries read = ReadCsv(dir.File("big.csv"));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // %.12e keeps 13 significant digits: values in [-1, 1] come back to 5e-13.
  constexpr double kPrintTolerance = 5e-13;
  EXPECT_TRUE(testing::ExpectMatricesNear(read.values, series.values, kPrintTolerance));
  // Generous bound (sanitizer builds are ~5x slower); the release figure is ~0.3 s.
  constexpr double kMaxSeconds = 20.0;
  EXPECT_LT(seconds, kMaxSeconds);
  std::printf("ReadCsv: %d x %d in %.3f s\n", kRows, kColumns, seconds);
}

// --- .mat ------------------------------------------------------------------

/// Writes variables (name, rows x cols column-major doubles) with libmatio.
void WriteMat(const std::string& path,
              mat_ft version,
              const std::vector<std::pair<std::string, Eigen::MatrixXd>>& variables) {
  mat_t* mat = Mat_CreateVer(path.c_str(), nullptr, version);
  ASSERT_NE(mat, nullptr) << "cannot create " << path;
  for (const auto& [name, matrix] : variables) {
    size_t dims[2] = {static_cast<size_t>(matrix.rows()), static_cast<size_t>(matrix.cols())};
    Eigen::MatrixXd copy = matrix;
    matvar_t* var =
        Mat_VarCreate(name.c_str(), MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, copy.data(), 0);
    ASSERT_NE(var, nullptr);
    EXPECT_EQ(Mat_VarWrite(mat, var, MAT_COMPRESSION_NONE), 0);
    Mat_VarFree(var);
  }
  Mat_Close(mat);
}

TEST(ReadMat, MatrixAndTimeVectorInEachFormat) {
  const TempDir dir;
  const TimeSeries reference = ReadCsv(DataPath("clean_knl50_T0.1.csv"));
  for (const auto version : {MAT_FT_MAT5, MAT_FT_MAT4, MAT_FT_MAT73}) {
    const std::string path = dir.File("x" + std::to_string(static_cast<int>(version)) + ".mat");
    if (version == MAT_FT_MAT73) {
      mat_t* probe = Mat_CreateVer(path.c_str(), nullptr, version);
      if (probe == nullptr) continue;  // matio built without HDF5
      Mat_Close(probe);
    }
    WriteMat(path, version,
             {{"t", reference.time_s.transpose()},  // a row vector, as MATLAB's 0:dt:T
              {"w", reference.values}});
    const TimeSeries series = ReadMat(path);
    EXPECT_EQ(series.values, reference.values) << path;
    EXPECT_EQ(series.time_s, reference.time_s) << path;
    EXPECT_EQ(series.channel_names, reference.channel_names) << path;
    EXPECT_EQ(ReadTimeSeries(path).values, reference.values);
  }
}

TEST(ReadMat, ScipyFilesWithStructsCellsStringsAndSparseMatrices) {
  // Written by scipy.io.savemat (tests/data/make_scipy_mat.py), an independent
  // writer, beside every array class the structure checks walk through.
  constexpr double kSameProduct = 0.0;  // t = 1e-3 * i in numpy and here: the same double
  constexpr double kLibmSin = 1e-15;    // numpy's sin and std::sin may differ by an ulp
  for (const char* name : {"scipy_rich_v5.mat", "scipy_rich_v5_compressed.mat"}) {
    const TimeSeries series = ReadMat(DataPath(name));
    ASSERT_EQ(series.samples(), 100) << name;
    ASSERT_EQ(series.channels(), 3) << name;
    for (int i = 0; i < 100; ++i) {
      EXPECT_NEAR(series.time_s(i), 1e-3 * i, kSameProduct) << name;
      for (int j = 0; j < 3; ++j) {
        EXPECT_NEAR(series.values(i, j), std::sin(0.1 * i + j), kLibmSin) << name;
      }
    }
  }
}

TEST(ReadMat, SamplingStepInsteadOfTimeAndExplicitNames) {
  const TempDir dir;
  const std::string path = dir.File("x.mat");
  Eigen::MatrixXd data(3, 2);
  data << 1, 2, 3, 4, 5, 6;
  WriteMat(
      path, MAT_FT_MAT5,
      {{"junk", Eigen::MatrixXd::Ones(1, 1)}, {"Y", data}, {"clock", Eigen::Vector3d(1, 2, 3)}});
  MatReadOptions options;
  options.variable = "Y";
  options.step_s = 0.5;
  TimeSeries series = ReadMat(path, options);
  EXPECT_EQ(series.values, data);
  EXPECT_EQ(series.time_s, Eigen::Vector3d(0, 0.5, 1.0));
  EXPECT_EQ(series.channel_names, (std::vector<std::string>{"Y1", "Y2"}));
  options.time_variable = "clock";
  series = ReadMat(path, options);
  EXPECT_EQ(series.time_s, Eigen::Vector3d(1, 2, 3));
  // Three samples 1e308 s apart: the grid overflows.
  options.time_variable.clear();
  options.step_s = 1e308;
  PODID_EXPECT_THROW_WITH(ReadMat(path, options), std::invalid_argument,
                          path +
                              " (sampling step): expected a finite time grid whose step > 0 s "
                              "is at least 1.11e-13 of its largest time (double precision "
                              "resolves it), got a start of 0 s, a step of 1e+308 s and 3 "
                              "samples (up to inf s)");
  // A subnormal step: its rate 1 / step overflows (IsSamplingStep).
  options.step_s = 1e-320;
  PODID_EXPECT_THROW_WITH(ReadMat(path, options), std::invalid_argument,
                          path +
                              " (sampling step): expected a time step whose rate 1 / step is "
                              "finite, got a step of 9.999888672e-321 s");
  DataReadOptions read;
  read.step_s = 1e-320;
  PODID_EXPECT_THROW_WITH(ReadTimeSeries(path, read), std::invalid_argument,
                          "sampling step: expected a finite step > 0 s whose rate 1 / step is "
                          "finite, got 9.999888672e-321");
  read.step_s = 0.0;
  read.rate_Hz = 1e-320;
  PODID_EXPECT_THROW_WITH(ReadTimeSeries(path, read), std::invalid_argument,
                          "sampling rate: expected a finite rate > 0 Hz");
}

TEST(ReadTimeSeries, NotesAChannelWithoutASingleChange) {
  // A dead sensor (all zero) and a stuck one (one value) are named; a channel
  // that moves once, or a file without such channels, gives no note.
  const TempDir dir;
  const std::string path = dir.Write("dead.csv",
                                     "t,a,b,c,d\n"
                                     "0,0,2.5,1,0\n"
                                     "0.1,0,2.5,2,0\n"
                                     "0.2,0,2.5,3,1e-300\n");
  std::vector<std::string> notes;
  const TimeSeries series = ReadTimeSeries(path, DataReadOptions{}, &notes);
  ASSERT_EQ(series.channels(), 4);
  ASSERT_EQ(notes.size(), 2u);
  EXPECT_EQ(notes[0],
            path + ": channel a is zero in all 3 samples: a dead or disconnected sensor?");
  EXPECT_EQ(
      notes[1],
      path + ": channel b is constant (2.5) in all 3 samples: a dead or disconnected sensor?");
  // The note follows the channels kept, in their order.
  DataReadOptions only_c;
  only_c.channels = {"d", "c"};
  notes.clear();
  EXPECT_EQ(ReadTimeSeries(path, only_c, &notes).channels(), 2);
  EXPECT_TRUE(notes.empty()) << notes.front();
  only_c.channels = {"c", "b"};
  ReadTimeSeries(path, only_c, &notes);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("channel b is constant"), std::string::npos) << notes[0];
}

TEST(IsSamplingStep, RequiresAFiniteRate) {
  EXPECT_TRUE(IsSamplingStep(1e-3));
  EXPECT_TRUE(
      IsSamplingStep(std::numeric_limits<double>::min()));  // smallest normal: rate 4.5e307 Hz
  EXPECT_TRUE(IsSamplingStep(std::numeric_limits<double>::max()));  // rate 5.6e-309 Hz, > 0
  EXPECT_FALSE(IsSamplingStep(1e-320));                             // subnormal: 1 / step = inf
  EXPECT_FALSE(IsSamplingStep(0.0));
  EXPECT_FALSE(IsSamplingStep(-1e-3));
  EXPECT_FALSE(IsSamplingStep(std::numeric_limits<double>::infinity()));
  EXPECT_FALSE(IsSamplingStep(std::nan("")));
}

TEST(ReadMat, Rejections) {
  const TempDir dir;
  const std::string path = dir.File("x.mat");
  Eigen::MatrixXd data(3, 2);
  data << 1, 2, 3, 4, 5, 6;
  WriteMat(path, MAT_FT_MAT5, {{"w", data}});
  PODID_EXPECT_THROW_WITH(ReadMat(path), std::invalid_argument,
                          path +
                              ": expected a time vector variable ('t' or 'time') or a sampling "
                              "step (--rate, --step), got neither");
  MatReadOptions options;
  options.variable = "v";
  PODID_EXPECT_THROW_WITH(ReadMat(path, options), std::invalid_argument,
                          path + ": expected a variable 'v' (variables: w), got none");
  WriteMat(path, MAT_FT_MAT5, {{"t", Eigen::Vector4d(0, 1, 2, 3)}, {"w", data}});
  PODID_EXPECT_THROW_WITH(ReadMat(path), std::invalid_argument,
                          path + ": variable 't': expected 3 times (one per sample of 'w'), got 4");
  WriteMat(path, MAT_FT_MAT5, {{"t", Eigen::Vector3d(0, 1, 3)}, {"w", data}});
  PODID_EXPECT_THROW_WITH(ReadMat(path), std::invalid_argument,
                          path + ": variable 't' element 3: expected a uniform time step 1 s");
  WriteMat(path, MAT_FT_MAT5, {{"t", Eigen::Vector3d(0, 1, 1)}, {"w", data}});
  PODID_EXPECT_THROW_WITH(ReadMat(path), std::invalid_argument,
                          "element 3: expected an increasing time (after t = 1), got 1");
  data(1, 1) = std::numeric_limits<double>::quiet_NaN();
  WriteMat(path, MAT_FT_MAT5, {{"t", Eigen::Vector3d(0, 1, 2)}, {"w", data}});
  PODID_EXPECT_THROW_WITH(ReadMat(path), std::invalid_argument,
                          path + ": variable 'w' element 5: expected finite numbers, got nan");
  WriteMat(path, MAT_FT_MAT5, {{"t", Eigen::Vector3d(0, 1, 2)}});
  PODID_EXPECT_THROW_WITH(
      ReadMat(path), std::invalid_argument,
      path + ": expected a numeric matrix or vector variable, or a struct of channels, got only t");
  WriteMat(path, MAT_FT_MAT5, {{"w", Eigen::MatrixXd::Ones(1, 1)}});
  options = {};
  options.step_s = 1.0;
  PODID_EXPECT_THROW_WITH(ReadMat(path, options), std::invalid_argument,
                          "expected a numeric matrix or vector variable, or a struct of channels, "
                          "got only w");
  options.variable = "w";
  PODID_EXPECT_THROW_WITH(ReadMat(path, options), std::invalid_argument,
                          "variable 'w': expected at least 2 samples, got 1");
  options.variable.clear();
  {
    mat_t* mat = Mat_CreateVer(path.c_str(), nullptr, MAT_FT_MAT5);
    size_t dims[2] = {1, 3};
    char text[] = "abc";
    matvar_t* var = Mat_VarCreate("s", MAT_C_CHAR, MAT_T_UINT8, 2, dims, text, 0);
    Mat_VarWrite(mat, var, MAT_COMPRESSION_NONE);
    Mat_VarFree(var);
    Mat_Close(mat);
  }
  options.variable = "s";
  PODID_EXPECT_THROW_WITH(
      ReadMat(path, options), std::invalid_argument,
      "variable 's': expected a real numeric matrix or a struct of channels, got a char array");
  const std::string not_mat = dir.Write("y.mat", "this is not a mat file");
  PODID_EXPECT_THROW_WITH(ReadMat(not_mat), std::invalid_argument,
                          "y.mat: expected a readable MATLAB .mat file");
  PODID_EXPECT_THROW_WITH(ReadTimeSeries(dir.File("y.txt")), std::invalid_argument,
                          "y.txt: expected a time-series file ending in .csv, .mat, .uff or .unv");
}

// --- WriteFileAtomically -----------------------------------------------------

void WriteText(std::ostream& os, const std::string& text) { os << text; }

TEST(WriteFileAtomically, WritesAndReplaces) {
  const TempDir dir;
  const std::string path = dir.File("out.txt");
  WriteFileAtomically(path, [](std::ostream& os) { WriteText(os, "first\n"); });
  EXPECT_EQ(ReadText(path), "first\n");
  WriteFileAtomically(path, [](std::ostream& os) { WriteText(os, "second\n"); });
  EXPECT_EQ(ReadText(path), "second\n");
  EXPECT_EQ(dir.Entries(), std::vector<std::string>{"out.txt"});
  // The usual permissions (0666 minus the umask), not mkstemp's 0600.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  struct stat info {};
  ASSERT_EQ(::stat(path.c_str(), &info), 0);
  EXPECT_EQ(info.st_mode & 0777, 0666u & ~mask);
}

TEST(WriteFileAtomically, MissingFolder) {
  const TempDir dir;
  const std::string path = dir.File("no/such/folder/out.csv");
  PODID_EXPECT_THROW_WITH(WriteFileAtomically(path, [](std::ostream& os) { WriteText(os, "x"); }),
                          std::runtime_error,
                          "cannot write " + path + ": cannot create a temporary file in");
  EXPECT_TRUE(dir.Entries().empty());
}

TEST(WriteFileAtomically, CallbackThrowsMidWrite) {
  const TempDir dir;
  const std::string path = dir.Write("out.csv", "precious\n");
  // More than the 64 KiB buffer, so part of it has reached the temporary file.
  auto write = [](std::ostream& os) {
    os << std::string(1 << 20, 'x');
    throw std::runtime_error("simulation diverged");
  };
  PODID_EXPECT_THROW_WITH(WriteFileAtomically(path, write), std::runtime_error,
                          "cannot write " + path + ": simulation diverged");
  EXPECT_EQ(ReadText(path), "precious\n");
  EXPECT_EQ(dir.Entries(), std::vector<std::string>{"out.csv"});
  // An invalid_argument stays one.
  PODID_EXPECT_THROW_WITH(
      WriteFileAtomically(path, [](std::ostream&) { throw std::invalid_argument("bad input"); }),
      std::invalid_argument, "writing " + path + ": bad input");
  EXPECT_EQ(dir.Entries(), std::vector<std::string>{"out.csv"});
}

TEST(WriteFileAtomically, StreamFailure) {
  const TempDir dir;
  const std::string path = dir.Write("out.csv", "precious\n");
  PODID_EXPECT_THROW_WITH(
      WriteFileAtomically(path, [](std::ostream& os) { os.setstate(std::ios::badbit); }),
      std::runtime_error, "the output stream reported a failure");
  EXPECT_EQ(ReadText(path), "precious\n");
  EXPECT_EQ(dir.Entries(), std::vector<std::string>{"out.csv"});
}

TEST(WriteFileAtomically, DestinationIsAFolder) {
  const TempDir dir;
  std::filesystem::create_directory(dir.File("out"));
  PODID_EXPECT_THROW_WITH(
      WriteFileAtomically(dir.File("out"), [](std::ostream& os) { WriteText(os, "x"); }),
      std::runtime_error, "cannot write " + dir.File("out") + ": it is a folder");
  EXPECT_EQ(dir.Entries(), std::vector<std::string>{"out"});
  PODID_EXPECT_THROW_WITH(WriteFileAtomically(dir.path() + "/", [](std::ostream&) {}),
                          std::invalid_argument, "expected a file name");
}

TEST(WriteFileAtomically, DiskFullLikeWriteError) {
  // RLIMIT_FSIZE makes write() fail with EFBIG once the file would exceed the
  // limit: a real write error in the middle of the data, as on a full disk.
  // Run in a child process (a death-test) so the limit does not leak.
  const TempDir dir;
  const std::string path = dir.Write("out.csv", "precious\n");
  auto child = [&]() {
    std::signal(SIGXFSZ, SIG_IGN);
    rlimit limit{1 << 16, 1 << 16};
    if (::setrlimit(RLIMIT_FSIZE, &limit) != 0) std::_Exit(3);
    try {
      WriteFileAtomically(path, [](std::ostream& os) { os << std::string(1 << 20, 'x'); });
    } catch (const std::runtime_error& e) {
      const std::string message = e.what();
      const bool names_file = message.find(path) != std::string::npos;
      const bool says_why = message.find("too large") != std::string::npos;
      const bool untouched = ReadText(path) == "precious\n";
      std::_Exit(names_file && says_why && untouched ? 0 : 2);
    }
    std::_Exit(1);
  };
  const testing::DeathTestTempRoot child_folders;
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(child(), ::testing::ExitedWithCode(0), "");
  EXPECT_EQ(ReadText(path), "precious\n");
  EXPECT_EQ(dir.Entries(), std::vector<std::string>{"out.csv"});
}

TEST(WriteFileAtomically, ReadOnlyFolder) {
  const TempDir dir;
  const std::string path = dir.Write("out.csv", "precious\n");
  std::filesystem::permissions(
      dir.path(), std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
  // Root (CAP_DAC_OVERRIDE) could write through permission bits, but a folder
  // with no write bit is refused by its mode: no skip as root.
  PODID_EXPECT_THROW_WITH(
      WriteFileAtomically(path, [](std::ostream& os) { WriteText(os, "new\n"); }),
      std::runtime_error, "cannot write " + path + ": cannot create a temporary file in");
  EXPECT_EQ(ReadText(path), "precious\n");
  EXPECT_EQ(dir.Entries(), std::vector<std::string>{"out.csv"});
}

}  // namespace
}  // namespace podid
