// Universal files (UFF): time responses from data sets 58 and 58b (io.hpp,
// ReadUff). Format: the I-DEAS universal file data set 58 (records 1-11 of
// fixed-width text, then the data: 6E13.5 or 4E20.12 per line in ASCII, raw
// IEEE 754 in 58b after a first line giving byte order, format and size).
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "io_internal.hpp"
#include "podid/core/error.hpp"
#include "podid/core/io.hpp"

namespace podid {
namespace {

using internal::CleanText;

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

/// Lines (at most kMaxUffLineBytes) and raw blocks of one file.
class UffFile {
 public:
  explicit UffFile(const std::string& path) : path_(path) {
    internal::RequireRegularFile(path, "a readable universal file (.uff)");
    file_.reset(std::fopen(path.c_str(), "rb"));
    if (!file_) {
      ThrowInvalid(path, "a readable universal file (.uff)",
                   std::string("\"") + std::strerror(errno) + "\"");
    }
    struct stat status {};
    size_ =
        ::fstat(fileno(file_.get()), &status) == 0 ? static_cast<std::uint64_t>(status.st_size) : 0;
  }

  /// The next line without "\r\n"; false at the end of the file.
  bool Next(std::string& line) {
    line.clear();
    bool any = false;
    while (true) {
      if (begin_ == end_ && !Refill()) break;
      any = true;
      const char* start = buffer_.data() + begin_;
      const auto* newline = static_cast<const char*>(std::memchr(start, '\n', end_ - begin_));
      const std::size_t take =
          newline != nullptr ? static_cast<std::size_t>(newline - start) : end_ - begin_;
      if (line.size() + take > kMaxUffLineBytes) {
        ThrowInvalid(Where(line_number_ + 1),
                     "a line of at most " + std::to_string(kMaxUffLineBytes) + " bytes",
                     "a longer line");
      }
      line.append(start, take);
      const std::size_t consumed = take + (newline != nullptr ? 1 : 0);
      begin_ += consumed;
      offset_ += consumed;
      if (newline != nullptr) break;
    }
    if (!any) return false;
    ++line_number_;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  }

  /// Reads exactly n bytes (n <= Remaining() checked by the caller).
  void Read(char* out, std::size_t n) {
    const std::size_t buffered = std::min(n, end_ - begin_);
    std::memcpy(out, buffer_.data() + begin_, buffered);
    begin_ += buffered;
    if (std::fread(out + buffered, 1, n - buffered, file_.get()) != n - buffered) {
      ThrowInvalid(Where(line_number_ + 1), std::to_string(n) + " bytes of binary data",
                   "the end of the file");
    }
    offset_ += n;
  }

  std::uint64_t Remaining() const { return size_ > offset_ ? size_ - offset_ : 0; }
  long long line_number() const { return line_number_; }
  std::string Where(long long line) const { return path_ + ":" + std::to_string(line); }

 private:
  bool Refill() {
    begin_ = 0;
    end_ = std::fread(buffer_.data(), 1, buffer_.size(), file_.get());
    return end_ > 0;
  }

