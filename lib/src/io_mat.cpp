// MATLAB .mat time series through libmatio: the file's variables, the choice
// of what to read, numeric matrices and vectors (structs: io_mat_struct.cpp).
#include <matio.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "io_internal.hpp"
#include "io_mat_internal.hpp"
#include "mat_structure.hpp"
#include "podid/core/error.hpp"
#include "podid/core/io.hpp"

namespace podid {
namespace internal {

namespace {

/// Whether the loaded libmatio leaks function handles' cells (before 1.5.25).
bool MatioLeaksFunctionCells() {
  static const bool leaks = [] {
    int major = 0, minor = 0, release = 0;
    Mat_GetLibraryVersion(&major, &minor, &release);
    return major * 10000 + minor * 100 + release < 10525;
  }();
  return leaks;
}

/// Frees the cells of the function handles in `var` (any depth) and leaves
/// their arrays, which Mat_VarFree frees, empty. Cells, struct fields and
/// function handles hold an array of nbytes / data_size matvar_t pointers.
void FreeFunctionCells(matvar_t* var) {
  const bool holds_vars = var->class_type == MAT_C_CELL || var->class_type == MAT_C_STRUCT ||
                          var->class_type == MAT_C_FUNCTION;
  if (!holds_vars || var->mem_conserve || var->data == nullptr ||
      var->data_size != sizeof(matvar_t*)) {
    return;
  }
  auto** children = static_cast<matvar_t**>(var->data);
  const std::size_t count = var->nbytes / sizeof(matvar_t*);
  for (std::size_t i = 0; i < count; ++i) {
    if (children[i] == nullptr) continue;
    FreeFunctionCells(children[i]);
    if (var->class_type == MAT_C_FUNCTION) {
      Mat_VarFree(children[i]);
      children[i] = nullptr;
    }
  }
}

}  // namespace

void FreeMatVar(matvar_t* var) {
  if (var == nullptr) return;
  if (MatioLeaksFunctionCells()) FreeFunctionCells(var);
  Mat_VarFree(var);
}

MatVarPtr ReadMatVar(mat_t* mat, const std::string& name) {
  // One pass over the headers; the variable's data is then read in place from
  // the position its header recorded, as ReadMat reads its variables.
  if (Mat_Rewind(mat) != 0) return nullptr;
  while (MatVarPtr var{Mat_VarReadNextInfo(mat)}) {
    if (var->name == nullptr || name != var->name) continue;
    return Mat_VarReadDataAll(mat, var.get()) == 0 ? std::move(var) : nullptr;
  }
  return nullptr;
}

std::size_t MatElements(const matvar_t& var) {
  std::size_t n = 1;
  for (int i = 0; i < var.rank; ++i) n *= var.dims[i];
  return n;
}

bool IsMatNumeric(const matvar_t& var) {
  return var.class_type >= MAT_C_DOUBLE && var.class_type <= MAT_C_UINT64 && !var.isComplex &&
         var.rank == 2;
}

std::string MatClassText(const matvar_t& var) {
  switch (var.class_type) {
    case MAT_C_CELL:
      return "a cell array";
    case MAT_C_STRUCT:
      return "a struct";
    case MAT_C_CHAR:
      return "a char array";
    case MAT_C_SPARSE:
      return "a sparse matrix";
    case MAT_C_EMPTY:
      return "an empty array";
    default:
      break;
  }
  if (var.isComplex) return "a complex matrix";
  if (var.rank != 2) return "an array of rank " + std::to_string(var.rank);
  if (IsMatNumeric(var)) return "a numeric matrix";
  return "an object of matio class " + std::to_string(static_cast<int>(var.class_type));
}

namespace {

template <typename T>
void Convert(const void* data, std::size_t n, std::vector<double>& out) {
  const T* p = static_cast<const T*>(data);
  out.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<double>(p[i]);
}

void AppendUtf8(std::string& out, std::uint32_t c) {
  if (c < 0x80) {
    out += static_cast<char>(c);
  } else if (c < 0x800) {
    out += static_cast<char>(0xC0 | (c >> 6));
    out += static_cast<char>(0x80 | (c & 0x3F));
  } else {
    out += static_cast<char>(0xE0 | (c >> 12));
    out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (c & 0x3F));
  }
}

}  // namespace

std::vector<double> MatDoubles(const matvar_t& var, const std::string& where) {
  const std::size_t n = MatElements(var);
  if (n > 0 && var.data == nullptr) ThrowInvalid(where, "readable numeric data", "a read failure");
  if (var.nbytes / std::max(1, var.data_size) < n && var.data_size > 0) {
    ThrowInvalid(where, std::to_string(n) + " elements of data",
                 std::to_string(var.nbytes / var.data_size));
  }
  std::vector<double> out;
  switch (var.data_type) {
    case MAT_T_DOUBLE:
      Convert<double>(var.data, n, out);
      break;
    case MAT_T_SINGLE:
      Convert<float>(var.data, n, out);
      break;
    case MAT_T_INT8:
      Convert<std::int8_t>(var.data, n, out);
      break;
    case MAT_T_UINT8:
      Convert<std::uint8_t>(var.data, n, out);
      break;
    case MAT_T_INT16:
      Convert<std::int16_t>(var.data, n, out);
      break;
    case MAT_T_UINT16:
      Convert<std::uint16_t>(var.data, n, out);
      break;
    case MAT_T_INT32:
      Convert<std::int32_t>(var.data, n, out);
      break;
    case MAT_T_UINT32:
      Convert<std::uint32_t>(var.data, n, out);
      break;
    case MAT_T_INT64:
      Convert<std::int64_t>(var.data, n, out);
      break;
    case MAT_T_UINT64:
      Convert<std::uint64_t>(var.data, n, out);
      break;
    default:
      ThrowInvalid(where, "numeric data",
                   "matio data type " + std::to_string(static_cast<int>(var.data_type)));
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(out[i])) {
      ThrowInvalid(where + " element " + std::to_string(i + 1), "finite numbers", ToText(out[i]));
    }
  }
  return out;
}

