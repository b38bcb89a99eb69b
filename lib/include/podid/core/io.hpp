#pragma once
// Time-series files and safe output. Every file podid writes goes to a
// temporary name in the destination folder and is renamed when complete, so an
// error never leaves a partial file and never harms an earlier one.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "podid/core/time_series.hpp"

namespace podid {

class OutputBatch;

/// Longest CSV line ReadCsv accepts (bytes, without the newline); a longer line
/// is rejected without reading the rest of it.
inline constexpr std::size_t kMaxCsvLineBytes = std::size_t{1} << 20;

/// Time stamps: a time column or vector must be increasing and lie on a
/// uniform grid t0 + i h, with t0 and h fitted by least squares, each stamp
/// within its rounding plus kTimeStepRelativeTolerance h. The rounding of a
/// printed stamp (CSV) is half a unit of its column's precision: the most
/// significant digits, or (fixed-point columns) the most decimals, that any
/// stamp of the column prints, and never more than half a unit of the stamp's
/// own last digit; so spreadsheet stamps such as 0.0009766, 0.001953 at
/// 1024 Hz are accepted and replaced by the fitted grid, while a gap or a
/// jitter beyond the printing precision is rejected. Stamps printed to half a
/// step or coarser (0.1, 0.2, 0.3 at 10 Hz) must have exact steps, since their
/// rounding could hide a missing sample. Binary stamps (.mat) round at their
/// floating-point precision.
inline constexpr double kTimeStepRelativeTolerance = 1e-6;

/// Most values (samples x channels) a reader allocates: 2^27 doubles (1 GiB).
/// Checked against the sizes a file declares before any data is read.
inline constexpr std::size_t kMaxReadValues = std::size_t{1} << 27;

/// Reads a CSV in the reference data's format: a header `t,<name>,...`, then one
/// row per sample. Throws std::invalid_argument naming file:line:column for a
/// missing header, a non-numeric cell, a ragged row, NaN/Inf, fewer than 2
/// samples, or a time column that is not increasing and uniform (see
/// kTimeStepRelativeTolerance).
/// The file is read through a 64 KiB buffer (grown for a long line) and parsed
/// with std::from_chars: memory is the result plus one block of 2^17 values. Cells may be
/// surrounded by spaces; CRLF line ends and empty lines are accepted. The first column is the time
/// (named "t" or "time"); the others become channels.
TimeSeries ReadCsv(const std::string& path);

/// Writes `t,<names...>` and the rows with 13 significant digits (%.12e), atomically.
/// A name ReadCsv would split, trim or take for a number is quoted (RFC 4180).
/// Throws std::invalid_argument (before touching any file) when the sizes
/// disagree, a channel name cannot be read back (empty, a control character,
/// a repeat, "t"), or a line would be longer than kMaxCsvLineBytes (about
/// 50,000 channels).
/// With a `batch`, the file is staged in it (see OutputBatch).
void WriteCsv(const std::string& path, const TimeSeries& series, OutputBatch* batch = nullptr);

struct MatReadOptions {
  std::string variable;  ///< the variable or struct to read; empty: chosen as ReadMat says
  std::string time_variable;  ///< time vector variable; empty: looks for "t" or "time"
  double step_s = 0.0;        ///< used when there is no time (> 0)
};

/// Reads a MATLAB .mat file (libmatio: v4, v5, v7.3 (HDF5)); docs/data-files.md.
/// What it reads (`variable`, or else the first of these in the file):
///  * a real numeric matrix of any class (converted to double): channels
///    "<name>1".."<name>n"; a vector is one channel named "<name>". Without a
///    variable, all the top-level vectors of the first one's length are read
///    together, one channel each (V1, V2 in the Silverbox file);
///  * a test-system export struct: x_values.{start_value, increment,
///    number_of_values}, y_values.values, function_record.name (channel names,
///    a string or a cell of strings), y_values.quantity (label: the unit; when
///    its unit_transformation is not the identity, the values are in SI and the
///    unit is derived from quantity_terms, e.g. "m/s^2" although the label says g);
///  * a plain struct: a time field ("t", "time", "t_s", "time_s", case-insensitive) and one
///    numeric field per channel (vectors, or matrices as above).
/// Orientation: a matrix is samples x channels or channels x samples, decided by
/// the time vector's length (or number_of_values), else the longer dimension is
/// the samples (rows on a tie). The time vector must be increasing and uniform
/// (kTimeStepRelativeTolerance); without time, t = i * step_s. The declared
/// sizes are checked against the file's size and kMaxReadValues before reading.
/// Notes (fields skipped, units derived) are appended to `notes` when given.
TimeSeries ReadMat(const std::string& path,
                   const MatReadOptions& options = {},
                   std::vector<std::string>* notes = nullptr);

/// Longest header or data line ReadUff accepts (bytes).
inline constexpr std::size_t kMaxUffLineBytes = std::size_t{1} << 16;

/// Reads a universal file (UFF, .uff/.unv): data sets 58 (ASCII) and 58b
/// (binary, either byte order, single or double precision, IEEE 754) of
/// function type 1 (time response) with an even abscissa become channels named
/// "<node><direction>" from record 6 (e.g. "3+Z", "12-X", "5S" for scalar;
/// "_<k>" appended to the k-th repeat of a name), with the units of record 9.
/// All such data sets must share one grid (count, start, increment). Other data
/// sets and function types are skipped with a note. Counts are checked against
/// the bytes left in the file and kMaxReadValues before allocation.
TimeSeries ReadUff(const std::string& path, std::vector<std::string>* notes = nullptr);

/// What ReadTimeSeries reads from a data file.
struct DataReadOptions {
  std::string variable;  ///< .mat: the variable or struct (MatReadOptions::variable)
  /// Channels to keep, in this order, by name; empty: all. At most 65536.
  std::vector<std::string> channels;
  double rate_Hz = 0.0;  ///< sampling rate for a file without time (or step_s; not both)
  double step_s = 0.0;   ///< sampling step for a file without time
  /// Throws std::invalid_argument when the fields contradict each other.
  void Check() const;
};

/// Dispatches on the extension: .csv -> ReadCsv, .mat -> ReadMat, .uff/.unv ->
/// ReadUff; then keeps `options.channels`. A rate or step given for a file
/// that has its own time must agree with it (relative 1e-6). `variable` is
/// only for .mat files.
TimeSeries ReadTimeSeries(const std::string& path,
                          const DataReadOptions& options,
                          std::vector<std::string>* notes = nullptr);

/// Dispatches on the extension with default options.
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

/// Why the existing folder `folder` takes no new files: access() refuses it
/// (strerror), or it has no write bit ("the folder is read-only (mode
/// 0555)": read-only for root too, whom access() lets through); "" when it
/// takes them. ResolveOutput's check of a file's folder, and the CLI's of an
/// output folder.
std::string FolderNotWritable(const std::string& folder);

/// Writes a file: `write` fills a stream; the target is ResolveOutput(path).
///  * kFile: atomically. The stream goes to a temporary in the target's own
///    folder ("<folder>/.<name>.tmp-<pid>-<n>", O_EXCL, registered for removal
///    on the fatal signals of temp_files.hpp), which is flushed, fsync'ed
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
/// With a `batch`, a kFile target is written to its temporary but renamed only
/// by batch->Commit() (see OutputBatch); kSpecial and kDescriptor targets are
/// written at once, as without one.
void WriteFileAtomically(const std::string& path,
                         const std::function<void(std::ostream&)>& write,
                         OutputBatch* batch = nullptr);

/// The files of one command, published together: a command that writes
/// several files (a CSV, a JSON, plots) stages each in one batch and commits
/// the batch once everything has succeeded, so a late failure (gnuplot, a full
/// disk, a bad value) leaves none of them, and no earlier file is replaced.
///   OutputBatch batch;
///   WriteCsv("ridge.csv", ridge, &batch);
///   WriteFileAtomically("fit.json", writer, &batch);
///   batch.Commit();  // renames both; before it, neither exists
/// Commit renames the temporaries onto their targets in the order they were
/// written and makes the renames durable. It first gives each file it is
/// about to replace a second name (a hard link beside it), so that a rename
/// failing midway (the targets were checked writable when staged) puts the
/// earlier ones back: a replaced file renamed back, a new file removed. Only
/// where no hard link could be made (a file system without them) can an
/// earlier file stay replaced; the error names it. A batch destroyed before
/// Commit removes its temporaries and the folders CreateFolders made or
/// AdoptFolder was given.
class OutputBatch {
 public:
  OutputBatch();
  ~OutputBatch();
  OutputBatch(const OutputBatch&) = delete;
  OutputBatch& operator=(const OutputBatch&) = delete;

  /// std::filesystem::create_directories(folder), remembering the folders it
  /// made: an uncommitted batch removes them again (those left empty).
  void CreateFolders(const std::string& folder);
  /// A folder the caller has just made for this batch's files (mkdtemp):
  /// removed, once its staged files are, if the batch is not committed.
  void AdoptFolder(const std::string& folder);
  /// Publishes every staged file; throws std::runtime_error naming the file
  /// whose rename failed, having put the others back. A batch is committed at
  /// most once; after a failed Commit it is not, and its destructor removes
  /// the files still staged.
  void Commit();
  /// Staged files not yet committed.
  std::size_t staged() const;

  struct Staged;  // a temporary and its target (io_atomic.cpp)

 private:
  friend void WriteFileAtomically(const std::string&,
                                  const std::function<void(std::ostream&)>&,
                                  OutputBatch*);
  std::vector<std::unique_ptr<Staged>> files_;
  std::vector<std::string> created_folders_;  // parents first
  bool committed_ = false;
};

}  // namespace podid
