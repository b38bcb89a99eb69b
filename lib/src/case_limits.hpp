#pragma once
// Bounds on case-file text, checked before toml++ sees it (docs/case-file.md,
// "Limits"): a size limit read with at most limit + 1 bytes (also from FIFOs
// and devices such as /dev/zero), and a nesting limit, since toml++ recurses
// once per level of dotted keys, arrays and inline tables (a 40,000-level
// dotted key overflowed its stack; 16,000 levels took 14 s).

#include <cstddef>
#include <string>
#include <string_view>

namespace podid::case_detail {

/// The largest case file read: 1 MiB (the reference case is 1.5 KiB).
inline constexpr std::size_t kMaxCaseFileBytes = 1 << 20;

/// The deepest TOML nesting accepted at any point of the text: open arrays,
/// inline tables and table-header brackets plus the dots of the dotted key
/// being read (`[[identify.parameter]]` is 3, the most the schema needs).
inline constexpr int kMaxTomlNesting = 32;

/// Reads the whole file at `path`, reading at most kMaxCaseFileBytes + 1
/// bytes. Throws std::invalid_argument naming the path when the file cannot
/// be opened or read, is a folder, or is larger than the limit.
std::string ReadCaseText(const std::string& path);

/// Throws std::invalid_argument("<source>:<line>: expected ...") when `text`
/// is longer than kMaxCaseFileBytes or nests deeper than kMaxTomlNesting.
/// A lexical scan (strings and comments skipped), linear in the text.
void CheckCaseText(std::string_view text, std::string_view source);

}  // namespace podid::case_detail
