// Structural checks of .mat files before libmatio reads them (mat_structure.hpp).
#include "mat_structure.hpp"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "podid/core/error.hpp"
#include "podid/core/io.hpp"

namespace podid::internal {
namespace {

constexpr std::uint64_t kUnbounded = std::numeric_limits<std::uint64_t>::max();
constexpr int kMaxDepth = 64;                  // nesting deeper than this is no time series
constexpr std::uint64_t kMaxDimsBytes = 4096;  // 1024 dimensions

// Data types and array classes of the level 5 format.
constexpr std::uint32_t kMiInt8 = 1;
constexpr std::uint32_t kMiInt32 = 5;
constexpr std::uint32_t kMiUint32 = 6;
constexpr std::uint32_t kMiMatrix = 14;
constexpr std::uint32_t kMiCompressed = 15;
constexpr std::uint32_t kClassCell = 1;
constexpr std::uint32_t kClassStruct = 2;
constexpr std::uint32_t kClassObject = 3;
constexpr std::uint32_t kClassChar = 4;
constexpr std::uint32_t kClassSparse = 5;
constexpr std::uint32_t kClassUint64 = 15;
constexpr std::uint32_t kClassFunction = 16;
constexpr std::uint32_t kFlagComplex = 0x0800;  // in the array flags' first word

/// Bytes read in order from a file region or an inflated stream; position()
/// counts from the source's start.
class ByteSource {
 public:
  virtual ~ByteSource() = default;
  /// Reads exactly n bytes; false when the source ends first.
  virtual bool Read(char* out, std::size_t n) = 0;
  /// Skips exactly n bytes; false when the source ends first.
  virtual bool Skip(std::uint64_t n) = 0;
  std::uint64_t position() const { return position_; }
  /// Why the source ended early (a corrupt compressed stream); empty if it did not.
  const std::string& error() const { return error_; }

 protected:
  std::uint64_t position_ = 0;
  std::string error_;
};

class FileSource final : public ByteSource {
 public:
  FileSource(std::ifstream& in, std::uint64_t size) : in_(in), size_(size) {}
  bool Read(char* out, std::size_t n) override {
    if (n > size_ - position_) return false;
    in_.seekg(static_cast<std::streamoff>(position_));
    in_.read(out, static_cast<std::streamsize>(n));
    if (!in_) return false;
    position_ += n;
    return true;
  }
  bool Skip(std::uint64_t n) override {
    if (n > size_ - position_) return false;
    position_ += n;
    return true;
  }

 private:
  std::ifstream& in_;
  std::uint64_t size_;
};

/// The zlib stream of an miCOMPRESSED element, inflated in 64 KiB pieces.
class InflateSource final : public ByteSource {
 public:
  InflateSource(std::ifstream& in, std::uint64_t offset, std::uint64_t bytes)
      : in_(in), next_in_offset_(offset), remaining_in_(bytes), input_(16384), output_(65536) {
    ok_ = inflateInit(&stream_) == Z_OK;
    if (!ok_) error_ = "zlib could not start";
  }
  ~InflateSource() override {
    if (ok_) inflateEnd(&stream_);
  }
  InflateSource(const InflateSource&) = delete;
  InflateSource& operator=(const InflateSource&) = delete;

  bool Read(char* out, std::size_t n) override {
    while (n > 0) {
      if (begin_ == end_ && !Fill()) return false;
      const std::size_t take = std::min(n, end_ - begin_);
      std::memcpy(out, output_.data() + begin_, take);
      begin_ += take;
      out += take;
      n -= take;
      position_ += take;
    }
    return true;
  }
  bool Skip(std::uint64_t n) override {
    while (n > 0) {
      if (begin_ == end_ && !Fill()) return false;
      const std::size_t take = static_cast<std::size_t>(std::min<std::uint64_t>(n, end_ - begin_));
      begin_ += take;
      n -= take;
      position_ += take;
    }
    return true;
  }

