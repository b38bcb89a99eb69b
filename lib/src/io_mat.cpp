// MATLAB .mat time series through libmatio.
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
#include "mat_structure.hpp"
#include "podid/core/error.hpp"
#include "podid/core/io.hpp"

namespace podid {
namespace {

struct MatCloser {
  void operator()(mat_t* mat) const { Mat_Close(mat); }
};
struct VarFreer {
  void operator()(matvar_t* var) const { Mat_VarFree(var); }
};
using MatPtr = std::unique_ptr<mat_t, MatCloser>;
using VarPtr = std::unique_ptr<matvar_t, VarFreer>;

struct VarInfo {
  std::string name;
  bool numeric = false;  // real, non-sparse, numeric class, rank 2
  std::size_t rows = 0, cols = 0;
};

/// Largest ratio of uncompressed to compressed size that deflate reaches.
constexpr double kMaxDeflateRatio = 1032.0;

/// Throws when the variable's declared size cannot be stored in a file of
/// `file_bytes`: each element takes at least one byte (matio may store doubles
/// as int8), times the deflate ratio when compressed (v5 compressed, v7.3).
/// Checked before anything is allocated from the header's dimensions.
void CheckSizeFitsFile(const matvar_t& var,
                       bool may_be_compressed,
                       double file_bytes,
                       const std::string& path) {
  double elements = 1.0;
  for (int i = 0; i < var.rank; ++i) elements *= static_cast<double>(var.dims[i]);
  const double limit = may_be_compressed ? file_bytes * kMaxDeflateRatio : file_bytes;
  if (elements > limit) {
    ThrowInvalid(path + ": variable '" + std::string(var.name ? var.name : "") + "'",
                 "dimensions whose data fits the file (" + ToText(file_bytes) + " bytes)",
                 ToText(elements) + " elements (a corrupt header)");
  }
}

std::string ClassText(const matvar_t& var) {
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
  return "an object of matio class " + std::to_string(static_cast<int>(var.class_type));
}

bool IsNumericClass(matio_classes c) { return c >= MAT_C_DOUBLE && c <= MAT_C_UINT64; }

template <typename T>
void Convert(const void* data, std::size_t n, std::vector<double>& out) {
  const T* p = static_cast<const T*>(data);
  out.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<double>(p[i]);
}

/// Reads a numeric variable's data as doubles (column-major); `expected` is
/// the element count its header gave when the file was listed.
std::vector<double> ReadDoubles(mat_t* mat,
                                const std::string& path,
                                const std::string& name,
                                std::size_t expected) {
  VarPtr var(Mat_VarRead(mat, name.c_str()));
  if (!var || var->data == nullptr) {
    ThrowInvalid(path + ": variable '" + name + "'", "readable numeric data", "a read failure");
  }
  std::size_t n = 1;
  for (int i = 0; i < var->rank; ++i) n *= var->dims[i];
  if (n != expected) {  // the data must fill the buffers sized from the listing
    ThrowInvalid(path + ": variable '" + name + "'",
                 std::to_string(expected) + " elements, as listed", std::to_string(n));
  }
  std::vector<double> out;
  switch (var->data_type) {
    case MAT_T_DOUBLE:
      Convert<double>(var->data, n, out);
      break;
    case MAT_T_SINGLE:
      Convert<float>(var->data, n, out);
      break;
    case MAT_T_INT8:
      Convert<std::int8_t>(var->data, n, out);
      break;
    case MAT_T_UINT8:
      Convert<std::uint8_t>(var->data, n, out);
      break;
    case MAT_T_INT16:
      Convert<std::int16_t>(var->data, n, out);
      break;
    case MAT_T_UINT16:
      Convert<std::uint16_t>(var->data, n, out);
      break;
    case MAT_T_INT32:
      Convert<std::int32_t>(var->data, n, out);
      break;
    case MAT_T_UINT32:
      Convert<std::uint32_t>(var->data, n, out);
      break;
    case MAT_T_INT64:
      Convert<std::int64_t>(var->data, n, out);
      break;
    case MAT_T_UINT64:
      Convert<std::uint64_t>(var->data, n, out);
      break;
    default:
      ThrowInvalid(path + ": variable '" + name + "'", "numeric data",
                   "matio data type " + std::to_string(static_cast<int>(var->data_type)));
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(out[i])) {
      ThrowInvalid(path + ": variable '" + name + "' element " + std::to_string(i + 1),
                   "finite numbers", ToText(out[i]));
    }
  }
  return out;
}

}  // namespace

