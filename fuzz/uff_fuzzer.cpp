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
    if (!podid::fuzz::SatisfiesSeriesContract(series)) {
      __builtin_trap();
    }
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
