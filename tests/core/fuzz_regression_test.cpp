// Inputs found by the fuzz targets in fuzz/ (or while reading the readers for
// them), kept as regression tests: each must end in std::invalid_argument with
// a clear message, in bounded memory, and never in a crash.
#include <gtest/gtest.h>
#include <matio.h>

#include <fstream>

#include <stdexcept>
#include <string>

#include "podid/core/case_file.hpp"
#include "podid/core/io.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

using testing::DataPath;
using testing::TempDir;

// --- .mat ------------------------------------------------------------------

TEST(FuzzRegressionMat, HeaderDimensionsLargerThanTheFileAreRejectedBeforeAllocating) {
  // podid_fuzz_mat, 5 s in: a 388-byte v5 file whose matrix header declares
  // 1075314688 elements. ReadMat sized the result from the header (8.6 GB)
  // before matio read any data. The fuzzed file is now caught by the element
  // check below; a file whose tags are consistent but whose dims are huge is
  // caught by the size check.
  MatReadOptions options;
  options.step_s = 1e-3;
  PODID_EXPECT_THROW_WITH(ReadMat(DataPath("fuzz/mat_huge_dims.mat"), options),
                          std::invalid_argument, "(a corrupt or truncated file)");

  const TempDir dir;
  const std::string path = dir.File("dims.mat");
  {
    mat_t* mat = Mat_CreateVer(path.c_str(), nullptr, MAT_FT_MAT5);
    ASSERT_NE(mat, nullptr);
    double data[10] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
    std::size_t dims[2] = {5, 2};
    matvar_t* var = Mat_VarCreate("w", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, data, 0);
    ASSERT_NE(var, nullptr);
    ASSERT_EQ(Mat_VarWrite(mat, var, MAT_COMPRESSION_NONE), 0);
    Mat_VarFree(var);
    Mat_Close(mat);
  }
  std::string bytes = testing::ReadText(path);
  // The dims subelement: miINT32 (5), 8 bytes, 5 rows, 2 columns.
  const std::string dims_tag("\x05\0\0\0\x08\0\0\0\x05\0\0\0\x02\0\0\0", 16);
  const std::size_t at = bytes.find(dims_tag);
  ASSERT_NE(at, std::string::npos);
  bytes[at + 8 + 3] = '\x40';  // 5 rows -> 0x40000005 rows
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  PODID_EXPECT_THROW_WITH(ReadMat(path, options), std::invalid_argument,
                          "variable 'w': expected dimensions whose data fits the file");
}

TEST(FuzzRegressionMat, ElementTagLargerThanItsParentIsRejectedBeforeMatioAllocatesIt) {
  // podid_fuzz_mat: a 424-byte v5 file whose char array's dims tag declares
  // 0x40000008 bytes; libmatio allocated 2 GB for the dims before reading
  // them. Every element of a v5 file is now checked to fit in its parent.
  MatReadOptions options;
  options.step_s = 1e-3;
  PODID_EXPECT_THROW_WITH(ReadMat(DataPath("fuzz/mat_v5_dims_tag_too_large.mat"), options),
                          std::invalid_argument,
                          "expected a data element of at most 7 bytes, got 8 bytes (a corrupt or "
                          "truncated file)");
}

// --- CSV -------------------------------------------------------------------

TEST(FuzzRegressionCsv, WideHeaderDoesNotAllocateBlocksOfItsWidthTimesSixteenThousand) {
  // A header of 100 000 columns followed by one short row: the reader used to
  // allocate its first block of rows as 16384 x columns doubles (13 GB) before
  // parsing the row. Blocks are now capped at 2^17 doubles.
  const TempDir dir;
  std::string header = "t";
  for (int j = 1; j <= 100000; ++j) header += ",c" + std::to_string(j);
  const std::string path = dir.Write("wide.csv", header + "\n0,1\n1,2\n");
  PODID_EXPECT_THROW_WITH(ReadCsv(path), std::invalid_argument,
                          ":2:4: expected 100001 cells as in the header, got 2 cells");
}

TEST(FuzzRegressionCsv, WideFileIsReadCorrectly) {
  // The capped block holds fewer rows than 16384 for wide files: rows must
  // still land in the right places across block boundaries (2^17 / 3000 = 43
  // rows per block, 100 rows = 3 blocks).
  constexpr int kColumns = 3000;
  constexpr int kRows = 100;
  const TempDir dir;
  std::string text = "t";
  for (int j = 1; j < kColumns; ++j) text += ",c" + std::to_string(j);
  text += '\n';
  for (int i = 0; i < kRows; ++i) {
    text += std::to_string(i);
    for (int j = 1; j < kColumns; ++j) text += "," + std::to_string(i * kColumns + j);
    text += '\n';
  }
  const TimeSeries series = ReadCsv(dir.Write("wide.csv", text));
  ASSERT_EQ(series.samples(), kRows);
  ASSERT_EQ(series.channels(), kColumns - 1);
  for (int i = 0; i < kRows; ++i) {
    EXPECT_EQ(series.time_s(i), i);
    for (int j = 1; j < kColumns; ++j) ASSERT_EQ(series.values(i, j - 1), i * kColumns + j);
  }
}

}  // namespace
}  // namespace podid
