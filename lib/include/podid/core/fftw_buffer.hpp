#pragma once
// fftw_malloc'd buffers (FFTW's SIMD alignment), freed by fftw_free: the
// modules that use FFTW (wavelet, the model's one-off transforms) share them.
// Header-only: it needs <fftw3.h>, and only modules that link FFTW include it.

#include <fftw3.h>

#include <cstddef>
#include <memory>
#include <new>

namespace podid::internal {

struct FftwFree {
  void operator()(void* p) const { fftw_free(p); }
};
template <typename T>
using FftwBuffer = std::unique_ptr<T[], FftwFree>;

/// n (at least 1) elements of T, uninitialised; throws std::bad_alloc.
template <typename T>
FftwBuffer<T> FftwAllocate(std::size_t n) {
  auto* p = static_cast<T*>(fftw_malloc(sizeof(T) * (n == 0 ? 1 : n)));
  if (p == nullptr) throw std::bad_alloc();
  return FftwBuffer<T>(p);
}

}  // namespace podid::internal
