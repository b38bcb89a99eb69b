// Structs in .mat files as time series (io.hpp, ReadMat): test-system exports
// (x_values, y_values, function_record) and plain structs of channels.
#include <matio.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include "io_internal.hpp"
#include "io_mat_internal.hpp"
#include "podid/core/error.hpp"

namespace podid::internal {
namespace {

matvar_t* Field(matvar_t* var, const char* name, int index = 0) {
  if (var == nullptr || var->class_type != MAT_C_STRUCT || var->data == nullptr) return nullptr;
  if (static_cast<std::size_t>(index) >= MatElements(*var)) return nullptr;
  return Mat_VarGetStructFieldByName(var, name, index);
}

/// A real numeric scalar field, or NaN.
double Scalar(matvar_t* var, const std::string& where) {
  if (var == nullptr || !IsMatNumeric(*var) || MatElements(*var) != 1) return NAN;
  return MatDoubles(*var, where)[0];
}

bool EqualsNoCase(const std::string& a, const char* b) {
  const std::string_view v(b);
  return a.size() == v.size() && std::equal(a.begin(), a.end(), v.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == y;
         });
}

/// The SI unit of a test-system quantity from its quantity_terms (a struct
/// array of num, den, quantity), e.g. LENGTH^1 TIME^-2 -> "m/s^2"; "" if unknown.
std::string SiUnit(matvar_t* terms, const std::string& where) {
  if (terms == nullptr || terms->class_type != MAT_C_STRUCT) return "";
  struct Base {
    const char* quantity;
    const char* unit;
    double exponent = 0.0;
  };
  std::vector<Base> bases = {{"MASS", "kg"},   {"LENGTH", "m"},           {"TIME", "s"},
                             {"CURRENT", "A"}, {"TEMPERATURE", "K"},      {"LIGHT", "cd"},
                             {"ANGLE", "rad"}, {"MOLCULAR_AMOUNT", "mol"}};
  for (std::size_t i = 0; i < MatElements(*terms); ++i) {
    const int k = static_cast<int>(i);
    const std::string quantity = MatText(Field(terms, "quantity", k));
    const double num = Scalar(Field(terms, "num", k), where);
    const double den = Scalar(Field(terms, "den", k), where);
    if (!std::isfinite(num) || !std::isfinite(den) || den == 0.0) return "";
    bool known = false;
    for (Base& b : bases) {
      if (quantity == b.quantity ||
          (quantity == "MOLECULAR_AMOUNT" && b.unit == std::string("mol"))) {
        b.exponent += num / den;
        known = true;
      }
    }
    if (!known && num != 0.0) return "";
  }
  // Named units first.
  auto is = [&](double kg, double m, double s) {
    return bases[0].exponent == kg && bases[1].exponent == m && bases[2].exponent == s &&
           std::all_of(bases.begin() + 3, bases.end(),
                       [](const Base& b) { return b.exponent == 0.0; });
  };
  if (is(1, 1, -2)) return "N";
  if (is(1, -1, -2)) return "Pa";
  if (is(1, 2, -2)) return "N m";
  std::string numerator, denominator;
  for (const Base& b : bases) {
    if (b.exponent == 0.0) continue;
    std::string& part = b.exponent > 0 ? numerator : denominator;
    const double e = std::abs(b.exponent);
    part += (part.empty() ? "" : " ") + std::string(b.unit) + (e == 1.0 ? "" : "^" + ToText(e));
  }
  if (numerator.empty() && denominator.empty()) return "1";
  if (numerator.empty()) numerator = "1";
  if (denominator.empty()) return numerator;
  if (denominator.find(' ') != std::string::npos) denominator = "(" + denominator + ")";
  return numerator + "/" + denominator;
}

/// The unit of a test-system quantity struct (index k of a struct array).
std::string QuantityUnit(matvar_t* quantity,
                         int k,
                         const std::string& where,
                         std::vector<std::string>* notes) {
  if (quantity == nullptr) return "";
  const std::string label = MatText(Field(quantity, "label", k));
  matvar_t* transform = Field(quantity, "unit_transformation", k);
  const double factor = Scalar(Field(transform, "factor"), where);
  const double offset = Scalar(Field(transform, "offset"), where);
  const bool identity =
      (std::isnan(factor) || factor == 1.0) && (std::isnan(offset) || offset == 0.0);
  if (identity) return label;
  // The label is a display unit: display = factor * value + offset, values in SI.
  const std::string si = SiUnit(Field(quantity, "quantity_terms", k), where);
  if (si.empty()) {
    if (notes)
      notes->push_back(where + ": unit '" + label + "' has a transformation (factor " +
                       ToText(factor) + ") and no SI terms; kept '" + label + "'");
    return label;
  }
  if (notes && si != label) {
    notes->push_back(where + ": values in SI (" + si + "); the label '" + label +
                     "' is the display unit (factor " + ToText(factor) + ")");
  }
  return si;
}

/// Channel names from a test-system function_record.name: a string, a char
/// matrix of one row per channel or a cell of strings.
std::vector<std::string> RecordNames(matvar_t* name, std::size_t channels) {
  std::vector<std::string> out;
  if (name == nullptr) return out;
  if (name->class_type == MAT_C_CHAR) {
    std::string text = MatText(name);
    std::size_t start = 0;
    while (true) {
      const auto end = text.find('\n', start);
      out.push_back(text.substr(start, end == std::string::npos ? end : end - start));
      if (end == std::string::npos) break;
      start = end + 1;
    }
  } else if (name->class_type == MAT_C_CELL && name->data != nullptr) {
    for (std::size_t i = 0; i < MatElements(*name); ++i)
      out.push_back(MatText(Mat_VarGetCell(name, static_cast<int>(i))));
  }
  if (out.size() != channels) out.clear();
  return out;
}

std::vector<std::string> NumberedNames(const std::string& stem, Eigen::Index n) {
  if (n == 1) return {stem};
  std::vector<std::string> names;
  for (Eigen::Index j = 0; j < n; ++j) names.push_back(stem + std::to_string(j + 1));
  return names;
}

/// Samples x channels from a numeric variable with `samples` rows or columns.
Eigen::MatrixXd SamplesByChannels(const matvar_t& v,
                                  std::size_t samples,
                                  const std::string& where) {
  const std::vector<double> data = MatDoubles(v, where);
  const std::size_t rows = v.dims[0], cols = v.dims[1];
  const Eigen::Map<const Eigen::MatrixXd> m(data.data(), static_cast<Eigen::Index>(rows),
                                            static_cast<Eigen::Index>(cols));
  if (rows == samples) return m;
  if (cols == samples) return m.transpose();
  ThrowInvalid(where, "a matrix with " + std::to_string(samples) + " samples (rows or columns)",
               std::to_string(rows) + " x " + std::to_string(cols));
}

TimeSeries TestSystemSeries(matvar_t& var,
                            const std::string& where,
                            std::vector<std::string>* notes) {
  matvar_t* x = Field(&var, "x_values");
  matvar_t* y = Field(&var, "y_values");
  const double start = Scalar(Field(x, "start_value"), where + ".x_values.start_value");
  const double increment = Scalar(Field(x, "increment"), where + ".x_values.increment");
  const double count = Scalar(Field(x, "number_of_values"), where + ".x_values.number_of_values");
  if (!std::isfinite(start) || !(increment > 0.0) || !std::isfinite(increment)) {
    ThrowInvalid(where + ".x_values",
                 "numeric scalars start_value and increment > 0 (a test-system export)",
                 "start_value " + ToText(start) + ", increment " + ToText(increment));
  }
  const std::string x_unit = MatText(Field(Field(x, "quantity"), "label"));
  if (!x_unit.empty() && x_unit != "s") {
    ThrowInvalid(where + ".x_values.quantity.label", "'s' (a time signal)", "'" + x_unit + "'");
  }
  matvar_t* values = Field(y, "values");
  if (values == nullptr || !IsMatNumeric(*values)) {
    ThrowInvalid(where + ".y_values.values", "a real numeric matrix",
                 values == nullptr ? std::string("none") : MatClassText(*values));
  }
  const std::size_t rows = values->dims[0], cols = values->dims[1];
  std::size_t samples = 0;
  if (std::isfinite(count) && count >= 2 &&
      (count == static_cast<double>(rows) || count == static_cast<double>(cols))) {
    samples = static_cast<std::size_t>(count);
  } else if (!std::isnan(count)) {
    ThrowInvalid(where + ".x_values.number_of_values",
                 "the number of rows or columns of y_values.values (" + std::to_string(rows) +
                     " x " + std::to_string(cols) + ") and >= 2",
                 ToText(count));
  } else {
    samples = std::max(rows, cols);
  }
  TimeSeries series;
  series.values = SamplesByChannels(*values, samples, where + ".y_values.values");
  const auto channels = series.values.cols();
  series.time_s = UniformTimes(start, increment, static_cast<std::size_t>(series.values.rows()),
                               where + ".x_values");

  series.channel_names = RecordNames(Field(Field(&var, "function_record"), "name"),
                                     static_cast<std::size_t>(channels));
  if (series.channel_names.empty()) {
    series.channel_names = NumberedNames(CleanText(var.name ? var.name : "x"), channels);
    if (notes)
      notes->push_back(where + ": no function_record.name per channel; channels named " +
                       series.channel_names.front() + "...");
  }
  matvar_t* quantity = Field(y, "quantity");
  const bool per_channel = quantity != nullptr && channels > 1 &&
                           MatElements(*quantity) == static_cast<std::size_t>(channels);
  const std::string common = QuantityUnit(quantity, 0, where + ".y_values.quantity", notes);
  for (Eigen::Index j = 0; j < channels; ++j) {
    series.units.push_back(per_channel ? QuantityUnit(quantity, static_cast<int>(j),
                                                      where + ".y_values.quantity", nullptr)
                                       : common);
  }
  return series;
}

}  // namespace