  std::string path_;
  std::unique_ptr<std::FILE, FileCloser> file_;
  std::vector<char> buffer_ = std::vector<char>(std::size_t{1} << 16);  // read ahead
  std::size_t begin_ = 0, end_ = 0;
  std::uint64_t size_ = 0, offset_ = 0;  // offset_: bytes handed out
  long long line_number_ = 0;
};

bool IsDelimiter(std::string_view line) { return Trim(line) == "-1"; }

/// Numbers of a line, also when fixed-width fields run together ("1.0E+00-2.0E+00").
bool ScanNumbers(std::string_view line, std::vector<double>& out, std::size_t max) {
  std::size_t i = 0;
  while (i < line.size() && out.size() < max) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    if (i == line.size()) break;
    if (line[i] == '+') ++i;
    double value = 0.0;
    const auto [ptr, ec] = std::from_chars(line.data() + i, line.data() + line.size(), value);
    if (ec != std::errc() || !std::isfinite(value)) return false;
    out.push_back(value);
    i = static_cast<std::size_t>(ptr - line.data());
  }
  return Trim(line.substr(std::min(i, line.size()))).empty();
}

/// A fixed-width integer field of a record; false if it is not one.
bool Field(std::string_view line, std::size_t begin, std::size_t width, long long& value) {
  if (begin >= line.size()) return false;
  const std::string_view text = Trim(line.substr(begin, width));
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return !text.empty() && ec == std::errc() && ptr == text.data() + text.size();
}

std::string DirectionText(long long direction) {
  static const char* const kNames[] = {"S", "+X", "+Y", "+Z", "+RX", "+RY", "+RZ"};
  if (direction >= 0 && direction <= 6) return kNames[direction];
  if (direction >= -6 && direction <= -1) {
    std::string name = kNames[-direction];
    name[0] = '-';
    return name;
  }
  return ":" + std::to_string(direction);
}

/// One time response read from a data set 58/58b.
struct Response {
  std::string name, unit;
  double start_s = 0.0, step_s = 0.0;
  std::vector<double> values;
  long long line = 0;
};

/// Skips to the data set's closing "-1"; false at the end of the file.
void SkipToDelimiter(UffFile& file, std::string& line) {
  while (file.Next(line)) {
    if (IsDelimiter(line)) return;
  }
}

/// `value` as an int when it is a whole number of at most 9 digits, else -1
/// (every code these records hold is small and >= 0).
int SmallInteger(double value) {
  return value >= 0 && value <= 999999999.0 && value == std::floor(value) ? static_cast<int>(value)
                                                                           : -1;
}

/// Reads a data set 58 or 58b whose first line (with the "58") is `first`.
/// Returns true with `out` filled for a time response; false (a note added)
/// when it is skipped. Leaves the file after the closing "-1".
bool ReadDataSet58(UffFile& file,
                   std::string_view first,
                   std::size_t values_so_far,
                   Response& out,
                   std::vector<std::string>* notes) {
  const long long first_line = file.line_number();
  const bool binary = Trim(first).substr(0, 3) == "58b";
  int byte_order = 1, format = 2;
  long long binary_bytes = 0;
  if (binary) {
    std::vector<double> fields;
    if (!ScanNumbers(Trim(first).substr(3), fields, 8) || fields.size() < 4) {
      ThrowInvalid(file.Where(first_line), "a 58b header: byte order, format, lines, bytes",
                   "\"" + CleanText(first.substr(0, 80)) + "\"");
    }
    // Range-checked before any conversion: a cast of an out-of-range double is
    // undefined behaviour (1.1e18 as a byte order, found by podid_fuzz_uff).
    byte_order = SmallInteger(fields[0]);
    format = SmallInteger(fields[1]);
    binary_bytes = fields[3] >= 0 && fields[3] <= 9.0e15 && fields[3] == std::floor(fields[3])
                       ? static_cast<long long>(fields[3])
                       : -1;
    if ((byte_order != 1 && byte_order != 2) || format != 2 || binary_bytes < 0) {
      ThrowInvalid(file.Where(first_line),
                   "a 58b header with byte order 1 (little endian) or 2 (big), format 2 (IEEE 754) "
                   "and a byte count >= 0",
                   "byte order " + ToText(fields[0]) + ", format " + ToText(fields[1]) + ", " +
                       ToText(fields[3]) + " bytes");
    }
  }
  std::string records[11];
  for (int r = 0; r < 11; ++r) {
    if (!file.Next(records[r]) || IsDelimiter(records[r])) {
      ThrowInvalid(file.Where(file.line_number()),
                   "record " + std::to_string(r + 1) + " of 11 of data set 58",
                   "the end of the data set");
    }
  }
  const std::string& r6 = records[5];
  long long function_type = 0, node = 0, direction = 0;
  bool ok6 =
      Field(r6, 0, 5, function_type) && Field(r6, 41, 10, node) && Field(r6, 51, 4, direction);
  if (!ok6) {  // not in its columns: the last five fields as tokens
    std::vector<std::string_view> tokens;
    for (std::size_t i = 0; i < r6.size();) {
      while (i < r6.size() && r6[i] == ' ') ++i;
      const std::size_t b = i;
      while (i < r6.size() && r6[i] != ' ') ++i;
      if (i > b) tokens.emplace_back(std::string_view(r6).substr(b, i - b));
    }
    ok6 = tokens.size() >= 9 && Field(tokens[0], 0, 40, function_type) &&
          Field(tokens[tokens.size() - 5], 0, 40, node) &&
          Field(tokens[tokens.size() - 4], 0, 40, direction);
  }
  if (!ok6) {
    ThrowInvalid(file.Where(first_line + (binary ? 6 : 6)),
                 "record 6: function type, ..., response node and direction",
                 "\"" + CleanText(r6.substr(0, 80)) + "\"");
  }
  // Record 7: 3I10 (type, count, spacing), then 3E13.5; the integers in their
  // columns when they are there (a 10-digit count touches the type).
  std::vector<double> r7;
  long long r7_int[3] = {};
  if (Field(records[6], 0, 10, r7_int[0]) && Field(records[6], 10, 10, r7_int[1]) &&
      Field(records[6], 20, 10, r7_int[2])) {
    for (long long v : r7_int) r7.push_back(static_cast<double>(v));
    if (!ScanNumbers(
            std::string_view(records[6]).substr(std::min<std::size_t>(30, records[6].size())), r7,
            6))
      r7.clear();
  } else if (!ScanNumbers(records[6], r7, 6)) {
    r7.clear();
  }
  if (r7.size() < 5) {
    ThrowInvalid(file.Where(first_line + 7),
                 "record 7: data type, count, spacing, start, increment",
                 "\"" + CleanText(std::string_view(records[6]).substr(0, 80)) + "\"");
  }
  const int data_type = SmallInteger(r7[0]);
  const double count = r7[1];
  const bool even = r7[2] == 1.0;
  const double start = r7[3], increment = r7[4];
  const bool complex = data_type == 5 || data_type == 6;
  const bool known_type = data_type == 2 || data_type == 4 || complex;
  const double per_value = (complex ? 2.0 : 1.0) * (even ? 1.0 : 2.0);
  if (!known_type || !(count >= 0) || count != std::floor(count)) {
    ThrowInvalid(file.Where(first_line + 7),
                 "record 7: data type 2, 4, 5 or 6 and a whole count >= 0",
                 "type " + ToText(r7[0]) + ", count " + ToText(count));
  }
  // Bounds before any allocation: the file must hold the data.
  const double numbers = count * per_value;
  const double element_bytes = binary ? (data_type == 2 || data_type == 5 ? 4.0 : 8.0) : 1.0;
  if (binary && (numbers * element_bytes != static_cast<double>(binary_bytes))) {
    ThrowInvalid(file.Where(first_line),
                 std::to_string(binary_bytes) + " bytes of data as the 58b header says",
                 ToText(numbers) + " numbers of " + ToText(element_bytes) + " bytes (record 7)");
  }
  if (numbers * element_bytes > static_cast<double>(file.Remaining())) {
    ThrowInvalid(
        file.Where(first_line + 7),
        "a count whose data fits in the " + std::to_string(file.Remaining()) + " bytes left",
        ToText(count) + " values (a corrupt or truncated file)");
  }
  const bool wanted = function_type == 1 && even && !complex;
  if (wanted && count + static_cast<double>(values_so_far) > static_cast<double>(kMaxReadValues)) {
    ThrowInvalid(file.Where(first_line + 7),
                 "at most " + std::to_string(kMaxReadValues) + " values in all (kMaxReadValues)",
                 ToText(count + static_cast<double>(values_so_far)));
  }
  const auto n = static_cast<std::size_t>(numbers);
  std::string line;
  std::vector<double> data;
  if (wanted) data.reserve(n);
  if (binary) {
    if (wanted) {
      const std::size_t size = static_cast<std::size_t>(element_bytes);
      std::vector<char> raw(n * size);
      file.Read(raw.data(), raw.size());
      const bool swap = byte_order == 2;  // big endian on this little-endian reader
      for (std::size_t i = 0; i < n; ++i) {
        char* p = raw.data() + i * size;
        if (swap) std::reverse(p, p + size);
        double value = 0.0;
        if (size == 4) {
          float f = 0.0f;
          std::memcpy(&f, p, 4);
          value = f;
        } else {
          std::memcpy(&value, p, 8);
        }
        if (!std::isfinite(value)) {
          ThrowInvalid(file.Where(first_line + 12),
                       "finite numbers (value " + std::to_string(i + 1) + ")", ToText(value));
        }
        data.push_back(value);
      }
    } else {
      std::vector<char> skip(std::size_t{1} << 16);
      for (std::size_t left = n * static_cast<std::size_t>(element_bytes); left > 0;) {
        const std::size_t piece = std::min(left, skip.size());
        file.Read(skip.data(), piece);
        left -= piece;
      }
    }
    while (file.Next(line) && Trim(line).empty()) {
    }
    if (!IsDelimiter(line)) {
      ThrowInvalid(file.Where(file.line_number()),
                   "the end of the data set (\"    -1\") after the binary data",
                   "\"" + CleanText(std::string_view(line).substr(0, 40)) + "\"");
    }
  } else if (wanted) {
    while (data.size() < n) {
      if (!file.Next(line) || IsDelimiter(line)) {
        ThrowInvalid(file.Where(file.line_number()), std::to_string(n) + " values (record 7)",
                     std::to_string(data.size()) + " values");
      }
      if (!ScanNumbers(line, data, n)) {
        ThrowInvalid(file.Where(file.line_number()), "finite numbers (6E13.5 or 4E20.12)",
                     "\"" + CleanText(std::string_view(line).substr(0, 40)) + "\"");
      }
    }
    while (file.Next(line) && Trim(line).empty()) {
    }
    if (!IsDelimiter(line)) {
      ThrowInvalid(file.Where(file.line_number()),
                   "the end of the data set (\"    -1\") after " + std::to_string(n) + " values",
                   "more data");
    }
  } else {
    SkipToDelimiter(file, line);
  }
  if (!wanted) {
    if (notes) {
      notes->push_back(
          file.Where(first_line) + ": data set 58 of function type " +
          std::to_string(function_type) + (complex ? ", complex" : "") +
          (even ? "" : ", uneven abscissa") +
          " skipped (only time responses, function type 1, real and evenly sampled, are read)");
    }
    return false;
  }
  if (!(increment > 0.0) || !std::isfinite(start)) {
    ThrowInvalid(file.Where(first_line + 7), "an abscissa increment > 0 s (record 7)",
                 ToText(increment));
  }
  std::string unit =
      CleanText(records[8].size() > 47 ? std::string_view(records[8]).substr(47) : "");
  const std::string denominator =
      CleanText(records[9].size() > 47 ? std::string_view(records[9]).substr(47) : "");
  if (unit == "NONE") unit = "";
  if (!denominator.empty() && denominator != "NONE") unit += "/" + denominator;
  out.name = std::to_string(node) + DirectionText(direction);
  out.unit = unit;
  out.start_s = start;
  out.step_s = increment;
  out.values = std::move(data);
  out.line = first_line;
  return true;
}

}  // namespace