 private:
  /// Inflates the next piece of output; false at the stream's end or on an
  /// error (then error() says which: a stream that is corrupt, fails its
  /// checksum or ends early is rejected, whatever libmatio would make of it).
  bool Fill() {
    if (!ok_ || finished_) return false;
    begin_ = end_ = 0;
    while (end_ == 0) {
      if (stream_.avail_in == 0) {
        if (remaining_in_ == 0) {
          error_ = "compressed data that ends before its zlib stream does";
          return false;
        }
        const std::size_t take =
            static_cast<std::size_t>(std::min<std::uint64_t>(remaining_in_, input_.size()));
        in_.seekg(static_cast<std::streamoff>(next_in_offset_));
        in_.read(reinterpret_cast<char*>(input_.data()), static_cast<std::streamsize>(take));
        if (!in_) return false;
        next_in_offset_ += take;
        remaining_in_ -= take;
        stream_.next_in = input_.data();
        stream_.avail_in = static_cast<uInt>(take);
      }
      stream_.next_out = output_.data();
      stream_.avail_out = static_cast<uInt>(output_.size());
      const int status = inflate(&stream_, Z_NO_FLUSH);
      end_ = output_.size() - stream_.avail_out;
      if (status == Z_STREAM_END) {
        finished_ = true;
        return end_ > 0;
      }
      if (status != Z_OK && status != Z_BUF_ERROR) {
        error_ =
            std::string("zlib: ") + (stream_.msg != nullptr ? stream_.msg : std::to_string(status));
        return false;
      }
    }
    return true;
  }

  std::ifstream& in_;
  std::uint64_t next_in_offset_;
  std::uint64_t remaining_in_;
  std::vector<unsigned char> input_, output_;
  std::size_t begin_ = 0, end_ = 0;
  z_stream stream_{};
  bool ok_ = false, finished_ = false;
};

/// One data element's tag: small elements carry up to 4 bytes in the tag.
struct Tag {
  std::uint32_t type = 0;
  std::uint64_t size = 0;  // data bytes
  bool small = false;
  std::array<char, 4> small_data{};
};

/// Walks a level 5 file the way libmatio reads it, accepting only the
/// canonical layout that MATLAB writes (strict, so that libmatio can never read
/// a header differently from this walk): top-level miMATRIX or miCOMPRESSED
/// elements; in each miMATRIX, array flags (miUINT32, 8 bytes), dimensions
/// (miINT32, 2..1024 of them), a name (miINT8), then by class a class name
/// (objects), a field name length (small miINT32) and field names (miINT8)
/// (structs, objects), and the cells or fields as miMATRIX elements (function
/// handles, which libmatio reads as cell arrays, too).
class Mat5Walker {
 public:
  Mat5Walker(const std::string& path, std::ifstream& in, bool swap)
      : path_(path), in_(in), swap_(swap) {}

  /// The variables of `src` up to `end` (kUnbounded: to the source's end).
  /// They are not padded and may be followed by fewer than 8 stray bytes.
  void Variables(ByteSource& src, std::uint64_t end) {
    while (src.position() < end) {
      Tag tag;
      if (end - src.position() < 8 || !ReadTag(src, tag)) {
        if (!src.error().empty())
          Fail(src.position(), "compressed data that inflates", src.error());
        return;  // the end, or fewer than 8 stray bytes: matio stops there too
      }
      const std::uint64_t at = src.position() - 8;
      const bool compressed = tag.type == kMiCompressed && !inflating_;
      if (tag.small || (tag.type != kMiMatrix && !compressed)) {
        Fail(at,
             inflating_ ? "an miMATRIX element (type 14)"
                        : "a variable: an miMATRIX or miCOMPRESSED element (type 14 or 15)",
             TagText(tag));
      }
      CheckFits(src, end, tag, "a variable");
      const std::uint64_t element_end = src.position() + tag.size;
      if (compressed) {
        inflating_ = true;
        compressed_at_ = at;
        {
          InflateSource inflated(in_, src.position(), tag.size);
          Variables(inflated, kUnbounded);
        }
        inflating_ = false;
      } else {
        Matrix(src, element_end, 1);
      }
      SkipTo(src, element_end);
    }
  }

