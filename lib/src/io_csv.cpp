// CSV time series: a streaming reader (std::from_chars, bounded line length)
// and a writer in the reference data's %.12e format.
#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <ostream>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "io_internal.hpp"
#include "podid/core/error.hpp"
#include "podid/core/io.hpp"

namespace podid {
namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

/// Hands out the file's lines one at a time from a buffer of 64 KiB that
/// doubles for a longer line, up to kMaxCsvLineBytes + 1 bytes; a longer line
/// is an error. (A small file does not pay for zeroing the largest buffer.)
class LineReader {
 public:
  LineReader(std::FILE* file, std::string path)
      : file_(file), path_(std::move(path)), buffer_(std::min(kInitialBytes, kMaxBytes)) {}

  /// The next line without its '\n' (and '\r'), or false at the end.
  bool Next(std::string_view& line) {
    while (true) {
      const char* begin = buffer_.data() + begin_;
      const auto* newline = static_cast<const char*>(std::memchr(begin, '\n', end_ - begin_));
      if (newline != nullptr) {
        line = std::string_view(begin, static_cast<std::size_t>(newline - begin));
        begin_ += line.size() + 1;
        break;
      }
      if (eof_) {
        if (begin_ == end_) return false;
        line = std::string_view(begin, end_ - begin_);
        begin_ = end_;
        break;
      }
      if (end_ - begin_ == buffer_.size()) {
        if (buffer_.size() == kMaxBytes) {
          ThrowInvalid(path_ + ":" + std::to_string(line_number_ + 1) + ":1",
                       "a line of at most " + std::to_string(kMaxCsvLineBytes) + " bytes",
                       "a longer line");
        }
        buffer_.resize(std::min(2 * buffer_.size(), kMaxBytes));
      }
      Refill();
    }
    ++line_number_;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    return true;
  }
  long long line_number() const { return line_number_; }

 private:
  void Refill() {
    if (begin_ > 0) {
      std::memmove(buffer_.data(), buffer_.data() + begin_, end_ - begin_);
      end_ -= begin_;
      begin_ = 0;
    }
    const std::size_t got = std::fread(buffer_.data() + end_, 1, buffer_.size() - end_, file_);
    end_ += got;
    if (got == 0) {
      if (std::ferror(file_)) {
        ThrowInvalid(path_ + ":" + std::to_string(line_number_ + 1), "a readable file",
                     std::string("a read error: ") + std::strerror(errno));
      }
      eof_ = true;
    }
  }

  static constexpr std::size_t kInitialBytes = std::size_t{1} << 16;
  static constexpr std::size_t kMaxBytes = kMaxCsvLineBytes + 1;

  std::FILE* file_;
  std::string path_;
  std::vector<char> buffer_;
  std::size_t begin_ = 0, end_ = 0;
  bool eof_ = false;
  long long line_number_ = 0;
};

// The blanks a cell may have around it.
bool IsBlankByte(char c) { return c == ' ' || c == '\t'; }

std::string_view Trim(std::string_view s) {
  while (!s.empty() && IsBlankByte(s.front())) s.remove_prefix(1);
  while (!s.empty() && IsBlankByte(s.back())) s.remove_suffix(1);
  return s;
}

// The first byte of `line` at or after `at` that is not a blank, else its size.
std::size_t SkipBlanks(std::string_view line, std::size_t at) {
  while (at < line.size() && IsBlankByte(line[at])) ++at;
  return at;
}

// A short, escaped excerpt of the offending cell (error.hpp): a file's bytes
// never reach the terminal raw or at length.
std::string Quote(std::string_view cell) { return Excerpt(cell); }

// The first cell of a header whose first name is wrong: show only its start.
constexpr std::size_t kShownFirstCellBytes = 12;

bool IsBlank(std::string_view line) { return Trim(line).empty(); }

// Whether from_chars reads all of `cell` as a number ("1", "nan", "inf" too).
bool IsNumber(std::string_view cell) {
  double number = 0.0;
  const auto [ptr, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), number);
  return !cell.empty() && ec == std::errc() && ptr == cell.data() + cell.size();
}

