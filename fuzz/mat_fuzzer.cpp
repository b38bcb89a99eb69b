// libFuzzer target: ReadMat on arbitrary bytes written to a temporary .mat
// file (libmatio itself is not instrumented; the target checks how podid uses
// what matio returns). Invalid input must end in std::invalid_argument.
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "fuzz_support.hpp"
#include "podid/core/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = podid::fuzz::WriteInput(data, size, ".mat");
  podid::MatReadOptions options;
  options.step_s = 1e-3;  // so that files without a time vector are read too
  try {
    const podid::TimeSeries series = podid::ReadMat(path, options);
    if (!podid::fuzz::SatisfiesSeriesContract(series)) {
      __builtin_trap();
    }
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