 private:
  /// The content of one miMATRIX element, ending at `end`.
  void Matrix(ByteSource& src, std::uint64_t end, int depth) {
    if (src.position() == end) return;  // an empty element (an empty cell)
    if (depth > kMaxDepth)
      Fail(src.position(), "at most " + std::to_string(kMaxDepth) + " nested arrays", "more");
    const std::vector<char> flags = SubElement(src, end, "array flags", kMiUint32, false, 8);
    if (flags.size() != 8)
      Fail(src.position(), "array flags of 8 bytes", std::to_string(flags.size()) + " bytes");
    const std::uint32_t array_class = Word(flags.data()) & 0xFFu;  // the class is the low byte
    const std::vector<char> dims =
        SubElement(src, end, "dimensions", kMiInt32, false, kMaxDimsBytes);
    if (dims.size() < 8 || dims.size() % 4 != 0) {
      Fail(src.position(),
           "2 to " + std::to_string(kMaxDimsBytes / 4) + " dimensions (4 bytes each)",
           std::to_string(dims.size()) + " bytes of them");
    }
    double elements = 1.0;  // a double: the product saturates rather than overflows
    for (std::size_t i = 0; i < dims.size(); i += 4) {
      const auto dim = static_cast<std::int32_t>(Word(dims.data() + i));
      if (dim < 0) Fail(src.position(), "non-negative dimensions", std::to_string(dim));
      elements *= static_cast<double>(dim);
    }
    SubElement(src, end, "array name", kMiInt8, true, 0);
    if (array_class == kClassObject) SubElement(src, end, "class name", kMiInt8, true, 0);

    double tags_needed = 0.0;  // 8-byte miMATRIX tags the rest of the element must hold
    double bytes_needed = 0.0;
    std::string what;
    bool walk_children = false;  // cells, function handles, struct fields
    if (array_class == kClassCell || array_class == kClassFunction) {
      tags_needed = elements;  // libmatio reads a function handle as a cell array
      walk_children = true;
      what = "a cell array";
    } else if (array_class == kClassStruct || array_class == kClassObject) {
      const std::vector<char> length = SubElement(src, end, "field name length", kMiInt32, true, 4);
      if (length.size() != 4) {
        Fail(src.position(), "a field name length of 4 bytes",
             std::to_string(length.size()) + " bytes");
      }
      const std::uint32_t name_length = Word(length.data());
      std::uint64_t names_bytes = 0;
      SubElement(src, end, "field names", kMiInt8, true, 0, &names_bytes);
      const double fields = name_length == 0 ? 0.0 : static_cast<double>(names_bytes / name_length);
      tags_needed = elements * fields;
      walk_children = true;
      what = "a struct";
    } else if (array_class > kClassSparse && array_class <= kClassUint64) {
      // libmatio reads `elements` values of the part's type whatever the
      // element's size says, and none of a type it does not convert (leaving
      // the array uninitialised): each part must hold exactly those values.
      NumericPart(src, end, elements, false, "real part");
      if (Word(flags.data()) & kFlagComplex)
        NumericPart(src, end, elements, false, "imaginary part");
    } else if (array_class == kClassSparse) {
      // libmatio counts a sparse array's values from the element sizes, but
      // reads none of a type it does not convert (leaving them uninitialised).
      NumericPart(src, end, -1.0, true, "row indices");
      NumericPart(src, end, -1.0, true, "column pointers");
      NumericPart(src, end, -1.0, false, "real part");
      if (Word(flags.data()) & kFlagComplex) NumericPart(src, end, -1.0, false, "imaginary part");
    } else if (array_class == kClassChar) {
      bytes_needed = elements;  // int8 storage at least
      what = "an array";
    } else {
      tags_needed = elements;  // opaque and unknown classes: as much as a cell array, not walked
      what = "an array of class " + std::to_string(array_class);
    }
    const double room = static_cast<double>(end - src.position());
    if (tags_needed * 8.0 > room || bytes_needed > room) {
      Fail(src.position(),
           what + " whose " + ToText(elements) + " elements fit in the " + ToText(room) +
               " bytes that follow",
           "more (a corrupt or truncated file)");
    }
    if (array_class == kClassChar) CharPart(src, end, elements);
    // The cells, or each element's fields, are miMATRIX elements.
    for (double i = 0; walk_children && i < tags_needed; ++i) {
      Tag tag;
      if (end - src.position() < 8 || !ReadTag(src, tag)) {
        Fail(src.position(), what + " of " + ToText(tags_needed) + " arrays", ToText(i));
      }
      if (tag.small || tag.type != kMiMatrix) {
        Fail(src.position() - 8, "an miMATRIX element (type 14) in " + what, TagText(tag));
      }
      CheckFits(src, end, tag, "an array");
      const std::uint64_t element_end = src.position() + tag.size;
      Matrix(src, element_end, depth + 1);
      SkipTo(src, element_end);
    }
    SkipTo(src, end);
  }

