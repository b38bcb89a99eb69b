// Inputs found by the fuzz targets in fuzz/ (or while reading the readers for
// them), kept as regression tests: each must end in std::invalid_argument with
// a clear message, in bounded memory, and never in a crash.
#include <gtest/gtest.h>
#include <matio.h>
#include <zlib.h>

#include <array>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "podid/core/case_file.hpp"
#include "podid/core/io.hpp"
#include "podid/core/model_io.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

using testing::DataPath;
using testing::TempDir;

// --- .mat ------------------------------------------------------------------

/// ReadMat of tests/data/fuzz/<name>, with a sampling step as the fuzz target
/// gives, so that files without a time vector are read as far as they go.
TimeSeries ReadFuzzedMat(const std::string& name) {
  MatReadOptions options;
  options.step_s = 1e-3;
  return ReadMat(DataPath("fuzz/" + name), options);
}

TEST(FuzzRegressionMat, HeaderDimensionsLargerThanTheFileAreRejectedBeforeAllocating) {
  // podid_fuzz_mat, 5 s in: a 388-byte v5 file whose matrix header declares
  // 1075314688 elements. ReadMat sized the result from the header (8.6 GB)
  // before matio read any data. The header walk now rejects the fuzzed file
  // at its array name (a 1 GB tag); a file whose tags are consistent but whose
  // dims are huge is rejected by the walk's element count (below).
  PODID_EXPECT_THROW_WITH(ReadFuzzedMat("mat_huge_dims.mat"), std::invalid_argument,
                          "byte 168: expected the array name: an element of type 1, got an element "
                          "of type 0 and 1075838976 bytes");

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
  // (The check of a numeric array's data, exactly its values, comes first.)
  PODID_EXPECT_THROW_WITH(ReadMat(path), std::invalid_argument,
                          "byte 176: expected the real part: 2147483658 values in an element of a "
                          "numeric type (1-7, 9, 12 or 13), got an element of type 9 and 80 bytes");
}

TEST(FuzzRegressionMat, ElementTagLargerThanItsParentIsRejectedBeforeMatioAllocatesIt) {
  // podid_fuzz_mat: a 424-byte v5 file whose char array's dims tag declares
  // 0x40000008 bytes; libmatio allocated 2 GB for the dims before reading
  // them. Every element of a v5 file is now checked to fit in its parent; this
  // file is rejected before that, at a numeric array whose data element
  // (8 bytes) does not fit in the 7 bytes its mutated parent leaves.
  PODID_EXPECT_THROW_WITH(ReadFuzzedMat("mat_v5_dims_tag_too_large.mat"), std::invalid_argument,
                          "byte 296: expected the real part in at most 7 bytes, got 8 bytes (a "
                          "corrupt or truncated file)");
}

TEST(FuzzRegressionMat, NestedCellDeclaringBillionsOfCellsIsRejectedBeforeMatioAllocatesThem) {
  // podid_fuzz_mat, 1 min in: a 424-byte v5 file whose cell array holds a cell
  // of dimensions 1 x 0xb2f60002; libmatio calloc'ed 24 GB of cell pointers.
  // miMATRIX headers at every depth are now checked against their element.
  PODID_EXPECT_THROW_WITH(ReadFuzzedMat("mat_v5_cell_3e9_elements.mat"), std::invalid_argument,
                          "byte 240: expected non-negative dimensions, got -1292500990");
}

TEST(FuzzRegressionMat, Level4NameLongerThanTheFileIsRejectedBeforeMatOpen) {
  // podid_fuzz_mat: a 292-byte v4 file whose name length is 0x5f000002;
  // Mat_Open itself calloc'ed 1.6 GB for the name (16 s under ASan).
  PODID_EXPECT_THROW_WITH(ReadFuzzedMat("mat_v4_name_length_1_6e9.mat"), std::invalid_argument,
                          "v4 matrix at byte 0: expected a name and data that fit in the 272 bytes "
                          "that follow, got 1593835522 + 80 bytes (a corrupt or truncated file)");
}

