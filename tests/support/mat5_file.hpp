#pragma once
// A level-5 MAT-file written without libmatio ("MAT-File Format", ch. 1): the
// 128-byte header (text, subsystem offset, version 0x0100, "IM"
// little-endian), then one miMATRIX element per variable, for tests and
// benchmarks that need files independent of the reader under test.
#include <Eigen/Core>
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

/// Raw bytes, a data element's tag (type, byte count), and the zero padding
/// to the next 8-byte boundary.
inline void Mat5Append(std::string* out, const void* data, std::size_t bytes) {
  out->append(static_cast<const char*>(data), bytes);
}
inline void Mat5Tag(std::string* out, std::uint32_t type, std::uint32_t bytes) {
  Mat5Append(out, &type, 4);
  Mat5Append(out, &bytes, 4);
}
inline void Mat5Pad(std::string* out) { out->append((8 - out->size() % 8) % 8, '\0'); }

/// A real double variable: flags (mxDOUBLE_CLASS), dimensions, name, values
/// column-major.
inline std::string Mat5DoubleVariable(const std::string& name, const Eigen::MatrixXd& a) {
  std::string body;
  Mat5Tag(&body, 6, 8);  // miUINT32 array flags: class mxDOUBLE_CLASS (6)
  const std::uint32_t flags[2] = {6, 0};
  Mat5Append(&body, flags, 8);
  Mat5Tag(&body, 5, 8);  // miINT32 dimensions
  const std::int32_t dims[2] = {static_cast<std::int32_t>(a.rows()),
                                static_cast<std::int32_t>(a.cols())};
  Mat5Append(&body, dims, 8);
  Mat5Tag(&body, 1, static_cast<std::uint32_t>(name.size()));  // miINT8 name
  body += name;
  Mat5Pad(&body);
  Mat5Tag(&body, 9, static_cast<std::uint32_t>(8 * a.size()));  // miDOUBLE
  Mat5Append(&body, a.data(), static_cast<std::size_t>(8 * a.size()));
  std::string element;
  Mat5Tag(&element, 14, static_cast<std::uint32_t>(body.size()));  // miMATRIX
  return element + body;
}

}  // namespace podid::testing
