// libFuzzer target: the FFTW wisdom cache's reader (wavelet/src/wisdom_file.cpp)
// on arbitrary bytes written to a file. ImportWisdomFile must return - the
// wisdom imported or why not - never hang or abort (FFTW's own importer
// aborts on flags that overflow its bit-fields); wisdom it lets through must
// then plan transforms that are right, checked against a direct DFT. The seeds
// are wisdom Debian's libfftw3 (what this build links) measured for the
// lengths below, so mutations reach entries FFTW will actually use.
#include <fftw3.h>

#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "../wavelet/src/wisdom_file.hpp"
#include "fuzz_support.hpp"

namespace {

constexpr int kLengths[] = {16, 60, 64};
constexpr unsigned kFlags[] = {FFTW_ESTIMATE, FFTW_MEASURE | FFTW_WISDOM_ONLY,
                               FFTW_PATIENT | FFTW_WISDOM_ONLY};

// A plan from bad wisdom that computes something else is a finding: max
// |FFTW's forward transform - the direct DFT| must stay within 1e-12 n^2 (the
// inputs are O(1), the outputs O(n); both sums' rounding is O(eps n) of that,
// a wrong transform O(1)).
void CheckForward(int n, unsigned flags) {
  fftw_complex* in = fftw_alloc_complex(static_cast<std::size_t>(n));
  fftw_complex* out = fftw_alloc_complex(static_cast<std::size_t>(n));
  fftw_plan plan = fftw_plan_dft_1d(n, in, out, FFTW_FORWARD, flags);
  if (plan != nullptr) {
    for (int k = 0; k < n; ++k) {  // planning may overwrite the arrays: fill after
      in[k][0] = std::cos(0.7 * k) + 0.1 * k;
      in[k][1] = std::sin(1.3 * k);
    }
    fftw_execute(plan);
    const double pi = std::acos(-1.0);
    for (int f = 0; f < n; ++f) {
      std::complex<double> sum = 0.0;
      for (int k = 0; k < n; ++k) {
        sum += std::complex<double>(in[k][0], in[k][1]) * std::polar(1.0, -2.0 * pi * f * k / n);
      }
      if (std::abs(sum - std::complex<double>(out[f][0], out[f][1])) > 1e-12 * n * n) {
        __builtin_trap();
      }
    }
    fftw_destroy_plan(plan);
  }
  fftw_free(in);
  fftw_free(out);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = podid::fuzz::WriteInput(data, size, ".wisdom");
  if (podid::wavelet::internal::ImportWisdomFile(path).empty()) {
    for (int n : kLengths) {
      for (unsigned flags : kFlags) CheckForward(n, flags);
    }
  }
  fftw_forget_wisdom();  // the next input starts from no wisdom
  return 0;
}