/// A level 4 sparse matrix (little-endian, double): the header, the name, then
/// the rows (i, j, value) column by column, the last row (rows, columns, 0).
std::string Mat4Sparse(const std::string& name, const std::vector<std::array<double, 3>>& rows) {
  std::string bytes;
  const auto word = [&](std::int32_t v) { bytes.append(reinterpret_cast<const char*>(&v), 4); };
  word(2);  // MOPT 0002: little-endian, double, sparse
  word(static_cast<std::int32_t>(rows.size()));
  word(3);
  word(0);
  word(static_cast<std::int32_t>(name.size() + 1));
  bytes.append(name.c_str(), name.size() + 1);
  for (int column = 0; column < 3; ++column) {
    for (const auto& row : rows) bytes.append(reinterpret_cast<const char*>(&row[column]), 8);
  }
  return bytes;
}

TEST(FuzzRegressionModel, Level4SparseRowsBeyondTheFileAreRejectedBeforeMatioAllocatesThem) {
  // podid_fuzz_model (CI's fuzz smoke run): a 22-byte v4 file with a sparse
  // matrix "M" of 1073741827 x 0. The structure check sized its data as
  // rows x columns = 0 bytes, and libmatio malloc'ed 4 GB of row indices.
  const ModelFiles files{DataPath("fuzz/mat_v4_sparse_0_columns_1e9_rows.mat"), "M", "K", ""};
  PODID_EXPECT_THROW_WITH(ReadModelMatrices(files), std::invalid_argument,
                          "v4 matrix at byte 0: expected a sparse matrix of at least 2 rows and 3 "
                          "or 4 columns (i, j, value[, imaginary part]), got 1073741827 x 0");
  PODID_EXPECT_THROW_WITH(ReadFuzzedMat("mat_v4_sparse_0_columns_1e9_rows.mat"),
                          std::invalid_argument, "expected a sparse matrix of at least 2 rows");
}

TEST(FuzzRegressionModel, CharDataLargerThanItsArrayIsRejectedBeforeMatioAllocatesIt) {
  // podid_fuzz_model (CI's fuzz smoke run, 2026-11-30): "M" a 3 x 3 char
  // array whose data element declares 3238002760 bytes in a 257-byte file.
  // The walk checked the array's room for 9 characters, not its data
  // element, and libmatio called calloc with the size read as an int and
  // sign-extended: 0xffffffffc1000048 bytes.
  const ModelFiles files{DataPath("fuzz/mat_v5_char_data_of_3e9_bytes.mat"), "M", "K", ""};
  PODID_EXPECT_THROW_WITH(ReadModelMatrices(files), std::invalid_argument,
                          "byte 176: expected the characters: at most 4 bytes each of the 9 in an "
                          "element, got an element of type 9 and 3238002760 bytes");
  PODID_EXPECT_THROW_WITH(ReadFuzzedMat("mat_v5_char_data_of_3e9_bytes.mat"), std::invalid_argument,
                          "expected the characters: at most 4 bytes each");
}

TEST(FuzzRegressionModel, Level4SparseColumnCountFromTheDataIsBounded) {
  // libmatio sizes a v4 sparse matrix's column pointers by its last row's j
  // (4 bytes a column, up to 2^32 - 2 columns: 16 GB) in a file of 80 bytes.
  const TempDir dir;
  const std::string path = dir.File("sparse.mat");
  std::ofstream(path, std::ios::binary) << Mat4Sparse("M", {{1, 1, 5}, {1, 4e9, 0}});
  PODID_EXPECT_THROW_WITH(ReadModelMatrices({path, "M", "K", ""}), std::invalid_argument,
                          "expected a sparse matrix's column count (its last row) in [0, "
                          "134217728], got 4000000000");
  std::ofstream(path, std::ios::binary) << Mat4Sparse("M", {{1, 1, 5}, {-1, 1, 0}});
  PODID_EXPECT_THROW_WITH(ReadModelMatrices({path, "M", "K", ""}), std::invalid_argument,
                          "expected a sparse matrix's row count (its last row) in [0, 134217728], "
                          "got -1");
}