  /// Reads one subelement of an miMATRIX of the given type (small or not, as
  /// `small_allowed`), padding included; returns its data when it has at most
  /// `keep` bytes (else skips it), and its size in `bytes`.
  std::vector<char> SubElement(ByteSource& src,
                               std::uint64_t end,
                               const char* name,
                               std::uint32_t type,
                               bool small_allowed,
                               std::uint64_t keep,
                               std::uint64_t* bytes = nullptr) {
    Tag tag;
    if (end - src.position() < 8 || !ReadTag(src, tag)) {
      Fail(src.position(), std::string("the ") + name + " of an array", "the end of its element");
    }
    if (tag.type != type || (tag.small && !small_allowed) || (tag.small && tag.size > 4)) {
      Fail(src.position() - 8,
           std::string("the ") + name + ": an element of type " + std::to_string(type) +
               (small_allowed ? "" : " (not small)"),
           TagText(tag));
    }
    if (bytes != nullptr) *bytes = tag.size;
    if (tag.small)
      return std::vector<char>(tag.small_data.begin(), tag.small_data.begin() + tag.size);
    const std::uint64_t padded = PaddedSize(src, end, tag, name);
    std::vector<char> data;
    if (tag.size <= keep) {
      data.resize(static_cast<std::size_t>(tag.size));
      if (!src.Read(data.data(), data.size())) {
        Fail(src.position(), std::string("the ") + name,
             src.error().empty() ? "the end of the " + SourceName() : src.error());
      }
      SkipTo(src, src.position() + (padded - tag.size));
    } else {
      SkipTo(src, src.position() + padded);
    }
    return data;
  }

  /// One part of a numeric array: an element of a numeric type (int8 ..
  /// uint64, single, double; miINT32 or miUINT32 only if `indices`) with
  /// exactly `values` values of that type (any whole number if `values` < 0).
  void NumericPart(
      ByteSource& src, std::uint64_t end, double values, bool indices, const char* name) {
    Tag tag;
    if (end - src.position() < 8 || !ReadTag(src, tag)) {
      Fail(src.position(), std::string("the ") + name + " of an array", "the end of its element");
    }
    // Bytes per value of the types libmatio converts to numbers: miINT8 (1)
    // to miUINT32 (6), miSINGLE (7), miDOUBLE (9), miINT64 (12), miUINT64 (13).
    static constexpr std::uint64_t kUnit[14] = {0, 1, 1, 2, 2, 4, 4, 4, 0, 8, 0, 0, 8, 8};
    std::uint64_t unit = tag.type < 14 ? kUnit[tag.type] : 0;
    if (indices && tag.type != 5 && tag.type != 6) unit = 0;  // miINT32, miUINT32 only
    const bool count_ok = values < 0
                              ? unit != 0 && tag.size % unit == 0
                              : static_cast<double>(tag.size) == values * static_cast<double>(unit);
    if (unit == 0 || !count_ok || (tag.small && tag.size > 4)) {
      const std::string count = values < 0 ? "a whole number of" : ToText(values);
      Fail(src.position() - 8,
           std::string("the ") + name + ": " + count + " values in an element of " +
               (indices ? "type 5 or 6 (int32)" : "a numeric type (1-7, 9, 12 or 13)"),
           TagText(tag));
    }
    if (tag.small) return;  // the data is in the tag
    const std::uint64_t padded = PaddedSize(src, end, tag, name);
    SkipTo(src, src.position() + padded);
  }

  /// The characters of a char array: one element, small or not, inside the
  /// array's element, of at most 4 bytes a character (UTF-8's longest).
  /// libmatio allocates the element's size as its tag says (read as an int: a
  /// size of 2^31 or more became a request of nearly 2^64 bytes).
  void CharPart(ByteSource& src, std::uint64_t end, double elements) {
    Tag tag;
    if (end - src.position() < 8 || !ReadTag(src, tag)) {
      Fail(src.position(), "the characters of an array", "the end of its element");
    }
    if ((tag.small && tag.size > 4) || static_cast<double>(tag.size) > 4.0 * elements) {
      Fail(src.position() - 8,
           "the characters: at most 4 bytes each of the " + ToText(elements) + " in an element",
           TagText(tag));
    }
    if (tag.small) return;
    SkipTo(src, src.position() + PaddedSize(src, end, tag, "characters"));
  }

