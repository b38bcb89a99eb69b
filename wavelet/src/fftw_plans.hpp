#pragma once
// Process-wide cache of FFTW plans, one per (kind, length). FFTW's planner is
// not thread-safe, so plan creation is serialised by a mutex; executing a plan
// with fftw_execute_dft*() on other (fftw_malloc-aligned) arrays is.

#include <fftw3.h>

#include <complex>
#include <cstddef>
#include <memory>

namespace podid::wavelet::internal {

struct FftwFree {
  void operator()(void* p) const { fftw_free(p); }
};
using RealBuffer = std::unique_ptr<double[], FftwFree>;
using ComplexBuffer = std::unique_ptr<std::complex<double>[], FftwFree>;

RealBuffer AllocateReal(std::size_t n);
ComplexBuffer AllocateComplex(std::size_t n);

/// Out-of-place real -> complex forward transform of length n (n / 2 + 1 outputs).
fftw_plan RealForwardPlan(int n);
/// In-place complex backward (unnormalised, exp(+2 pi i k j / n)) transform of length n.
fftw_plan ComplexBackwardPlan(int n);

inline fftw_complex* AsFftw(std::complex<double>* p) { return reinterpret_cast<fftw_complex*>(p); }

}  // namespace podid::wavelet::internal