TEST(FuzzRegressionModel, Level4SparseMatricesAreStillRead) {
  // The same layout with sizes that agree: M = diag(2, 1), K = [[3, -1], [-1, 3]].
  const TempDir dir;
  const std::string path = dir.File("model.mat");
  std::ofstream(path, std::ios::binary)
      << Mat4Sparse("M", {{1, 1, 2}, {2, 2, 1}, {2, 2, 0}})
      << Mat4Sparse("K", {{1, 1, 3}, {2, 1, -1}, {1, 2, -1}, {2, 2, 3}, {2, 2, 0}});
  const ImportedMatrices m = ReadModelMatrices({path, "M", "K", ""});
  ASSERT_EQ(m.mass.rows(), 2);
  ASSERT_EQ(m.stiffness.cols(), 2);
  EXPECT_EQ(m.mass.coeff(0, 0), 2.0);
  EXPECT_EQ(m.mass.coeff(1, 1), 1.0);
  EXPECT_EQ(m.mass.coeff(0, 1), 0.0);
  EXPECT_EQ(m.stiffness.coeff(1, 0), -1.0);
  EXPECT_EQ(m.stiffness.coeff(0, 1), -1.0);
  EXPECT_EQ(m.stiffness.coeff(1, 1), 3.0);
}

TEST(FuzzRegressionMat, NonCanonicalLayoutThatMatioReadsDifferentlyIsRejected) {
  // podid_fuzz_mat: a dims tag in the small-element form (768 bytes declared,
  // 4 in the tag). libmatio read it as a normal tag, so the next "dims" it
  // found declared 3e8 dimensions (2.5 GB), while a walk that honoured the
  // small form saw nothing wrong. The walk now takes only the canonical layout.
  PODID_EXPECT_THROW_WITH(
      ReadFuzzedMat("mat_v5_dims_small_element_768_bytes.mat"), std::invalid_argument,
      "byte 152: expected the dimensions: an element of type 5 (not small), got a small element "
      "of type 5 and 768 bytes");
}

TEST(FuzzRegressionMat, CompressedDataFailingItsChecksumIsRejected) {
  // podid_fuzz_mat: a compressed variable whose zlib stream fails its adler32
  // check. The walk dropped the stream and saw no variable; libmatio read the
  // inflated bytes anyway and calloc'ed 2.5 GB from them.
  PODID_EXPECT_THROW_WITH(ReadFuzzedMat("mat_v5_compressed_bad_checksum.mat"),
                          std::invalid_argument,
                          "compressed variable at byte 128, inflated byte 0: expected compressed "
                          "data that inflates, got zlib: incorrect data check");
}

TEST(FuzzRegressionMat, FunctionHandleDeclaringHalfABillionElementsIsRejected) {
  // podid_fuzz_mat: a 224-byte v5 file whose array of class 16 (a function
  // handle, which libmatio reads as a cell array) declares 1 x 536870933
  // elements: libmatio malloc'ed 4 GB of pointers for them.
  PODID_EXPECT_THROW_WITH(
      ReadFuzzedMat("mat_v5_function_handle_5e8_elements.mat"), std::invalid_argument,
      "byte 176: expected a cell array whose 536870933 elements fit in the 48 bytes that follow");
}

TEST(FuzzRegressionMat, FunctionHandleCellsAreFreed) {
  // podid_fuzz_mat, a LeakSanitizer report: libmatio before 1.5.25 frees a
  // function handle's array of cells but not the cells (Debian 12 has 1.5.23).
  // The file is valid: int16 w (3 x 2), a function handle c of two cells, and
  // char s; w is read. Under AddressSanitizer (the CI's sanitizer build) the
  // leak fails this test binary at exit.
  const TimeSeries series = ReadFuzzedMat("mat_v5_function_handle_two_cells.mat");
  EXPECT_EQ(series.channel_names, (std::vector<std::string>{"w1", "w2"}));
  ASSERT_EQ(series.samples(), 3);
  EXPECT_EQ(series.values(2, 1), 5.0);  // column-major int16 0, 2, 4, 1, 3, 5
}

