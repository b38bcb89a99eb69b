#pragma once
// Time-series files and safe output. Every file podid writes goes to a
// temporary name in the destination folder and is renamed when complete, so an
// error never leaves a partial file and never harms an earlier one.

#include <cstddef>
#include <functional>
#include <iosfwd>
#include <string>

#include "podid/core/time_series.hpp"

namespace podid {

/// Longest CSV line ReadCsv accepts (bytes, without the newline); a longer line
/// is rejected without reading the rest of it.
inline constexpr std::size_t kMaxCsvLineBytes = std::size_t{1} << 20;

/// Relative tolerance on the uniformity of a time column: each step d must
/// satisfy |d - h| <= 1e-6 h + 2e-12 |t| (h the first step; the second term is
/// the rounding of 13 significant digits, the %.12e format, at time t).
inline constexpr double kTimeStepRelativeTolerance = 1e-6;

/// Reads a CSV in the reference data's format: a header `t,<name>,...`, then one
/// row per sample. Throws std::invalid_argument naming file:line:column for a
/// missing header, a non-numeric cell, a ragged row, NaN/Inf, fewer than 2
/// samples, or a time column that is not increasing and uniform (relative
/// tolerance 1e-6 on the step).
/// The file is streamed in 1 MiB blocks and parsed with std::from_chars: memory
/// is the result plus one block of 16384 rows. Cells may be surrounded by spaces;
/// CRLF line ends and empty lines are accepted. The first column is the time
/// (named "t" or "time"); the others become channels.
TimeSeries ReadCsv(const std::string& path);

/// Writes `t,<names...>` and the rows with 13 significant digits (%.12e), atomically.
/// Throws std::invalid_argument (before touching any file) when the sizes
/// disagree or a channel name is empty or contains ',', '"' or a line break.
void WriteCsv(const std::string& path, const TimeSeries& series);

struct MatReadOptions {
  std::string variable;  ///< numeric matrix (samples x channels); empty: the only/first 2-D matrix
  std::string time_variable;  ///< time vector variable; empty: looks for "t" or "time"
  double step_s = 0.0;        ///< used when there is no time vector (> 0)
};

/// Reads a MATLAB .mat file (libmatio, v4/v5/v7.3). The matrix may be of any
/// real numeric class (converted to double); a vector is one channel. Channel
/// names are the variable's name followed by 1..n_channels ("w" -> w1..w6).
/// The time vector must have one entry per sample and be increasing and
/// uniform, as for ReadCsv; without one, t = i * step_s.
TimeSeries ReadMat(const std::string& path, const MatReadOptions& options = {});

/// Dispatches on the extension: .csv -> ReadCsv, .mat -> ReadMat.
TimeSeries ReadTimeSeries(const std::string& path);

/// Writes a file atomically: `write` fills a stream on a temporary file in the
/// same folder, which is flushed, checked and renamed onto `path`. On any
/// error (the callback throws, the disk is full, the folder is missing or
/// read-only) the temporary is removed, `path` is untouched and
/// std::runtime_error / std::invalid_argument says which file and why.
/// The temporary is "<folder>/.<name>.tmp-<pid>-<n>", created with mode 0666
/// minus the umask; the folder is fsync'ed after the rename (best effort).
/// An exception thrown by `write` is rethrown as the same kind
/// (std::invalid_argument, else std::runtime_error) with the file name added.
void WriteFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace podid
