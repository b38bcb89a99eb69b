#pragma once
// Time-series files and safe output. Every file podid writes goes to a
// temporary name in the destination folder and is renamed when complete, so an
// error never leaves a partial file and never harms an earlier one.

#include <functional>
#include <iosfwd>
#include <string>

#include "podid/core/time_series.hpp"

namespace podid {

/// Reads a CSV in the reference data's format: a header `t,<name>,...`, then one
/// row per sample. Throws std::invalid_argument naming file:line:column for a
/// missing header, a non-numeric cell, a ragged row, NaN/Inf, fewer than 2
/// samples, or a time column that is not increasing and uniform (relative
/// tolerance 1e-6 on the step).
TimeSeries ReadCsv(const std::string& path);

/// Writes `t,<names...>` and the rows with 13 significant digits (%.12e), atomically.
void WriteCsv(const std::string& path, const TimeSeries& series);

struct MatReadOptions {
  std::string variable;       ///< numeric matrix (samples x channels); empty: the only/first 2-D matrix
  std::string time_variable;  ///< time vector variable; empty: looks for "t" or "time"
  double step_s = 0.0;        ///< used when there is no time vector (> 0)
};

/// Reads a MATLAB .mat file (libmatio, v4/v5/v7.3).
TimeSeries ReadMat(const std::string& path, const MatReadOptions& options = {});

/// Dispatches on the extension: .csv -> ReadCsv, .mat -> ReadMat.
TimeSeries ReadTimeSeries(const std::string& path);

/// Writes a file atomically: `write` fills a stream on a temporary file in the
/// same folder, which is flushed, checked and renamed onto `path`. On any
/// error (the callback throws, the disk is full, the folder is missing or
/// read-only) the temporary is removed, `path` is untouched and
/// std::runtime_error / std::invalid_argument says which file and why.
void WriteFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace podid
