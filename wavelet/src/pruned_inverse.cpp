#include "pruned_inverse.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "podid/core/error.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace podid::wavelet::internal {
namespace {

// a * b written out: std::complex's operator* checks for NaN (a call to
// __muldc3 on the slow path) and does not vectorise.
inline void Multiply(const double* a, const double* b, double* out) {
  const double re = a[0] * b[0] - a[1] * b[1];
  const double im = a[0] * b[1] + a[1] * b[0];
  out[0] = re;
  out[1] = im;
}

// emit(j, i) for every output j = q D + r < times and its block entry
// i = r m + q, in output order. D fixed at compile time (kDecimation > 0)
// unrolls the interleave of the D blocks: a run-time count per group of D
// outputs was a short loop of unknown length (fCWT's case 1.04x at 10^4,
// 1.07x at 10^5; docs/benchmarks.md).
template <Eigen::Index kDecimation, class Emit>
void Interleave(Eigen::Index d, Eigen::Index m, Eigen::Index times, Emit emit) {
  if constexpr (kDecimation > 0) d = kDecimation;
  const Eigen::Index groups = times / d;  // whole groups of d outputs
  for (Eigen::Index q = 0; q < groups; ++q) {
    for (Eigen::Index r = 0; r < d; ++r) emit(q * d + r, r * m + q);
  }
  for (Eigen::Index j = groups * d; j < times; ++j) emit(j, j % d * m + j / d);
}

// Interleave with D as a compile-time constant for the decimations
// PrunedInverse::Decimation gives (powers of 2), any other D at run time.
template <class Emit>
void InterleaveBlocks(Eigen::Index d, Eigen::Index m, Eigen::Index times, Emit emit) {
  switch (d) {
    case 1:
      Interleave<1>(d, m, times, emit);
      break;
    case 2:
      Interleave<2>(d, m, times, emit);
      break;
    case 4:
      Interleave<4>(d, m, times, emit);
      break;
    case 8:
      Interleave<8>(d, m, times, emit);
      break;
    case 16:
      Interleave<16>(d, m, times, emit);
      break;
    case 32:
      Interleave<32>(d, m, times, emit);
      break;
    case 64:
      Interleave<64>(d, m, times, emit);
      break;
    default:
      Interleave<0>(d, m, times, emit);
      break;
  }
}

}  // namespace

void PrunedInverse::Reset(Eigen::Index p, bool measure) {
  PODID_CHECK(p >= 1 && p <= (Eigen::Index{1} << 27));
  measure_ = measure;
  if (p == p_) return;
  p_ = p;
  twiddle_.resize(static_cast<std::size_t>(p));
  const double step = 2.0 * std::numbers::pi / static_cast<double>(p);
  for (Eigen::Index t = 0; t < p; ++t) {
    // Angles reduced to [-pi, pi] keep the argument of sin/cos small and exact.
    const Eigen::Index signed_t = 2 * t > p ? t - p : t;
    const double angle = step * static_cast<double>(signed_t);
    twiddle_[static_cast<std::size_t>(t)] = Complex(std::cos(angle), std::sin(angle));
  }
}

Eigen::Index PrunedInverse::Decimation(Eigen::Index p, Eigen::Index bins) {
  PODID_CHECK(p >= 1);
  Eigen::Index d = 1;
  while (2 * d <= kMaxDecimation && p % (2 * d) == 0 && p / (2 * d) >= bins) d *= 2;
  return d;
}

Eigen::Index PrunedInverse::Batch(Eigen::Index p, Eigen::Index d) {
  PODID_CHECK(p >= 1 && d >= 1 && p % d == 0);
  const Eigen::Index m = p / d;
  Eigen::Index best = 1;
  for (Eigen::Index g = 2; g <= d; ++g) {
    if (d % g == 0 && g * m <= kBatchPoints) best = g;
  }
  return best;
}

fftw_plan PrunedInverse::Plan(Eigen::Index d, Eigen::Index batch) const {
  PODID_CHECK(d >= 1 && p_ % d == 0 && batch >= 1 && d % batch == 0);
  return BatchedBackwardPlan(static_cast<int>(p_ / d), static_cast<int>(batch), measure_);
}

