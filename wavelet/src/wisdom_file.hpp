#pragma once
// The FFTW wisdom cache (fftw_plans.cpp), read defensively. FFTW's own reader
// trusts its file: fftw_import_wisdom_from_filename blocked for ever on a FIFO
// and on a link to /dev/zero, and abort()ed the process on an entry whose
// flags overflow FFTW's bit-fields (planner.c: "assertion failed: flags.l ==
// l"). So podid reads the file itself - a regular file of at most
// kMaxWisdomBytes - and hands FFTW only text in the shape
// fftw_export_wisdom writes, every field within FFTW's bounds.

#include <cstddef>
#include <string>
#include <string_view>

namespace podid::wavelet::internal {

/// About 95 bytes a plan: 16 MiB hold some 170,000 plans (`podid plan` for
/// fCWT's 10^5-sample case writes a few hundred, 14 kB for a 1 s record).
constexpr std::size_t kMaxWisdomBytes = std::size_t{16} << 20;

/// "" when `text` is wisdom as FFTW 3 exports it - "(fftw-VERSION
/// fftw_wisdom #xH #xH #xH #xH", then entries "(NAME ID #xL #xU #xT #xH #xH
/// #xH #xH)" and a closing ")" - with names of 1-63 identifier characters, ids
/// of at most 9 digits, hex fields of 1-8 digits, L and U below 2^20 and T
/// below 2^9 (FFTW's flags_t); else what was expected where.
std::string CheckWisdomText(std::string_view text);

/// Imports the wisdom at `path` into FFTW (callers hold the planner mutex).
/// Returns "" when it was imported or there is no file, else why it was
/// ignored: not a regular file, unreadable, over kMaxWisdomBytes, not in the
/// exported shape (CheckWisdomText), or refused by FFTW (another FFTW version
/// or build).
std::string ImportWisdomFile(const std::string& path);

}  // namespace podid::wavelet::internal