bool IsMatSeriesStruct(matvar_t& info) {
  if (info.class_type != MAT_C_STRUCT || MatElements(info) != 1) return false;
  if (Field(&info, "x_values") != nullptr && Field(&info, "y_values") != nullptr) return true;
  const unsigned fields = Mat_VarGetNumberOfFields(&info);
  char* const* names = Mat_VarGetStructFieldnames(&info);
  for (unsigned f = 0; f < fields && names != nullptr; ++f) {
    matvar_t* v = Field(&info, names[f]);
    if (v != nullptr && IsMatNumeric(*v) && MatElements(*v) >= 2) return true;
  }
  return false;
}

TimeSeries MatStructSeries(matvar_t& var,
                           const std::string& path,
                           double step_s,
                           bool* has_time,
                           std::vector<std::string>* notes) {
  const std::string name = CleanText(var.name ? var.name : "");
  const std::string where = path + ": " + name;
  if (MatElements(var) != 1) {
    ThrowInvalid(where, "a 1 x 1 struct", std::to_string(MatElements(var)) + " struct elements");
  }
  if (Field(&var, "x_values") != nullptr && Field(&var, "y_values") != nullptr) {
    if (has_time) *has_time = true;
    return TestSystemSeries(var, where, notes);
  }
  // A plain struct: a time field and numeric fields of one length.
  const unsigned fields = Mat_VarGetNumberOfFields(&var);
  char* const* field_names = Mat_VarGetStructFieldnames(&var);
  matvar_t* time = nullptr;
  std::string time_name;
  for (unsigned f = 0; f < fields && field_names != nullptr; ++f) {
    const std::string field = field_names[f];
    if (EqualsNoCase(field, "t") || EqualsNoCase(field, "time") || EqualsNoCase(field, "time_s") ||
        EqualsNoCase(field, "t_s")) {
      time = Field(&var, field_names[f]);
      time_name = field;
      break;
    }
  }
  std::size_t samples = 0;
  if (time != nullptr) {
    if (!IsMatNumeric(*time) || (time->dims[0] != 1 && time->dims[1] != 1) ||
        MatElements(*time) < 2) {
      ThrowInvalid(where + "." + time_name, "a real numeric time vector of >= 2 samples",
                   MatClassText(*time) + " of " + std::to_string(MatElements(*time)) + " elements");
    }
    samples = MatElements(*time);
  }
  TimeSeries series;
  std::vector<Eigen::MatrixXd> blocks;
  std::string skipped;
  for (unsigned f = 0; f < fields && field_names != nullptr; ++f) {
    const std::string field = field_names[f];
    matvar_t* v = Field(&var, field_names[f]);
    if (v == nullptr || v == time) continue;
    const bool numeric = IsMatNumeric(*v) && MatElements(*v) >= 2;
    if (numeric && samples == 0) samples = std::max(v->dims[0], v->dims[1]);
    if (!numeric || (v->dims[0] != samples && v->dims[1] != samples)) {
      skipped += (skipped.empty() ? "" : ", ") + CleanText(field);
      continue;
    }
    blocks.push_back(SamplesByChannels(*v, samples, where + "." + CleanText(field)));
    for (auto& n : NumberedNames(CleanText(field), blocks.back().cols()))
      series.channel_names.push_back(n);
  }
  if (blocks.empty()) {
    ThrowInvalid(where, "a struct with numeric fields of one length (channels)",
                 "none (fields: " + skipped + ")");
  }
  if (!skipped.empty() && notes) {
    notes->push_back(where + ": fields " + skipped + " skipped (not numeric, or not " +
                     std::to_string(samples) + " samples long)");
  }
  series.values = ConcatenateChannels(blocks, static_cast<Eigen::Index>(samples));
  series.units.assign(series.channel_names.size(), "");
  if (time != nullptr) {
    series.time_s = MatTimeVector(MatDoubles(*time, where + "." + time_name), time->class_type,
                                  where + "." + time_name);
    if (has_time) *has_time = true;
  } else {
    // A scalar field fs (Hz) or dt (s) gives the sampling when no option does.
    for (unsigned f = 0; !(step_s > 0.0) && f < fields && field_names != nullptr; ++f) {
      const std::string field = field_names[f];
      const bool rate = EqualsNoCase(field, "fs");
      if (!rate && !EqualsNoCase(field, "dt")) continue;
      const double value = Scalar(Field(&var, field_names[f]), where + "." + field);
      if (value > 0.0 && std::isfinite(value) && std::isfinite(1.0 / value)) {
        step_s = rate ? 1.0 / value : value;
        if (notes)
          notes->push_back(where + ": sampling from its field " + field + " = " + ToText(value));
      }
    }
    if (!(step_s > 0.0) || !std::isfinite(step_s)) {
      ThrowInvalid(
          where,
          "a time field ('t', 'time', 'time_s', 't_s'), a scalar field 'fs' (Hz) or 'dt' (s), "
          "or a sampling step (--rate, --step)",
          "none of them");
    }
    series.time_s = UniformTimes(0.0, step_s, samples, where + " (sampling step)");
    if (has_time) *has_time = false;
  }
  return series;
}

}  // namespace podid::internal