// One name of the header from byte `start` of `line`: a bare cell (the blanks
// around it trimmed) or a quoted one as RFC 4180 writes it ("..." with "" for
// a quote, blanks allowed around the quotes): R's write.csv quotes every
// name, and a quoted name may hold a comma and is never taken for a number.
// Hand-written rather than a CSV library's: only the header can be quoted,
// and the rows keep the reader's single pass of from_chars.
struct HeaderCell {
  std::string name;
  bool quoted = false;
  std::size_t next = std::string_view::npos;      // the next cell's first byte; npos: none
  std::size_t error_at = std::string_view::npos;  // a malformed quote's byte, else npos
  const char* expected = "";
  std::string got;
};

HeaderCell NextHeaderCell(std::string_view line, std::size_t start) {
  HeaderCell cell;
  std::size_t at = SkipBlanks(line, start);
  if (at == line.size() || line[at] != '"') {
    const std::size_t comma = line.find(',', start);
    cell.name = Trim(line.substr(start, comma == line.npos ? line.npos : comma - start));
    cell.next = comma == line.npos ? line.npos : comma + 1;
    return cell;
  }
  cell.quoted = true;
  const std::size_t open = at++;
  while (true) {
    if (at >= line.size()) {
      cell.error_at = open;
      cell.expected = "a closing quote '\"' for the column name opened here";
      cell.got = "the end of the line";
      return cell;
    }
    if (line[at] == '"') {
      if (at + 1 < line.size() && line[at + 1] == '"') {  // "" inside quotes: one quote
        cell.name.push_back('"');
        at += 2;
        continue;
      }
      ++at;
      break;
    }
    cell.name.push_back(line[at++]);
  }
  at = SkipBlanks(line, at);
  if (at < line.size() && line[at] != ',') {
    cell.error_at = at;
    cell.expected = "a comma or the end of the line after a quoted column name";
    cell.got = Quote(line.substr(at, 1));
    return cell;
  }
  cell.next = at < line.size() ? at + 1 : line.npos;
  return cell;
}

}  // namespace

