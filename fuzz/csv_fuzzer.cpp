// libFuzzer target: ReadCsv on arbitrary bytes. Invalid input must end in
// std::invalid_argument; anything else (a crash, a sanitizer report, another
// exception, a hang) is a finding.
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "fuzz_support.hpp"
#include "podid/core/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = podid::fuzz::WriteInput(data, size, ".csv");
  try {
    const podid::TimeSeries series = podid::ReadCsv(path);
    // A series that was accepted satisfies the reader's contract.
    if (!podid::fuzz::SatisfiesSeriesContract(series)) {
      __builtin_trap();
    }
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