  /// A (not small) element's size padded to 8 bytes, checked to end by `end`
  /// (its tag just read).
  std::uint64_t PaddedSize(const ByteSource& src,
                           std::uint64_t end,
                           const Tag& tag,
                           const char* name) {
    const std::uint64_t padded = (tag.size + 7) / 8 * 8;
    if (padded > end - src.position()) {
      Fail(src.position() - 8,
           std::string("the ") + name + " in at most " + std::to_string(end - src.position()) +
               " bytes",
           std::to_string(tag.size) + " bytes (a corrupt or truncated file)");
    }
    return padded;
  }

  /// Checks that an element's data, after its tag, ends by `end`.
  void CheckFits(const ByteSource& src, std::uint64_t end, const Tag& tag, const char* what) {
    if (end != kUnbounded && tag.size > end - src.position()) {
      Fail(src.position() - 8,
           std::string(what) + " of at most " + std::to_string(end - src.position()) + " bytes",
           std::to_string(tag.size) + " bytes (a corrupt or truncated file)");
    }
  }

  bool ReadTag(ByteSource& src, Tag& tag) {
    char bytes[8];
    if (!src.Read(bytes, 8)) return false;
    const std::uint32_t first = Word(bytes);
    tag.small = (first >> 16) != 0;  // small element: (bytes << 16 | type), then the data
    if (tag.small) {
      tag.type = first & 0xFFFFu;
      tag.size = first >> 16;
      std::memcpy(tag.small_data.data(), bytes + 4, 4);
    } else {
      tag.type = first;
      tag.size = Word(bytes + 4);
    }
    return true;
  }

  static std::string TagText(const Tag& tag) {
    return std::string(tag.small ? "a small element" : "an element") + " of type " +
           std::to_string(tag.type) + " and " + std::to_string(tag.size) + " bytes";
  }

  void SkipTo(ByteSource& src, std::uint64_t to) {
    if (to > src.position() && !src.Skip(to - src.position())) {
      Fail(src.position(), "the rest of a data element",
           src.error().empty() ? "the end of the " + SourceName() : src.error());
    }
  }

  std::string SourceName() const { return inflating_ ? "compressed data" : "file"; }

  std::uint32_t Word(const char* at) const {
    std::uint32_t v = 0;
    std::memcpy(&v, at, 4);
    return swap_ ? __builtin_bswap32(v) : v;
  }

  [[noreturn]] void Fail(std::uint64_t at, const std::string& expected, const std::string& got) {
    const std::string where = inflating_ ? "compressed variable at byte " +
                                               std::to_string(compressed_at_) + ", inflated byte " +
                                               std::to_string(at)
                                         : "byte " + std::to_string(at);
    ThrowInvalid(path_ + ": " + where, expected, got);
  }