TimeSeries ReadCsv(const std::string& path) {
  internal::RequireRegularFile(path, "a readable CSV file");
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
  if (!file) {
    ThrowInvalid(path, "a readable CSV file", std::string("\"") + std::strerror(errno) + "\"");
  }
  LineReader reader(file.get(), path);
  auto where = [&](long long line, std::size_t column) {
    return path + ":" + std::to_string(line) + ":" + std::to_string(column);
  };

  // Header.
  std::string_view line;
  bool have_line = false;
  while ((have_line = reader.Next(line)) && IsBlank(line)) {
  }
  if (!have_line) ThrowInvalid(where(1, 1), "a header line such as \"t,w1,w2\"", "an empty file");
  // A UTF-8 byte-order mark (spreadsheets write one) is not part of the first
  // name; columns in messages still count its 3 bytes.
  std::size_t bom = 0;
  if (reader.line_number() == 1 && line.starts_with("\xEF\xBB\xBF")) {
    line.remove_prefix(3);
    bom = 3;
  }
  std::vector<std::string> names;
  {
    std::set<std::string> seen;
    std::size_t start = 0;
    while (true) {
      const HeaderCell parsed = NextHeaderCell(line, start);
      if (parsed.error_at != line.npos) {
        ThrowInvalid(where(reader.line_number(), bom + parsed.error_at + 1), parsed.expected,
                     parsed.got);
      }
      const std::size_t next = parsed.next;  // npos: the last name
      const std::string_view cell = parsed.name;
      if (cell.empty()) {
        ThrowInvalid(where(reader.line_number(), bom + start + 1),
                     "a header line such as \"t,w1,w2\"", "an empty column name");
      }
      if (!parsed.quoted && IsNumber(cell)) {
        ThrowInvalid(where(reader.line_number(), bom + start + 1),
                     "a header line such as \"t,w1,w2\"",
                     "a row of numbers (the header is missing)");
      }
      if (names.empty() && cell != "t" && cell != "time") {
        // A first line without a comma is no CSV header (`[force] file =
        // /etc/shadow`): nothing of it is shown, only its length.
        if (next == line.npos) {
          ThrowInvalid(where(reader.line_number(), bom + start + 1),
                       "a CSV header line such as \"t,w1,w2\"",
                       "a first line of " + std::to_string(line.size()) +
                           " bytes without a comma (not a CSV file?)");
        }
        ThrowInvalid(where(reader.line_number(), bom + start + 1),
                     "a header line whose first name is \"t\" or \"time\"",
                     Excerpt(cell, kShownFirstCellBytes));
      }
      if (HasControlCharacter(cell)) {  // names reach messages, tables and outputs
        ThrowInvalid(where(reader.line_number(), bom + start + 1),
                     "column names without control characters", Quote(cell));
      }
      if (!seen.insert(std::string(cell)).second) {
        ThrowInvalid(where(reader.line_number(), bom + start + 1), "distinct column names",
                     Quote(cell) + " twice");
      }
      names.emplace_back(cell);
      if (next == line.npos) break;
      start = next;
    }
    if (names.size() < 2) {
      ThrowInvalid(where(reader.line_number(), bom + line.size() + 1),
                   "a time column and at least one channel in the header",
                   "only " + Quote(names[0]));
    }
  }
  const std::size_t columns = names.size();

  // Rows, stored row-major in blocks of block_rows rows: the blocks are freed
  // one by one while the result is filled, so the peak memory is about the
  // result's size plus one block (no reallocation of one growing buffer).
  // A block holds at most 2^17 doubles (16384 rows of 8 columns): a wide
  // header must not make the first row allocate 16384 times its width.
  constexpr std::size_t kBlockDoubles = std::size_t{1} << 17;
  const std::size_t block_rows = std::max<std::size_t>(1, kBlockDoubles / columns);
  std::vector<std::unique_ptr<double[]>> blocks;
  double* row_out = nullptr;
  std::size_t rows = 0;
  double t_previous = 0.0;
  // Per row: the time stamp's own rounding (half a unit of its last printed
  // digit) and line; per column: the most significant digits and decimals.
  std::vector<float> time_rounding;
  std::vector<long long> time_lines;
  int max_significant = 0, max_decimals = -1;
  while (reader.Next(line)) {
    if (IsBlank(line)) continue;
    // The bound of every reader (io.hpp): a file of any length stops there,
    // not when the memory does (a 270 MB file of zeros took 6 GB).
    if ((rows + 1) * columns > kMaxReadValues) {
      ThrowInvalid(where(reader.line_number(), 1),
                   "at most " + std::to_string(kMaxReadValues) +
                       " values in all (kMaxReadValues: " + std::to_string(columns) +
                       " columns x " + std::to_string(kMaxReadValues / columns) + " rows)",
                   "more rows");
    }
    if (rows % block_rows == 0) {
      blocks.push_back(std::make_unique_for_overwrite<double[]>(block_rows * columns));
    }
    row_out = blocks.back().get() + (rows % block_rows) * columns;
    const long long line_number = reader.line_number();
    std::size_t position = 0;
    for (std::size_t c = 0; c < columns; ++c) {
      if (c > 0) {
        if (position >= line.size() || line[position] != ',') {
          ThrowInvalid(where(line_number, position + 1),
                       std::to_string(columns) + " cells as in the header",
                       std::to_string(c) + " cells (a ragged row)");
        }
        ++position;
      }
      std::size_t cell_end = line.find(',', position);
      if (cell_end == line.npos) cell_end = line.size();
      const std::string_view raw = line.substr(position, cell_end - position);
      std::string_view cell = Trim(raw);
      const std::size_t column = position + 1 + static_cast<std::size_t>(cell.data() - raw.data());
      if (!cell.empty() && cell.front() == '+') cell.remove_prefix(1);
      double value = 0.0;
      const auto [ptr, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), value);
      if (cell.empty()) {
        ThrowInvalid(where(line_number, column), "a number in column " + names[c], "an empty cell");
      }
      if (ptr != cell.data() + cell.size() ||
          (ec != std::errc() && ec != std::errc::result_out_of_range)) {
        ThrowInvalid(where(line_number, column), "a number in column " + names[c], Quote(cell));
      }
      if (ec == std::errc::result_out_of_range || !std::isfinite(value)) {
        ThrowInvalid(where(line_number, column), "a finite number in column " + names[c],
                     Quote(cell));
      }
      row_out[c] = value;
      if (c == 0) {
        const internal::PrintedNumber printed = internal::Printed(cell);
        time_rounding.push_back(static_cast<float>(printed.half_unit));
        max_significant = std::max(max_significant, printed.significant);
        max_decimals = std::max(max_decimals, printed.decimals);
      }
      position = cell_end;
    }
    if (position < line.size()) {
      ThrowInvalid(where(line_number, position + 1),
                   std::to_string(columns) + " cells as in the header",
                   "more cells (a ragged row)");
    }
    // The time column: increasing here, uniform when all is read.
    const double t = row_out[0];
    if (rows > 0 && !(t - t_previous > 0.0)) {
      ThrowInvalid(where(line_number, 1),
                   "an increasing time (after t = " + ToText(t_previous) + ")", ToText(t));
    }
    time_lines.push_back(line_number);
    t_previous = t;
    ++rows;
  }
  if (rows < 2) {
    ThrowInvalid(where(reader.line_number() + 1, 1), "at least 2 samples", std::to_string(rows));
  }

  TimeSeries series;
  series.channel_names.assign(names.begin() + 1, names.end());
  series.time_s.resize(static_cast<Eigen::Index>(rows));
  series.values.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(columns - 1));
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const double* block = blocks[b].get();
    const std::size_t first = b * block_rows;
    const std::size_t count = std::min(block_rows, rows - first);
    for (std::size_t i = 0; i < count; ++i) {
      const double* row = block + i * columns;
      const auto r = static_cast<Eigen::Index>(first + i);
      series.time_s(r) = row[0];
      for (std::size_t c = 1; c < columns; ++c) {
        series.values(r, static_cast<Eigen::Index>(c - 1)) = row[c];
      }
    }
    blocks[b].reset();
  }
  // The stamps' rounding: the column's printed precision, at most the stamp's own.
  const double decimals_half_unit = max_decimals >= 0 ? 0.5 * std::pow(10.0, -max_decimals) : 0.0;
  const auto rounding = [&](std::size_t i) {
    const double t = series.time_s(static_cast<Eigen::Index>(i));
    double digits_half_unit = 0.0;
    if (t != 0.0) {
      double exponent = std::floor(std::log10(std::abs(t)));  // of the leading digit
      if (std::pow(10.0, exponent + 1) <= std::abs(t)) exponent += 1;
      if (std::pow(10.0, exponent) > std::abs(t)) exponent -= 1;
      digits_half_unit = 0.5 * std::pow(10.0, exponent - max_significant + 1);
    }
    return std::min(static_cast<double>(time_rounding[i]),
                    std::max(digits_half_unit, decimals_half_unit));
  };
  const internal::UniformGrid grid = internal::FitUniformGrid(
      series.time_s.data(), rows, rounding,
      [&](std::size_t i) { return where(time_lines[i], 1); });
  series.time_s = internal::GridOrStamps(series.time_s.data(), rows, grid);
  return series;
}