TEST(FuzzRegressionMat, FunctionHandlePassedOverIsFreed) {
  // podid_fuzz_mat, a LeakSanitizer report (322 bytes) on a file like the one
  // above with its data after the function handle: Mat_VarRead(name) passed
  // over c and freed it with libmatio's own Mat_VarFree, leaking c's cells.
  // ReadMat now reads each variable in place from its listing, and every
  // variable is freed with FreeMatVar. The file (made by a script): the
  // function handle c of two cells, then a double x = 1 2 3 4.
  const TimeSeries series = ReadFuzzedMat("mat_v5_function_handle_before_the_data.mat");
  EXPECT_EQ(series.channel_names, (std::vector<std::string>{"x"}));
  ASSERT_EQ(series.samples(), 4);
  EXPECT_EQ(series.values(3, 0), 4.0);
}

TEST(FuzzRegressionMat, NumericDataOfTheWrongTypeOrCountIsRejected) {
  // The same fuzzer run: a double 1 x 4 whose data was a 4-byte miUTF8
  // element. libmatio converts no UTF-8 to double and returned the array as
  // malloc'ed (a heap pointer, 4.6e-310, came out as a sample). libmatio also
  // reads as many values as the dimensions say whatever the element holds:
  // 2 doubles for 4 values read 16 bytes of the next variable.
  PODID_EXPECT_THROW_WITH(ReadFuzzedMat("mat_v5_double_with_utf8_data.mat"), std::invalid_argument,
                          "byte 176: expected the real part: 4 values in an element of a numeric "
                          "type (1-7, 9, 12 or 13), got a small element of type 16 and 4 bytes");
  PODID_EXPECT_THROW_WITH(ReadFuzzedMat("mat_v5_double_with_two_of_four_values.mat"),
                          std::invalid_argument,
                          "byte 176: expected the real part: 4 values in an element of a numeric "
                          "type (1-7, 9, 12 or 13), got an element of type 9 and 16 bytes");
}

TEST(FuzzRegressionMat, NamelessVariableIsRejectedInsteadOfCrashing) {
  // podid_fuzz_mat, a SEGV in podid: the first variable is an empty miMATRIX
  // element, which libmatio lists with a null name; comparing the next
  // variable's name with it ran strlen(nullptr).
  PODID_EXPECT_THROW_WITH(ReadFuzzedMat("mat_v5_nameless_variable.mat"), std::invalid_argument,
                          "expected a name for every variable, got variable 1 without one");
}

TEST(FuzzRegressionMat, TwoVariablesOfOneNameAreRejectedInsteadOfOverflowing) {
  // podid_fuzz_mat, a heap-buffer-overflow in podid: a file with two variables
  // named 't' (1 x 21, then 5 x 2). The second was taken as the data and sized
  // 5 x 2 from the listing, but Mat_VarRead(name) read the first: 21 doubles
  // were copied into 10. Names must now be distinct, and the data read must
  // have the listed size. The fuzzed file's first t holds 5 of its 21 values
  // (rejected by the walk now); the same two variables written by libmatio:
  PODID_EXPECT_THROW_WITH(ReadFuzzedMat("mat_v5_two_variables_named_t.mat"), std::invalid_argument,
                          "byte 176: expected the real part: 21 values");
  const TempDir dir;
  const std::string path = dir.File("two_t.mat");
  {
    mat_t* mat = Mat_CreateVer(path.c_str(), nullptr, MAT_FT_MAT5);
    ASSERT_NE(mat, nullptr);
    double data[21] = {};
    std::size_t first[2] = {1, 21}, second[2] = {5, 2};
    for (const auto& [name, dims] : {std::pair{"t", first}, std::pair{"u", second}}) {
      matvar_t* var = Mat_VarCreate(name, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, data, 0);
      ASSERT_NE(var, nullptr);
      ASSERT_EQ(Mat_VarWrite(mat, var, MAT_COMPRESSION_NONE), 0);
      Mat_VarFree(var);
    }
    Mat_Close(mat);
  }
  // libmatio writes no two variables of one name: rename u (a small miINT8 name element) to t.
  std::string bytes = testing::ReadText(path);
  const std::size_t at = bytes.find(std::string("\x01\0\x01\0u\0\0\0", 8));
  ASSERT_NE(at, std::string::npos);
  bytes[at + 4] = 't';
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  PODID_EXPECT_THROW_WITH(ReadMat(path), std::invalid_argument,
                          "expected variables with distinct names, got 't' twice");
}

