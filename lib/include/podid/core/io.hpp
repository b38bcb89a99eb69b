#pragma once
// Time-series files and safe output. Every file podid writes goes to a
// temporary name in the destination folder and is renamed when complete, so an
// error never leaves a partial file and never harms an earlier one.

#include <cstddef>
#include <cstdint>
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

/// Where WriteFileAtomically(path) writes: `path` with its symlinks followed
/// (at most 40; relative links are relative to the link's folder).
struct OutputTarget {
  enum class Kind {
    kFile,        ///< a regular file or nothing yet: a temporary renamed onto `path`
    kSpecial,     ///< an existing device, FIFO or socket: opened and written in place
    kDescriptor,  ///< /dev/stdout, /dev/stderr, /dev/fd/N, /proc/self/fd/N: descriptor N
  };
  Kind kind = Kind::kFile;
  std::string path;     ///< the final path (kFile: the name replaced or created)
  int descriptor = -1;  ///< kDescriptor: N
  bool exists = false;  ///< something exists at the target: `device` and `inode` name it
  std::uint64_t device = 0;
  std::uint64_t inode = 0;
};

/// Resolves `path` as WriteFileAtomically does and checks, without writing
/// anything, that it can be written: its folder exists and is writable, the
/// target is not a folder, not a read-only file, and (kDescriptor) the
/// descriptor is open. Throws std::runtime_error("cannot write <path>: <why>"),
/// or std::invalid_argument for an empty path or one ending in '/'.
OutputTarget ResolveOutput(const std::string& path);

/// Writes a file: `write` fills a stream; the target is ResolveOutput(path).
///  * kFile: atomically. The stream goes to a temporary in the target's own
///    folder ("<folder>/.<name>.tmp-<pid>-<n>", O_EXCL, registered for removal
///    on SIGINT/SIGTERM/SIGHUP, see temp_files.hpp), which is flushed, fsync'ed
///    and renamed onto the target; the folder is fsync'ed (best effort). A new
///    file gets mode 0666 minus the umask; an existing one keeps its mode (and,
///    for root, its owner). Writing through a symlink replaces the file it
///    points to and keeps the link. A file with several hard links is replaced
///    at this name only: its other names keep the previous content.
///  * kSpecial (/dev/null, a FIFO, a terminal) and kDescriptor (/dev/stdout):
///    written in place, never replaced by a regular file; not atomic.
/// On any error (the callback throws, the disk is full, the folder is missing
/// or read-only) the temporary is removed, the target is untouched and
/// std::runtime_error / std::invalid_argument says which file and why. An
/// exception thrown by `write` is rethrown as the same kind
/// (std::invalid_argument, else std::runtime_error) with the file name added.
void WriteFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace podid