void WriteCsv(const std::string& path, const TimeSeries& series, OutputBatch* batch) {
  const auto rows = series.values.rows();
  const auto cols = series.values.cols();
  if (series.time_s.size() != rows) {
    ThrowInvalid("WriteCsv(" + path + ")", std::to_string(rows) + " times (one per sample)",
                 std::to_string(series.time_s.size()));
  }
  if (static_cast<Eigen::Index>(series.channel_names.size()) != cols) {
    ThrowInvalid("WriteCsv(" + path + ")", std::to_string(cols) + " channel names",
                 std::to_string(series.channel_names.size()));
  }
  // The names ReadCsv reads back: not empty, no control character, distinct
  // (from the time column's "t" too). A name the reader would trim, split or
  // take for a number is written quoted.
  std::set<std::string_view> seen = {"t"};
  std::string header = "t";
  for (const auto& name : series.channel_names) {
    if (name.empty() || HasControlCharacter(name)) {
      ThrowInvalid("WriteCsv(" + path + ")", "channel names without control characters, not empty",
                   Quote(name));
    }
    if (!seen.insert(name).second) {
      ThrowInvalid("WriteCsv(" + path + ")", "distinct channel names other than \"t\"",
                   Quote(name) + " twice");
    }
    header += ',';
    if (name.find_first_of(",\"") == std::string::npos && Trim(name) == name && !IsNumber(name)) {
      header += name;
      continue;
    }
    header += '"';
    for (const char c : name) {
      if (c == '"') header += '"';  // "" is one quote inside quotes
      header += c;
    }
    header += '"';
  }
  // Every line within ReadCsv's bound, checked before anything is written
  // (a descriptor such as stdout is written as it goes): without it, about
  // 50,000 channels made a file that its own reader refuses.
  const auto too_long = [&](const std::string& line_name, std::size_t bytes) {
    ThrowInvalid("WriteCsv(" + path + ")",
                 "lines of at most " + std::to_string(kMaxCsvLineBytes) +
                     " bytes (kMaxCsvLineBytes, what ReadCsv reads back)",
                 line_name + " of " + std::to_string(bytes) + " bytes (" + std::to_string(cols) +
                     " channels)");
  };
  if (header.size() > kMaxCsvLineBytes) too_long("a header", header.size());
  header += '\n';
  // One row per line: 13 significant digits, as printf("%.12e"). The time
  // gets more when 13 would not resolve its step to 1e-6 of the step (the
  // reader's tolerance): a record starting at t = 1e9 s at 5 kHz was
  // written as 501 equal stamps. 17 digits round-trip any double.
  int time_precision = 12;
  if (rows >= 2) {
    const double span = std::max(std::abs(series.time_s(0)), std::abs(series.time_s(rows - 1)));
    const double step =
        (series.time_s(rows - 1) - series.time_s(0)) / static_cast<double>(rows - 1);
    if (step > 0.0 && span > 0.0) {
      const double needed = std::ceil(std::log10(span / step)) + 6.0;
      time_precision = static_cast<int>(std::clamp(needed, 12.0, 16.0));
    }
  }
  // The longest a cell prints: "-d." + 16 digits + "e+308" for the time,
  // "-d." + 12 + "e+308" for a value, and a comma before each value.
  constexpr std::size_t kTimeCellBytes = 24, kValueCellBytes = 21;
  const std::size_t row_bound = kTimeCellBytes + static_cast<std::size_t>(cols) * kValueCellBytes;
  std::vector<char> buffer(row_bound + 1);
  const auto format_row = [&](Eigen::Index i) {
    char* p = buffer.data();
    char* const end = buffer.data() + buffer.size();
    for (Eigen::Index j = -1; j < cols; ++j) {
      if (j >= 0) *p++ = ',';
      const double v = j < 0 ? series.time_s(i) : series.values(i, j);
      p = std::to_chars(p, end, v, std::chars_format::scientific, j < 0 ? time_precision : 12).ptr;
    }
    return static_cast<std::size_t>(p - buffer.data());
  };
  if (row_bound > kMaxCsvLineBytes) {
    // Only so wide a file pays for formatting twice: most values print
    // shorter than the bound (a positive one with a two-digit exponent, 19).
    for (Eigen::Index i = 0; i < rows; ++i) {
      const std::size_t bytes = format_row(i);
      if (bytes > kMaxCsvLineBytes)
        too_long("line " + std::to_string(i + 2), bytes);  // after the header
    }
  }
  WriteFileAtomically(
      path,
      [&](std::ostream& os) {
        os.write(header.data(), static_cast<std::streamsize>(header.size()));
        for (Eigen::Index i = 0; i < rows; ++i) {
          const std::size_t bytes = format_row(i);
          buffer[bytes] = '\n';
          os.write(buffer.data(), static_cast<std::streamsize>(bytes + 1));
        }
      },
      batch);
}

}  // namespace podid
