#pragma once
// Process-wide cache of FFTW plans, one per (kind, length). FFTW's planner is
// not thread-safe, so plan creation is serialised by a mutex (the one of
// podid/core/fftw_lock.hpp, which the model module's interpolation takes
// too); executing a plan with fftw_execute_dft*() on other
// (fftw_malloc-aligned) arrays is.
//
// Planning effort (podid/wavelet/plans.hpp): a length with wisdom in the
// on-disk cache (or measured earlier in this process) gets its most rigorous
// measured plan (FFTW_PATIENT before FFTW_MEASURE); otherwise kEstimate plans
// with FFTW_ESTIMATE (microseconds) and kMeasure measures (FFTW_MEASURE) and
// stores the wisdom in the cache.

#include <fftw3.h>

#include <complex>
#include <cstddef>
#include <memory>

#include "podid/core/fftw_buffer.hpp"

namespace podid::wavelet::internal {

/// The longest transform (n x howmany points) planned: 2 GiB of complex doubles.
inline constexpr int kMaxPlanLength = 1 << 27;

using RealBuffer = podid::internal::FftwBuffer<double>;
using ComplexBuffer = podid::internal::FftwBuffer<std::complex<double>>;

inline RealBuffer AllocateReal(std::size_t n) { return podid::internal::FftwAllocate<double>(n); }
inline ComplexBuffer AllocateComplex(std::size_t n) {
  return podid::internal::FftwAllocate<std::complex<double>>(n);
}

/// Out-of-place real -> complex forward transform of length n (n / 2 + 1 outputs).
fftw_plan RealForwardPlan(int n, bool measure);
/// In-place complex forward (exp(-2 pi i k j / n)) transform of length n. The
/// CWT's forward FFT of its real signal: FFTW_ESTIMATE plans it in ~0.2 ms
/// where a real-to-complex plan takes ~3 ms (FFTW 3.3.10, 9216 points), which
/// a one-shot `podid cwt` pays in full; executing it costs ~1 ms at 10^5 points.
fftw_plan ComplexForwardPlan(int n, bool measure);
/// In-place complex backward (unnormalised, exp(+2 pi i k j / n)) transform of length n.
fftw_plan ComplexBackwardPlan(int n, bool measure);
/// Out-of-place: d complex backward transforms of length m, the t-th from
/// in[t m .. t m + m - 1] to out[t m .. t m + m - 1] (in is preserved: the
/// pruned inverse of pruned_inverse.hpp twiddles its next block from it). (Writing the outputs
/// interleaved, stride d, lets FFTW skip a pass but is slower: 0.97-1.2 ms against 0.50-0.54 ms for
/// 16 x 6400 points.)
/// *measured (if given): whether the plan was measured (now, or earlier in
/// the wisdom) rather than estimated.
fftw_plan BatchedBackwardPlan(int m, int d, bool measure, bool* measured = nullptr);

/// Cost of an FFT of length n relative to n log2 n (a model of FFTW's codelets:
/// radix 2 cheapest, then 3, 5, 7); +inf when n has a prime factor above 7.
double FftCostModel(long long n);
/// The length in [n, max(n + 8, ceil(1.25 n))] with factors 2, 3, 5, 7 only and the
/// lowest FftCostModel(m) * m.
long long FastFftLength(long long n);
/// The same for a block of a longer record whose `overlap` points (0 <= overlap
/// < n) are thrown away: the lowest cost per kept point, FftCostModel(m) * m /
/// (m - overlap), so that the record's blocks cost least in all; up to 2048
/// points only (FastFftLength(n) beyond).
long long FastBlockLength(long long n, long long overlap);

inline fftw_complex* AsFftw(std::complex<double>* p) { return reinterpret_cast<fftw_complex*>(p); }

}  // namespace podid::wavelet::internal