std::string MatText(const matvar_t* var) {
  if (var == nullptr || var->class_type != MAT_C_CHAR || var->rank != 2 || var->data == nullptr)
    return "";
  const std::size_t rows = var->dims[0], cols = var->dims[1];
  const std::size_t n = rows * cols;
  const bool wide = var->data_type == MAT_T_UINT16 || var->data_type == MAT_T_INT16 ||
                    var->data_type == MAT_T_UTF16;
  const bool narrow =
      var->data_type == MAT_T_UINT8 || var->data_type == MAT_T_INT8 || var->data_type == MAT_T_UTF8;
  if ((!wide && !narrow) || var->nbytes < n * (wide ? 2 : 1)) return "";
  std::string out;
  for (std::size_t r = 0; r < rows; ++r) {
    if (r > 0) out += '\n';
    std::string row;
    for (std::size_t c = 0; c < cols; ++c) {
      const std::size_t at = r + c * rows;  // column-major
      if (wide) {
        AppendUtf8(row, static_cast<const std::uint16_t*>(var->data)[at]);
      } else {
        row += static_cast<const char*>(var->data)[at];
      }
    }
    out += CleanText(row);
  }
  return out;
}

Eigen::MatrixXd ConcatenateChannels(std::vector<Eigen::MatrixXd>& blocks, Eigen::Index samples) {
  Eigen::Index channels = 0;
  for (const auto& b : blocks) channels += b.cols();
  Eigen::MatrixXd values(samples, channels);
  for (Eigen::Index at = 0; auto& b : blocks) {
    values.middleCols(at, b.cols()) = b;
    at += b.cols();
    b.resize(0, 0);
  }
  return values;
}

Eigen::VectorXd MatTimeVector(const std::vector<double>& t,
                              matio_classes time_class,
                              const std::string& where) {
  // Half a unit in the last place of the stored precision.
  const double relative = time_class == MAT_C_SINGLE ? 0.5 * 1.1920929e-7 : 0.0;
  const UniformGrid grid = FitUniformGrid(
      t.data(), t.size(), [&](std::size_t i) { return relative * std::abs(t[i]); },
      [&](std::size_t i) { return where + " element " + std::to_string(i + 1); });
  return GridOrStamps(t.data(), t.size(), grid);
}

