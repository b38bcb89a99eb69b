// libFuzzer target: ReadUff on arbitrary bytes written to a temporary .uff
// file. Invalid input must end in std::invalid_argument; a result must satisfy
// the reader's contract.
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "fuzz_support.hpp"
#include "podid/core/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = podid::fuzz::WriteInput(data, size, ".uff");
  try {
    const podid::TimeSeries series = podid::ReadUff(path);
    if (series.time_s.size() < 2 || series.values.rows() != series.time_s.size() ||
        static_cast<std::size_t>(series.values.cols()) != series.channel_names.size() ||
        series.units.size() != series.channel_names.size() || !series.values.allFinite() ||
        !(series.time_s(1) > series.time_s(0))) {
      __builtin_trap();
    }
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
