#pragma once
// Shared by the fuzz targets: the fuzz input written to a file of this process.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "podid/core/time_series.hpp"

namespace podid::fuzz {

/// Writes `data` to "<TMPDIR or /tmp>/podid-fuzz-<pid><suffix>" (overwritten on
/// every call with that suffix) and returns the path; the files are removed
/// when the process exits normally (a crash keeps them beside its report).
/// Aborts if the file cannot be written: that is a problem of the machine, not
/// a finding.
inline std::string WriteInput(const std::uint8_t* data, std::size_t size, const char* suffix) {
  struct Written {
    std::vector<std::string> paths;
    ~Written() {
      for (const std::string& path : paths) std::remove(path.c_str());
    }
  };
  static Written written;
  static const std::string prefix = [] {
    const char* tmp = std::getenv("TMPDIR");
    return std::string(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp") + "/podid-fuzz-" +
           std::to_string(getpid());
  }();
  const std::string path = prefix + suffix;
  bool known = false;
  for (const std::string& p : written.paths) known |= p == path;
  if (!known) written.paths.push_back(path);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr || (size > 0 && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0) {
    std::perror(path.c_str());
    std::abort();
  }
  return path;
}

/// The contract of every time-series reader (time_series.hpp): at least two
/// samples, a name per channel and a unit per channel (or none at all), finite
/// values, and finite, strictly increasing times. Anything else is a finding.
inline bool SatisfiesSeriesContract(const TimeSeries& series) {
  const auto n = series.time_s.size();
  if (n < 2 || series.values.rows() != n ||
      static_cast<std::size_t>(series.values.cols()) != series.channel_names.size() ||
      (!series.units.empty() && series.units.size() != series.channel_names.size()) ||
      !series.values.allFinite() || !series.time_s.allFinite()) {
    return false;
  }
  for (Eigen::Index i = 1; i < n; ++i) {
    if (!(series.time_s(i) > series.time_s(i - 1))) return false;
  }
  return true;
}

}  // namespace podid::fuzz
