// The wisdom cache read defensively (wisdom_file.hpp).
#include "wisdom_file.hpp"

#include <fftw3.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include "podid/core/bounded_read.hpp"

namespace podid::wavelet::internal {
namespace {

// FFTW's limits (kernel/ifftw.h, planner.c): a solver name is read into
// char[MAXNAM + 1] with MAXNAM 64, at most 63 characters; flags_t packs l and
// u in 20 bits and timelimit_impatience in 9, and the importer CK()s (aborts)
// when a value does not fit.
constexpr std::size_t kMaxName = 63;
constexpr std::size_t kMaxId = 9;   // digits of an int
constexpr std::size_t kMaxHex = 8;  // digits of a 32-bit field
constexpr std::uint32_t kFlagLimit = 1u << 20, kTimeLimit = 1u << 9;

// A cursor over the text; every Take* says what it expected on failure.
class Reader {
 public:
  explicit Reader(std::string_view text) : s_(text) {}

  bool Blanks() {  // at least one blank (FFTW writes one or a newline and two spaces)
    const std::size_t start = i_;
    while (i_ < s_.size() && IsBlank(s_[i_])) ++i_;
    return i_ > start || Fail("a blank");
  }
  void OptionalBlanks() {
    while (i_ < s_.size() && IsBlank(s_[i_])) ++i_;
  }
  bool Char(char c) {
    if (i_ >= s_.size() || s_[i_] != c) return Fail(std::string("'") + c + "'");
    ++i_;
    return true;
  }
  bool Word(std::string_view w) {
    if (s_.substr(i_, w.size()) != w) return Fail("\"" + std::string(w) + "\"");
    i_ += w.size();
    return true;
  }
  // [A-Za-z0-9_]{1,max} (also '.', '-' when `version`).
  bool Name(std::size_t max, bool version) {
    const std::size_t start = i_;
    while (i_ < s_.size() && i_ - start <= max && IsNameChar(s_[i_], version)) ++i_;
    if (i_ == start || i_ - start > max) {
      return Fail("a name of 1-" + std::to_string(max) + " letters, digits or '_'");
    }
    return true;
  }
  bool Digits(std::size_t max) {
    const std::size_t start = i_;
    while (i_ < s_.size() && i_ - start <= max && s_[i_] >= '0' && s_[i_] <= '9') ++i_;
    if (i_ == start || i_ - start > max) return Fail("1-" + std::to_string(max) + " digits");
    return true;
  }
  // "#x" and 1-8 hex digits below `limit` (0: any 32-bit value).
  bool Hex(std::uint32_t limit, const char* field) {
    if (!Word("#x")) return false;
    const std::size_t start = i_;
    std::uint64_t value = 0;
    while (i_ < s_.size() && i_ - start <= kMaxHex && HexDigit(s_[i_]) >= 0) {
      value = value * 16 + static_cast<std::uint64_t>(HexDigit(s_[i_]));
      ++i_;
    }
    if (i_ == start || i_ - start > kMaxHex) return Fail("1-8 hex digits");
    if (limit != 0 && value >= limit) {
      i_ = start;
      return Fail(std::string(field) + " below #x" + ToHex(limit));
    }
    return true;
  }
  bool AtEnd() { return i_ == s_.size() || Fail("the end after the closing ')'"); }
  bool Peek(char c) const { return i_ < s_.size() && s_[i_] == c; }
  bool Expected(const std::string& what) { return Fail(what); }
  const std::string& why() const { return why_; }

 private:
  static bool IsBlank(char c) {  // C isspace
    return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r';
  }
  static bool IsNameChar(char c, bool version) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           (version && (c == '.' || c == '-'));
  }
  static int HexDigit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  }
  static std::string ToHex(std::uint32_t v) {
    char buffer[16];
    std::snprintf(buffer, sizeof buffer, "%x", static_cast<unsigned>(v));
    return buffer;
  }
  bool Fail(const std::string& expected) {
    if (why_.empty()) {
      std::size_t line = 1;
      for (std::size_t k = 0; k < i_ && k < s_.size(); ++k) line += s_[k] == '\n';
      why_ = "line " + std::to_string(line) + ": expected " + expected;
    }
    return false;
  }

  std::string_view s_;
  std::size_t i_ = 0;
  std::string why_;
};

}  // namespace

std::string CheckWisdomText(std::string_view text) {
  Reader r(text);
  r.OptionalBlanks();
  // "(fftw-3.3.10 fftw_wisdom #x... #x... #x... #x..." (the build's signature).
  bool ok =
      r.Char('(') && r.Word("fftw-") && r.Name(32, true) && r.Blanks() && r.Word("fftw_wisdom");
  for (int k = 0; ok && k < 4; ++k) ok = r.Blanks() && r.Hex(0, "");
  while (ok) {
    r.OptionalBlanks();
    if (r.Peek(')')) break;
    if (!r.Peek('(')) {
      ok = r.Expected("'(' (an entry) or ')' (the end)");
      break;
    }
    // "(fftw_codelet_n1_64 0 #xL #xU #xT #x... #x... #x... #x...)"
    ok = r.Char('(') && r.Name(kMaxName, false) && r.Blanks() && r.Digits(kMaxId) && r.Blanks() &&
         r.Hex(kFlagLimit, "flags l") && r.Blanks() && r.Hex(kFlagLimit, "flags u") && r.Blanks() &&
         r.Hex(kTimeLimit, "timelimit");
    for (int k = 0; ok && k < 4; ++k) ok = r.Blanks() && r.Hex(0, "");
    ok = ok && r.Char(')');
  }
  ok = ok && r.Char(')');
  if (ok) r.OptionalBlanks();
  ok = ok && r.AtEnd();
  return ok ? std::string() : r.why();
}

std::string ImportWisdomFile(const std::string& path) {
  using Status = podid::internal::BoundedRead::Status;
  // Regular files only: a FIFO or a device is refused before any read.
  podid::internal::BoundedRead file = podid::internal::ReadFileBounded(path, kMaxWisdomBytes, true);
  const std::string at_most =
      "expected at most " + std::to_string(kMaxWisdomBytes) + " bytes, got ";
  std::string why;
  switch (file.status) {
    case Status::kOk:
      why = CheckWisdomText(file.text);
      break;
    case Status::kCannotOpen:
      if (file.error == ENOENT || file.error == ENOTDIR) return "";  // no cache yet
      why = "cannot open it (" + std::string(std::strerror(file.error)) + ")";
      break;
    case Status::kCannotStat:
      why = "cannot stat it (" + std::string(std::strerror(file.error)) + ")";
      break;
    case Status::kFolder:
    case Status::kNotRegular:
      why = "not a regular file";
      break;
    case Status::kTooLarge:
      why = at_most + std::to_string(file.size);
      break;
    case Status::kReadError:
      why = "cannot read it (" + std::string(std::strerror(file.error)) + ")";
      break;
    case Status::kMoreThanMax:
      why = at_most + "more";
      break;
  }
  if (why.empty() && fftw_import_wisdom_from_string(file.text.c_str()) == 0) {
    why = "FFTW refused it (wisdom of another FFTW version or build)";
  }
  return why.empty() ? why : path + ": " + why;
}

}  // namespace podid::wavelet::internal