TimeSeries ReadUff(const std::string& path, std::vector<std::string>* notes_out) {
  std::vector<std::string> local_notes;
  std::vector<std::string>* notes = &local_notes;
  UffFile file(path);
  std::vector<Response> responses;
  std::size_t values = 0;
  std::string line;
  while (file.Next(line)) {
    if (Trim(line).empty()) continue;
    if (!IsDelimiter(line)) {
      ThrowInvalid(file.Where(file.line_number()), "a data set starting with \"    -1\"",
                   "\"" + CleanText(std::string_view(line).substr(0, 40)) + "\"");
    }
    if (!file.Next(line)) break;
    const std::string_view type = Trim(line).substr(0, Trim(line).find(' '));
    if (type == "58" || type == "58b") {
      Response response;
      if (ReadDataSet58(file, line, values, response, notes)) {
        values += response.values.size();
        responses.push_back(std::move(response));
      }
    } else {
      const long long at = file.line_number();
      if (notes)
        notes->push_back(file.Where(at) + ": data set " + CleanText(type.substr(0, 12)) +
                         " skipped");
      SkipToDelimiter(file, line);
    }
  }
  if (responses.empty()) {
    std::string skipped;
    for (const auto& note : local_notes) skipped += "; " + note.substr(path.size() + 1);
    ThrowInvalid(path, "a data set 58 or 58b with a time response (function type 1)",
                 "none" + (skipped.empty() ? std::string() : " (" + skipped.substr(2) + ")"));
  }
  if (notes_out) notes_out->insert(notes_out->end(), local_notes.begin(), local_notes.end());
  const Response& first = responses[0];
  for (const Response& r : responses) {
    const bool same =
        r.values.size() == first.values.size() &&
        std::abs(r.step_s - first.step_s) <= kTimeStepRelativeTolerance * first.step_s &&
        std::abs(r.start_s - first.start_s) <= kTimeStepRelativeTolerance * first.step_s;
    if (!same) {
      ThrowInvalid(file.Where(r.line),
                   "the grid of the first time response (line " + std::to_string(first.line) +
                       "): " + std::to_string(first.values.size()) + " samples from " +
                       ToText(first.start_s) + " s every " + ToText(first.step_s) + " s",
                   std::to_string(r.values.size()) + " samples from " + ToText(r.start_s) +
                       " s every " + ToText(r.step_s) + " s");
    }
  }
  const auto samples = static_cast<Eigen::Index>(first.values.size());
  if (samples < 2)
    ThrowInvalid(file.Where(first.line), "at least 2 samples", std::to_string(samples));
  TimeSeries series;
  series.time_s = internal::UniformTimes(first.start_s, first.step_s, first.values.size(),
                                         file.Where(first.line + 7) + " (record 7)");
  series.values.resize(samples, static_cast<Eigen::Index>(responses.size()));
  // A repeated name gets _2, _3, ... (the first free one: a file may name
  // another channel "a_2" already). Hashed: a file of 10^6 two-sample data
  // sets compared every name with every earlier one.
  std::unordered_map<std::string, int> repeats;
  std::unordered_set<std::string> used;
  for (std::size_t j = 0; j < responses.size(); ++j) {
    Response& r = responses[j];
    std::copy(r.values.begin(), r.values.end(),
              series.values.col(static_cast<Eigen::Index>(j)).data());
    std::vector<double>().swap(r.values);
    std::string name = r.name;
    int& repeat = repeats[r.name];
    while (!used.insert(name).second) name = r.name + "_" + std::to_string(++repeat + 1);
    series.channel_names.push_back(std::move(name));
    series.units.push_back(r.unit);
  }
  return series;
}

}  // namespace podid