namespace {

using MatPtr = std::unique_ptr<mat_t, decltype([](mat_t* mat) { Mat_Close(mat); })>;

/// Largest ratio of uncompressed to compressed size that deflate reaches.
constexpr double kMaxDeflateRatio = 1032.0;

/// Throws when a variable's declared size (numeric and char arrays at any depth
/// of structs and cells) cannot be stored in a file of `file_bytes` (each
/// element takes at least one byte, as int8, times the deflate ratio when
/// compressed) or exceeds kMaxReadValues. Checked before anything is read.
void CheckDeclaredSize(const matvar_t& var,
                       bool may_be_compressed,
                       double file_bytes,
                       const std::string& path) {
  double elements = 0.0;
  const auto count = [&](const auto& self, const matvar_t& v, int depth) -> void {
    if (depth > 64) return;  // mat_structure.cpp bounds the depth of v5 files
    double n = 1.0;
    for (int i = 0; i < v.rank; ++i) n *= static_cast<double>(v.dims[i]);
    if (v.class_type == MAT_C_STRUCT || v.class_type == MAT_C_CELL) {
      if (v.data == nullptr) return;
      const double children = v.class_type == MAT_C_STRUCT
                                  ? n * Mat_VarGetNumberOfFields(const_cast<matvar_t*>(&v))
                                  : n;
      auto* const* cells = static_cast<matvar_t* const*>(v.data);
      const double available = static_cast<double>(v.nbytes / sizeof(matvar_t*));
      for (double i = 0; i < std::min(children, available); ++i) {
        if (cells[static_cast<std::size_t>(i)] != nullptr)
          self(self, *cells[static_cast<std::size_t>(i)], depth + 1);
      }
    } else if (v.class_type != MAT_C_SPARSE) {
      elements += n * (v.isComplex ? 2.0 : 1.0);
    }
  };
  count(count, var, 0);
  const std::string where = path + ": variable '" + std::string(var.name ? var.name : "") + "'";
  const double limit = may_be_compressed ? file_bytes * kMaxDeflateRatio : file_bytes;
  if (elements > limit) {
    ThrowInvalid(where, "dimensions whose data fits the file (" + ToText(file_bytes) + " bytes)",
                 ToText(elements) + " elements (a corrupt header)");
  }
  if (elements > static_cast<double>(kMaxReadValues)) {
    ThrowInvalid(where,
                 "at most " + std::to_string(kMaxReadValues) +
                     " values (podid's memory budget, kMaxReadValues)",
                 ToText(elements));
  }
}

/// Samples x channels from a matrix, given the number of samples if known
/// (0: the longer dimension, rows on a tie).
Eigen::MatrixXd Oriented(const std::vector<double>& data,
                         std::size_t rows,
                         std::size_t cols,
                         std::size_t samples,
                         const std::string& where) {
  bool transpose = false;
  if (samples == 0) {
    transpose = cols > rows;
  } else if (rows == samples) {
    transpose = false;
  } else if (cols == samples) {
    transpose = true;
  } else {
    ThrowInvalid(where, "a matrix with " + std::to_string(samples) + " samples (rows or columns)",
                 std::to_string(rows) + " x " + std::to_string(cols));
  }
  const Eigen::Map<const Eigen::MatrixXd> m(data.data(), static_cast<Eigen::Index>(rows),
                                            static_cast<Eigen::Index>(cols));
  if (transpose) return m.transpose();
  return m;
}

/// The data of a variable as listed (Mat_VarReadNextInfo), read in place from
/// the position the listing recorded: each variable is found once, in one
/// pass over the headers, where a read by name would pass over the headers
/// before it again (a file of 1000 vectors: 2.7 s by name, 0.042 s in place).
void ReadListedData(mat_t* mat, matvar_t* listed, const std::string& where) {
  if (Mat_VarReadDataAll(mat, listed) != 0) {
    ThrowInvalid(where, "readable data", "a read failure");
  }
}

/// The values of a listed numeric variable, which is then freed (`listed`
/// reset: a file's variables are converted one at a time).
std::vector<double> ReadNumeric(mat_t* mat, const std::string& path, MatVarPtr& listed) {
  const std::string where = path + ": variable '" + std::string(listed->name) + "'";
  ReadListedData(mat, listed.get(), where);
  std::vector<double> values = MatDoubles(*listed, where);
  listed.reset();
  return values;
}

}  // namespace