  const std::string& path_;
  std::ifstream& in_;
  bool swap_;
  bool inflating_ = false;
  std::uint64_t compressed_at_ = 0;
};

std::uint64_t FileSize(std::ifstream& in) {
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  in.seekg(0);
  return size > 0 ? static_cast<std::uint64_t>(size) : 0;
}

void CheckMat5Structure(const std::string& path, std::ifstream& in, std::uint64_t size, bool swap) {
  constexpr std::uint64_t kHeaderBytes = 128;
  FileSource file(in, size);
  file.Skip(kHeaderBytes);
  Mat5Walker walker(path, in, swap);
  walker.Variables(file, size);
}

// A v4 sparse matrix's size, its last row (i = rows, j = columns) as doubles
// at `data`: each at most kMaxReadValues, so that libmatio's column pointers
// (4 bytes a column, and a pass over them) stay bounded whatever the file says.
void CheckMat4SparseSize(std::ifstream& in,
                         std::uint64_t data,
                         std::int32_t rows,
                         bool big_endian,
                         const std::string& where) {
  for (int column = 0; column < 2; ++column) {
    const std::uint64_t offset =
        data + (static_cast<std::uint64_t>(column) * static_cast<std::uint64_t>(rows) +
                static_cast<std::uint64_t>(rows) - 1) *
                   8;
    std::uint64_t bits = 0;
    in.seekg(static_cast<std::streamoff>(offset));
    in.read(reinterpret_cast<char*>(&bits), sizeof bits);
    if (big_endian) bits = __builtin_bswap64(bits);
    double value = 0.0;
    std::memcpy(&value, &bits, sizeof value);
    if (!in || !(value >= 0.0 && value <= static_cast<double>(kMaxReadValues))) {
      ThrowInvalid(where,
                   std::string("a sparse matrix's ") + (column == 0 ? "row" : "column") +
                       " count (its last row) in [0, " + std::to_string(kMaxReadValues) + "]",
                   in ? ToText(value) : std::string("none"));
    }
  }
}

void CheckMat4Structure(const std::string& path, std::ifstream& in, std::uint64_t size) {
  std::uint64_t at = 0;
  while (size - at >= 20) {
    std::int32_t header[5];
    in.seekg(static_cast<std::streamoff>(at));
    in.read(reinterpret_cast<char*>(header), sizeof header);
    if (!in) return;
    // The type MOPT (M: 0 little-, 1 big-endian) tells the byte order.
    if (header[0] < 0 || header[0] > 9999) {
      for (auto& v : header)
        v = static_cast<std::int32_t>(__builtin_bswap32(static_cast<std::uint32_t>(v)));
    }
    const std::int32_t type = header[0];
    const int precision = (type / 10) % 10;
    const bool valid_type =
        type >= 0 && type / 1000 <= 4 && (type / 100) % 10 == 0 && precision <= 5 && type % 10 <= 2;
    if (!valid_type && at == 0) {
      ThrowInvalid(path, "a readable MATLAB .mat file (v4, v5 or v7.3)",
                   "a file that starts with neither a v5 header nor a v4 matrix header");
    }
    const std::string where = path + ": v4 matrix at byte " + std::to_string(at);
    if (!valid_type) {
      ThrowInvalid(where, "a matrix type MOPT with M <= 4, O = 0, P <= 5, T <= 2",
                   std::to_string(type));
    }
    if (header[1] < 0 || header[2] < 0 || header[4] < 1) {
      ThrowInvalid(where, "non-negative dimensions and a name length >= 1",
                   std::to_string(header[1]) + " x " + std::to_string(header[2]) +
                       ", name length " + std::to_string(header[4]));
    }
    static constexpr int kBytes[] = {8, 4, 4, 2, 2, 1};
    const bool sparse = type % 10 == 2;
    // A sparse matrix is N + 1 rows of (i, j, value[, imaginary part]): libmatio
    // (1.5.23, mat4.c) allocates N row indices before it reads a column count,
    // reads both index columns as doubles whatever P says, and sizes the column
    // pointers by the last row's j, a number from the data.
    if (sparse && (header[1] < 2 || (header[2] != 3 && header[2] != 4))) {
      ThrowInvalid(
          where,
          "a sparse matrix of at least 2 rows and 3 or 4 columns (i, j, value[, imaginary part])",
          std::to_string(header[1]) + " x " + std::to_string(header[2]));
    }
    const double rows = header[1];
    const double data = sparse ? rows * 2 * 8 + rows * (header[2] - 2) * kBytes[precision]
                               : rows * header[2] * (header[3] != 0 ? 2 : 1) * kBytes[precision];
    const double room = static_cast<double>(size - at - 20);
    if (header[4] + data > room) {
      ThrowInvalid(where, "a name and data that fit in the " + ToText(room) + " bytes that follow",
                   ToText(static_cast<double>(header[4])) + " + " + ToText(data) +
                       " bytes (a corrupt or truncated file)");
    }
    if (sparse) CheckMat4SparseSize(in, at + 20 + header[4], header[1], type / 1000 == 1, where);
    at += 20 + static_cast<std::uint64_t>(header[4]) + static_cast<std::uint64_t>(data);
  }
}

}  // namespace

void CheckMatStructure(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return;  // matio reports it
  const std::uint64_t size = FileSize(in);
  unsigned char header[128] = {};
  if (size >= sizeof header) in.read(reinterpret_cast<char*>(header), sizeof header);
  // Level 5 header: version (2 bytes) and endian indicator "IM" at 124..127.
  const bool little = header[126] == 'I' && header[127] == 'M';
  const bool big = header[126] == 'M' && header[127] == 'I';
  if (little || big) {
    const unsigned version =
        little ? header[124] | header[125] << 8 : header[125] | header[124] << 8;
    if (version == 0x0100) CheckMat5Structure(path, in, size, big);
    if (version == 0x0100 || version == 0x0200) return;
  }
  in.clear();
  CheckMat4Structure(path, in, size);
}

}  // namespace podid::internal
