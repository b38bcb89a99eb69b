#pragma once
// A level-5 MAT-file's 128-byte header ("MAT-File Format", ch. 1: text,
// subsystem offset, version 0x0100, "IM" little-endian), for tests and
// benchmarks that write .mat files without libmatio.
#include <cstdint>
#include <cstring>
#include <string>

namespace podid::testing {

/// The header, `text` (at most 116 bytes) padded with spaces; append the
/// variables' miMATRIX elements after it.
inline std::string Mat5Header(const std::string& text) {
  std::string file(128, ' ');
  std::memcpy(file.data(), text.data(), text.size() < 116 ? text.size() : 116);
  std::memset(file.data() + 116, 0, 8);
  const std::uint16_t version = 0x0100;
  std::memcpy(file.data() + 124, &version, 2);
  file[126] = 'I';
  file[127] = 'M';
  return file;
}

}  // namespace podid::testing