TimeSeries ReadMatFile(const std::string& path,
                       const std::string& variable,
                       const std::string& time_variable,
                       double step_s,
                       bool* has_time,
                       std::vector<std::string>* notes) {
  internal::RequireRegularFile(path, "a readable .mat file");
  // libmatio allocates what the headers declare, from Mat_Open on: check them
  // against the file first (v5, v4 here; v7.3 with libhdf5).
  CheckMatStructure(path);
  std::optional<Hdf5Quiet> quiet;
  if (CheckMat73Storage(path)) quiet.emplace();
  MatPtr mat(Mat_Open(path.c_str(), MAT_ACC_RDONLY));
  if (!mat)
    ThrowInvalid(path, "a readable MATLAB .mat file (v4, v5 or v7.3)", "a file matio cannot open");

  struct stat file_status {};
  const double file_bytes =
      ::stat(path.c_str(), &file_status) == 0 ? static_cast<double>(file_status.st_size) : 0.0;
  const bool v73 = Mat_GetVersion(mat.get()) == MAT_FT_MAT73;

  std::vector<MatVarPtr> vars;  // information only, no data
  std::string names;
  while (true) {
    MatVarPtr var(Mat_VarReadNextInfo(mat.get()));
    if (!var) break;
    // Variables are chosen by name (the data, t, time): a nameless one could not be.
    if (var->name == nullptr || var->name[0] == '\0') {
      ThrowInvalid(path, "a name for every variable",
                   "variable " + std::to_string(vars.size() + 1) + " without one");
    }
    const std::string name = var->name;
    CheckDeclaredSize(*var, v73 || var->compression != MAT_COMPRESSION_NONE, file_bytes, path);
    for (const auto& v : vars) {
      // A variable is chosen by name: a second one of that name would be ambiguous.
      if (name == v->name)
        ThrowInvalid(path, "variables with distinct names", "'" + name + "' twice");
    }
    names += (names.empty() ? "" : ", ") + CleanText(name);
    vars.push_back(std::move(var));
  }
  auto owner = [&](const matvar_t* v) -> MatVarPtr& {
    return *std::find_if(vars.begin(), vars.end(),
                         [v](const MatVarPtr& p) { return p.get() == v; });
  };
  auto find = [&](const std::string& name) -> matvar_t* {
    for (const auto& v : vars) {
      if (name == v->name) return v.get();
    }
    return nullptr;
  };

  // The time vector.
  const matvar_t* time = nullptr;
  if (!time_variable.empty()) {
    time = find(time_variable);
    if (time == nullptr) {
      ThrowInvalid(path, "a time variable '" + time_variable + "' (variables: " + names + ")",
                   "none");
    }
  } else {
    time = find("t");
    if (time == nullptr) time = find("time");
  }

  // What to read: one matrix, the vectors of one length, or a struct.
  std::vector<matvar_t*> columns;  // numeric variables, each a channel or a matrix of channels
  matvar_t* group = nullptr;       // a struct
  if (!variable.empty()) {
    matvar_t* v = find(variable);
    if (v == nullptr) {
      ThrowInvalid(path, "a variable '" + variable + "' (variables: " + names + ")", "none");
    }
    if (v->class_type == MAT_C_STRUCT) {
      group = v;
    } else if (IsMatNumeric(*v)) {
      columns.push_back(v);
    } else {
      ThrowInvalid(path + ": variable '" + variable + "'",
                   "a real numeric matrix or a struct of channels", MatClassText(*v));
    }
  } else {
    for (const auto& v : vars) {
      if (v.get() == time || !IsMatNumeric(*v) || MatElements(*v) < 2) continue;
      const bool vector = v->dims[0] == 1 || v->dims[1] == 1;
      if (columns.empty()) {
        columns.push_back(v.get());
        if (!vector) break;
      } else if (vector && MatElements(*v) == MatElements(*columns[0])) {
        columns.push_back(v.get());
      }
    }
    if (columns.empty()) {
      for (const auto& v : vars) {
        if (v->class_type == MAT_C_STRUCT && IsMatSeriesStruct(*v)) {
          group = v.get();
          break;
        }
      }
    }
    if (columns.empty() && group == nullptr) {
      ThrowInvalid(path, "a numeric matrix or vector variable, or a struct of channels",
                   vars.empty() ? std::string("no variables") : "only " + names);
    }
  }

  if (group != nullptr) {
    if (time != nullptr && !time_variable.empty()) {
      ThrowInvalid(path,
                   "a time variable only with a matrix (the struct '" + std::string(group->name) +
                       "' has its own)",
                   "'" + time_variable + "'");
    }
    ReadListedData(mat.get(), group, path + ": variable '" + std::string(group->name) + "'");
    return MatStructSeries(*group, path, step_s, has_time, notes);
  }

  // Samples: the time vector's length, else each matrix's longer dimension.
  std::size_t samples = 0;
  if (time != nullptr) {
    const std::string where = path + ": variable '" + std::string(time->name) + "'";
    if (!IsMatNumeric(*time) || (time->dims[0] != 1 && time->dims[1] != 1)) {
      ThrowInvalid(where, "a real numeric time vector", MatClassText(*time));
    }
    samples = MatElements(*time);
  }
  TimeSeries series;
  std::vector<Eigen::MatrixXd> blocks;
  for (matvar_t* v : columns) {
    const std::string name = v->name;
    const std::string where = path + ": variable '" + name + "'";
    const std::size_t rows = v->dims[0], cols = v->dims[1];
    const bool vector = rows == 1 || cols == 1;
    if (time != nullptr && rows != samples && cols != samples) {
      ThrowInvalid(
          path + ": variable '" + std::string(time->name) + "'",
          std::to_string(vector ? rows * cols : rows) + " times (one per sample of '" + name + "')",
          std::to_string(samples));
    }
    const std::size_t own = samples != 0 ? samples : vector ? rows * cols : std::max(rows, cols);
    if (own < 2) ThrowInvalid(where, "at least 2 samples", std::to_string(own));
    if (samples == 0 && !blocks.empty() && own != static_cast<std::size_t>(blocks[0].rows())) {
      ThrowInvalid(where, std::to_string(blocks[0].rows()) + " samples as the other channels",
                   std::to_string(own));
    }
    blocks.push_back(Oriented(ReadNumeric(mat.get(), path, owner(v)), rows, cols, own, where));
    if (vector) {
      series.channel_names.push_back(CleanText(name));
    } else {
      for (Eigen::Index j = 0; j < blocks.back().cols(); ++j)
        series.channel_names.push_back(CleanText(name) + std::to_string(j + 1));
    }
  }
  series.values = ConcatenateChannels(blocks, blocks[0].rows());
  series.units.assign(series.channel_names.size(), "");

  if (time != nullptr) {
    const std::string name = time->name;
    const matio_classes time_class = time->class_type;
    series.time_s = MatTimeVector(ReadNumeric(mat.get(), path, owner(time)), time_class,
                                  path + ": variable '" + name + "'");
    if (has_time) *has_time = true;
  } else {
    if (!(step_s > 0.0) || !std::isfinite(step_s)) {
      ThrowInvalid(path,
                   "a time vector variable ('t' or 'time') or a sampling step "
                   "(--rate, --step)",
                   "neither");
    }
    series.time_s = internal::UniformTimes(
        0.0, step_s, static_cast<std::size_t>(series.values.rows()), path + " (sampling step)");
    if (has_time) *has_time = false;
  }
  return series;
}

}  // namespace internal

TimeSeries ReadMat(const std::string& path,
                   const MatReadOptions& options,
                   std::vector<std::string>* notes) {
  return internal::ReadMatFile(path, options.variable, options.time_variable, options.step_s,
                               nullptr, notes);
}

}  // namespace podid