TEST(FuzzRegressionMat, CompressedCellDeclaringMoreCellsThanItHoldsIsRejected) {
  // The same check inside an miCOMPRESSED element, which is inflated as a
  // stream: a cell of 1 x 10^8 cells in a 70-byte compressed variable.
  auto word = [](std::string& out, std::uint32_t v) { out.append(reinterpret_cast<char*>(&v), 4); };
  std::string matrix;  // miMATRIX content: flags (cell), dims 1 x 1e8, name "c"
  word(matrix, 6), word(matrix, 8), word(matrix, 1), word(matrix, 0);
  word(matrix, 5), word(matrix, 8), word(matrix, 1), word(matrix, 100000000);
  word(matrix, 1 << 16 | 1), word(matrix, 'c');
  std::string element;
  word(element, 14), word(element, static_cast<std::uint32_t>(matrix.size()));
  element += matrix;
  std::string deflated(compressBound(element.size()), '\0');
  uLongf deflated_size = deflated.size();
  ASSERT_EQ(compress(reinterpret_cast<Bytef*>(deflated.data()), &deflated_size,
                     reinterpret_cast<const Bytef*>(element.data()), element.size()),
            Z_OK);
  deflated.resize(deflated_size);
  std::string file(116, ' ');
  file.replace(0, 10, "MATLAB 5.0");
  file.append(8, '\0');
  file += std::string("\x00\x01IM", 4);
  word(file, 15), word(file, static_cast<std::uint32_t>(deflated.size()));
  file += deflated;
  const TempDir dir;
  const std::string path = dir.Write("compressed_cell.mat", file);
  MatReadOptions options;
  options.step_s = 1e-3;
  PODID_EXPECT_THROW_WITH(
      ReadMat(path, options), std::invalid_argument,
      "compressed variable at byte 128, inflated byte 48: expected a cell array "
      "whose 100000000 elements fit in the 0 bytes that follow, got more (a "
      "corrupt or truncated file)");
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

// --- case files --------------------------------------------------------------

// The case fuzzer's input as fuzz/case_fuzzer.cpp reads it: TOML, then
// "---" and --set lines. Returns the message of the std::invalid_argument.
std::string CaseFuzzerMessage(const std::string& input) {
  const std::size_t separator = input.find("\n---\n");
  try {
    CaseDocument document = CaseDocument::Parse(input.substr(0, separator), "fuzz.toml");
    if (separator != std::string::npos) {
      std::string sets = input.substr(separator + 5);
      while (!sets.empty()) {
        const std::size_t end = sets.find('\n');
        document.Set(sets.substr(0, sets.find('=')),
                     sets.substr(sets.find('=') + 1, end - sets.find('=') - 1));
        sets = end == std::string::npos ? "" : sets.substr(end + 1);
      }
    }
    document.ToSpec();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

// Issue 10 item 8: a 40,000-level dotted key overflowed toml++'s stack
// (16,000 levels took 14 s); the seeds fuzz/corpus/case/deep_*.toml keep the
// fuzzer on the depth check.
TEST(FuzzRegressionCase, DeepTomlIsRejectedBeforeToml) {
  std::string key = "a";
  for (int i = 1; i < 40'000; ++i) key += ".a";
  EXPECT_NE(CaseFuzzerMessage("[beam]\n" + key + " = 1\n").find(
                "fuzz.toml:2: expected TOML nested at most 32 levels deep"),
            std::string::npos);
  for (const char* seed : {"deep_dotted_key.toml", "deep_arrays_tables.toml", "deep_set.toml"}) {
    std::ifstream in(testing::ExamplePath(std::string("../fuzz/corpus/case/") + seed),
                     std::ios::binary);
    ASSERT_TRUE(in) << seed;
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(CaseFuzzerMessage(text).find("expected TOML nested at most 32 levels deep"),
              std::string::npos)
        << seed << ": " << CaseFuzzerMessage(text);
  }
}

}  // namespace
}  // namespace podid