TimeSeries ReadMat(const std::string& path, const MatReadOptions& options) {
  // libmatio allocates what the headers declare, from Mat_Open on: check them
  // against the file first.
  internal::CheckMatStructure(path);
  MatPtr mat(Mat_Open(path.c_str(), MAT_ACC_RDONLY));
  if (!mat)
    ThrowInvalid(path, "a readable MATLAB .mat file (v4, v5 or v7.3)", "a file matio cannot open");

  struct stat file_status {};
  const double file_bytes =
      ::stat(path.c_str(), &file_status) == 0 ? static_cast<double>(file_status.st_size) : 0.0;
  const bool v73 = Mat_GetVersion(mat.get()) == MAT_FT_MAT73;

  std::vector<VarInfo> vars;
  while (true) {
    VarPtr var(Mat_VarReadNextInfo(mat.get()));
    if (!var) break;
    if (IsNumericClass(var->class_type) || var->class_type == MAT_C_CHAR) {
      CheckSizeFitsFile(*var, v73 || var->compression != MAT_COMPRESSION_NONE, file_bytes, path);
    }
    VarInfo info;
    info.name = var->name ? var->name : "";
    for (const auto& v : vars) {
      // Mat_VarRead finds a variable by name: a second one could not be read.
      if (v.name.substr(0, v.name.find('\0')) == info.name) {
        ThrowInvalid(path, "variables with distinct names", "'" + info.name + "' twice");
      }
    }
    info.numeric = IsNumericClass(var->class_type) && !var->isComplex && var->rank == 2;
    if (var->rank == 2) {
      info.rows = var->dims[0];
      info.cols = var->dims[1];
    }
    if (!info.numeric) {
      // Keep the description for messages.
      info.name += '\0' + ClassText(*var);
    }
    vars.push_back(std::move(info));
  }
  auto find = [&](const std::string& name) -> const VarInfo* {
    for (const auto& v : vars) {
      if (v.name.substr(0, v.name.find('\0')) == name) return &v;
    }
    return nullptr;
  };
  auto describe = [](const VarInfo& v) {
    const auto zero = v.name.find('\0');
    return zero == std::string::npos ? std::string("a numeric matrix") : v.name.substr(zero + 1);
  };
  std::string names;
  for (const auto& v : vars)
    names += (names.empty() ? "" : ", ") + v.name.substr(0, v.name.find('\0'));

  // The time vector.
  const VarInfo* time = nullptr;
  if (!options.time_variable.empty()) {
    time = find(options.time_variable);
    if (time == nullptr) {
      ThrowInvalid(path,
                   "a time variable '" + options.time_variable + "' (variables: " + names + ")",
                   "none");
    }
  } else {
    time = find("t");
    if (time == nullptr) time = find("time");
  }
  // The data matrix.
  const VarInfo* data = nullptr;
  if (!options.variable.empty()) {
    data = find(options.variable);
    if (data == nullptr) {
      ThrowInvalid(path, "a variable '" + options.variable + "' (variables: " + names + ")",
                   "none");
    }
  } else {
    for (const auto& v : vars) {
      if (&v != time && v.numeric && v.rows * v.cols > 0) {
        data = &v;
        break;
      }
    }
    if (data == nullptr) {
      ThrowInvalid(path, "a numeric matrix variable (samples x channels)",
                   vars.empty() ? std::string("no variables") : "only " + names);
    }
  }
  if (!data->numeric) {
    ThrowInvalid(path + ": variable '" + options.variable + "'",
                 "a real numeric matrix (samples x channels)", describe(*data));
  }
  const std::string data_name = data->name;
  const bool vector = data->rows == 1 || data->cols == 1;
  const std::size_t samples = vector ? data->rows * data->cols : data->rows;
  const std::size_t channels = vector ? 1 : data->cols;
  if (samples < 2) {
    ThrowInvalid(path + ": variable '" + data_name + "'", "at least 2 samples (rows)",
                 std::to_string(samples));
  }

  TimeSeries series;
  series.values.resize(static_cast<Eigen::Index>(samples), static_cast<Eigen::Index>(channels));
  {
    const auto values = ReadDoubles(mat.get(), path, data_name, samples * channels);
    std::copy(values.begin(), values.end(), series.values.data());  // both column-major
  }
  for (std::size_t j = 0; j < channels; ++j) {
    series.channel_names.push_back(data_name + std::to_string(j + 1));
  }

  series.time_s.resize(static_cast<Eigen::Index>(samples));
  if (time != nullptr) {
    const std::string time_name = time->name.substr(0, time->name.find('\0'));
    const std::string where = path + ": variable '" + time_name + "'";
    if (!time->numeric || (time->rows != 1 && time->cols != 1)) {
      ThrowInvalid(where, "a real numeric time vector", describe(*time));
    }
    if (time->rows * time->cols != samples) {
      ThrowInvalid(where, std::to_string(samples) + " times (one per row of '" + data_name + "')",
                   std::to_string(time->rows * time->cols));
    }
    const auto t = ReadDoubles(mat.get(), path, time_name, samples);
    const double h = t[1] - t[0];
    for (std::size_t i = 1; i < samples; ++i) {
      const double d = t[i] - t[i - 1];
      if (!(d > 0.0)) {
        ThrowInvalid(where + " element " + std::to_string(i + 1),
                     "an increasing time (after t = " + ToText(t[i - 1]) + ")", ToText(t[i]));
      }
      if (!internal::IsUniformStep(d, h, t[i])) {
        ThrowInvalid(where + " element " + std::to_string(i + 1),
                     "a uniform time step " + ToText(h) + " s (relative tolerance " +
                         ToText(kTimeStepRelativeTolerance) + ")",
                     "a step of " + ToText(d) + " s");
      }
    }
    std::copy(t.begin(), t.end(), series.time_s.data());
  } else {
    if (!(options.step_s > 0.0) || !std::isfinite(options.step_s)) {
      ThrowInvalid(path,
                   "a time vector variable ('t' or 'time') or a sampling step "
                   "MatReadOptions::step_s > 0",
                   "neither");
    }
    for (std::size_t i = 0; i < samples; ++i) {
      series.time_s(static_cast<Eigen::Index>(i)) = static_cast<double>(i) * options.step_s;
    }
  }
  return series;
}

}  // namespace podid