void PrunedInverse::Execute(const Complex* spectrum,
                            const double* filter,
                            Eigen::Index first_bin,
                            Eigen::Index bins,
                            Eigen::Index d,
                            Eigen::Index batch,
                            fftw_plan plan,
                            Complex* work,
                            Complex* out) const {
  const Eigen::Index m = p_ / d;
  PODID_CHECK(d >= 1 && p_ % d == 0 && bins >= 1 && bins <= m && batch >= 1 && d % batch == 0);
  PODID_CHECK(first_bin >= -((p_ - 1) / 2) && first_bin + bins - 1 <= p_ / 2);
  // The band lies at slots [slot0, slot0 + head) and [0, tail) of each block.
  const Eigen::Index slot0 = ((first_bin % m) + m) % m;
  const Eigen::Index head = std::min(bins, m - slot0);
  const Eigen::Index tail = bins - head;
  // Y_b = X_b filter (X_-b = conj X_b) for bins i_begin .. i_begin + count - 1.
  const auto fill = [&](Eigen::Index i_begin, Eigen::Index count, Complex* dest) {
    const Eigen::Index first = first_bin + i_begin;
    const Eigen::Index negative = std::clamp<Eigen::Index>(-first, 0, count);
    for (Eigen::Index i = 0; i < negative; ++i) {
      dest[i] = std::conj(spectrum[-(first + i)]) * filter[i_begin + i];
    }
    const auto* x = reinterpret_cast<const double*>(spectrum + first + negative);
    auto* to = reinterpret_cast<double*>(dest + negative);
    const double* g = filter + i_begin + negative;
    for (Eigen::Index i = 0; i < count - negative; ++i) {
      to[2 * i] = x[2 * i] * g[i];
      to[2 * i + 1] = x[2 * i + 1] * g[i];
    }
  };
  const auto clear = [&](Complex* block) {
    std::fill(block + tail, block + slot0, Complex(0.0, 0.0));
    std::fill(block + slot0 + head, block + m, Complex(0.0, 0.0));
  };
  if (d == 1) {  // no twiddle: the band straight into its slots
    clear(work);
    fill(0, head, work + slot0);
    if (tail > 0) fill(head, tail, work);
    fftw_execute_dft(plan, AsFftw(work), AsFftw(out));
    return;
  }
  // The untwiddled band, kept apart: the batches overwrite the blocks.
  Complex* band = work + batch * m;
  fill(0, bins, band);
  const auto* tw = reinterpret_cast<const double*>(twiddle_.data());
  const Eigen::Index a_mod = ((first_bin % p_) + p_) % p_;
  for (Eigen::Index r0 = 0; r0 < d; r0 += batch) {
    for (Eigen::Index r = r0; r < r0 + batch; ++r) {
      Complex* block = work + (r - r0) * m;
      clear(block);
      if (r == 0) {
        std::copy(band, band + head, block + slot0);
        std::copy(band + head, band + bins, block);
        continue;
      }
      // Block r's slot of bin b = a + i is Y_b w^(b r): one exact table value
      // at t = b r mod P, which steps by r and wraps at P (then the gather
      // is a plain copy).
      const auto run = [&](Eigen::Index i_begin, Eigen::Index count, Eigen::Index slot) {
        const auto* in = reinterpret_cast<const double*>(band + i_begin);
        auto* to = reinterpret_cast<double*>(block + slot);
        Eigen::Index t = (a_mod + i_begin) % p_ * r % p_;
        for (Eigen::Index i = 0; i < count;) {
          const Eigen::Index before_wrap = (p_ - 1 - t) / r + 1;  // t + k r < P for k < this
          const Eigen::Index n = std::min(count - i, before_wrap);
          const double* w = tw + 2 * t;
          for (Eigen::Index k = 0; k < n; ++k) {
            Multiply(in + 2 * (i + k), w + 2 * k * r, to + 2 * (i + k));
          }
          i += n;
          t += n * r - p_;  // the next segment's start (only used after a wrap)
        }
      };
      run(0, head, slot0);
      if (tail > 0) run(head, tail, 0);
    }
    fftw_execute_dft(plan, AsFftw(work), AsFftw(out + r0 * m));
  }
}

void PrunedInverse::Gather(const Complex* blocks, Eigen::Index d, Eigen::Index times,
                           double scale, Complex* column) const {
  PODID_CHECK(d >= 1 && d <= kMaxDecimation && p_ % d == 0);
  const auto* in = reinterpret_cast<const double*>(blocks);
  auto* out = reinterpret_cast<double*>(column);
#if defined(__SSE2__)
  // The output (16 bytes per value, 300 x 10^5 values in fCWT's case) is far
  // larger than any cache: stream it past the cache instead of reading each
  // line before writing it.
  const __m128d factor = _mm_set1_pd(scale);
  InterleaveBlocks(d, p_ / d, times, [&](Eigen::Index j, Eigen::Index i) {
    _mm_stream_pd(out + 2 * j, _mm_mul_pd(_mm_loadu_pd(in + 2 * i), factor));
  });
  _mm_sfence();
#else
  InterleaveBlocks(d, p_ / d, times, [&](Eigen::Index j, Eigen::Index i) {
    out[2 * j] = in[2 * i] * scale;
    out[2 * j + 1] = in[2 * i + 1] * scale;
  });
#endif
}

void PrunedInverse::GatherMagnitude(const Complex* blocks, Eigen::Index d, Eigen::Index times,
                                    double scale, float* magnitude) const {
  PODID_CHECK(d >= 1 && d <= kMaxDecimation && p_ % d == 0);
  const auto* in = reinterpret_cast<const double*>(blocks);
  InterleaveBlocks(d, p_ / d, times, [&](Eigen::Index j, Eigen::Index i) {
    // |y| of the scaled transform (no overflow), rounded once to float.
    const double re = in[2 * i], im = in[2 * i + 1];
    magnitude[j] = static_cast<float>(std::sqrt(re * re + im * im) * scale);
  });
}

}  // namespace podid::wavelet::internal
