#include "pruned_inverse.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "podid/core/error.hpp"
#include "podid/core/target_clones.hpp"
#include "ridge_cost.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
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

// out[k] = a[k] w[k], k < n complex values (out == a allowed).
PODID_CLONES_V3 void MultiplyRun(const double* a, const double* w, double* out, Eigen::Index n) {
  for (Eigen::Index k = 0; k < n; ++k) Multiply(a + 2 * k, w + 2 * k, out + 2 * k);
}

// to[k] = x[k] g[k], k < n: complex x, real g.
PODID_CLONES_V3 void ScaleRun(const double* x, const double* g, double* to, Eigen::Index n) {
  for (Eigen::Index k = 0; k < n; ++k) {
    to[2 * k] = x[2 * k] * g[k];
    to[2 * k + 1] = x[2 * k + 1] * g[k];
  }
}

// dest[i - i_begin] = Y_b = X_b filter_i (X_-b = conj X_b), b = first_bin + i,
// for i = i_begin .. i_begin + count - 1, a chunk of the filter at a time
// (generated ones stay in the L1 cache).
void FillBins(const std::complex<double>* spectrum,
              const ScaleFilter& filter,
              Eigen::Index first_bin,
              Eigen::Index i_begin,
              Eigen::Index count,
              std::complex<double>* dest) {
  double scratch[ScaleFilter::kChunkBins];
  for (Eigen::Index done = 0; done < count;) {
    const Eigen::Index n = std::min(count - done, ScaleFilter::kChunkBins);
    const double* g = filter.Values(i_begin + done, n, scratch);
    const Eigen::Index first = first_bin + i_begin + done;
    const Eigen::Index negative = std::clamp<Eigen::Index>(-first, 0, n);
    std::complex<double>* to = dest + done;
    for (Eigen::Index i = 0; i < negative; ++i) to[i] = std::conj(spectrum[-(first + i)]) * g[i];
    ScaleRun(reinterpret_cast<const double*>(spectrum + first + negative), g + negative,
             reinterpret_cast<double*>(to + negative), n - negative);
    done += n;
  }
}

// emit(j - first, i) for every output j = q D + r in [first, first + times)
// and its block entry i = r m + q, in output order. D fixed at compile time
// (kDecimation > 0) unrolls the interleave of the D blocks: a run-time count
// per group of D outputs was a short loop of unknown length (fCWT's case
// 1.04x at 10^4, 1.07x at 10^5; docs/benchmark-log.md, "fCWT with measured
// plans").
template <Eigen::Index kDecimation, class Emit>
void Interleave(Eigen::Index d, Eigen::Index m, Eigen::Index first, Eigen::Index times, Emit emit) {
  if constexpr (kDecimation > 0) d = kDecimation;
  const Eigen::Index end = first + times;
  // Up to the first whole group, the whole groups, the rest.
  Eigen::Index j = first;
  for (const Eigen::Index head = std::min(end, (first + d - 1) / d * d); j < head; ++j) {
    emit(j - first, j % d * m + j / d);
  }
  for (Eigen::Index q = j / d; q < end / d; ++q) {
    for (Eigen::Index r = 0; r < d; ++r) emit(q * d + r - first, r * m + q);
  }
  for (j = std::max(j, end / d * d); j < end; ++j) emit(j - first, j % d * m + j / d);
}

// Interleave with D as a compile-time constant for the decimations
// PrunedInverse::Decimation gives (powers of 2), any other D at run time.
template <class Emit>
void InterleaveBlocks(
    Eigen::Index d, Eigen::Index m, Eigen::Index first, Eigen::Index times, Emit emit) {
  switch (d) {
    case 1:
      Interleave<1>(d, m, first, times, emit);
      break;
    case 2:
      Interleave<2>(d, m, first, times, emit);
      break;
    case 4:
      Interleave<4>(d, m, first, times, emit);
      break;
    case 8:
      Interleave<8>(d, m, first, times, emit);
      break;
    case 16:
      Interleave<16>(d, m, first, times, emit);
      break;
    case 32:
      Interleave<32>(d, m, first, times, emit);
      break;
    case 64:
      Interleave<64>(d, m, first, times, emit);
      break;
    default:
      Interleave<0>(d, m, first, times, emit);
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
                            const ScaleFilter& filter,
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
  const auto fill = [&](Eigen::Index i_begin, Eigen::Index count, Complex* dest) {
    FillBins(spectrum, filter, first_bin, i_begin, count, dest);
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
  // Block r holds Y_b w^(b r) at the band's slots. Computed as
  // [Y_b w^(b (r - 1))] w^b from block r - 1, one product per bin with w^b
  // read in order from the table (at b mod P); the exact w^(b r) (at b r mod
  // P) is a strided read, far apart for large r (fCWT's case 1.06-1.08x).
  // The recurrence adds a rounding per block, so every kAnchorBlocks-th
  // block is twiddled exactly from the untwiddled band: at most 8 roundings
  // (below 2e-15 of sum |Y_b|, test PrunedInverse.*). The plans preserve
  // their input, so block r - 1 is intact after its transform and the zero
  // slots stay zero: a block position is cleared only when first used.
  constexpr Eigen::Index kAnchorBlocks = 8;
  const auto* tw = reinterpret_cast<const double*>(twiddle_.data());
  const Eigen::Index a_mod = ((first_bin % p_) + p_) % p_;
  // to[slot of bin i] = from[slot of bin i] * w^((a + i) step), i < bins;
  // from == to is allowed (in place).
  const auto twiddle = [&](const Complex* from, Complex* to, Eigen::Index step, bool from_slots) {
    for (Eigen::Index i = 0; i < bins;) {  // runs contiguous in slots and, at step 1, table
      const Eigen::Index slot = i < head ? slot0 + i : i - head;
      const Eigen::Index t = (a_mod + i) % p_ * step % p_;
      const Eigen::Index before_wrap = (p_ - 1 - t) / step + 1;  // t + k step < P below it
      const Eigen::Index n = std::min({bins - i, before_wrap, i < head ? head - i : bins - i});
      const auto* v = reinterpret_cast<const double*>(from + (from_slots ? slot : i));
      auto* o = reinterpret_cast<double*>(to + slot);
      const double* w = tw + 2 * t;
      if (step == 1) {
        MultiplyRun(v, w, o, n);
      } else {
        for (Eigen::Index k = 0; k < n; ++k) Multiply(v + 2 * k, w + 2 * k * step, o + 2 * k);
      }
      i += n;
    }
  };
  // The untwiddled band, kept apart for the anchors (the batches overwrite
  // the blocks).
  Complex* band = work + batch * m;
  if (d > kAnchorBlocks) fill(0, bins, band);
  for (Eigen::Index r0 = 0; r0 < d; r0 += batch) {
    for (Eigen::Index r = r0; r < r0 + batch; ++r) {
      Complex* block = work + (r - r0) * m;
      if (r0 == 0) clear(block);
      if (r == 0 && d > kAnchorBlocks) {
        std::copy(band, band + head, block + slot0);
        std::copy(band + head, band + bins, block);
      } else if (r == 0) {
        fill(0, head, block + slot0);
        if (tail > 0) fill(head, tail, block);
      } else if (r % kAnchorBlocks == 0) {
        twiddle(band, block, r, false);
      } else {
        twiddle(work + (r - 1 - r0 + batch) % batch * m, block, 1, true);
      }
    }
    fftw_execute_dft(plan, AsFftw(work), AsFftw(out + r0 * m));
  }
}

namespace {

// Where ExecuteSplit leaves block l's inverse: blocks 0-3 in the half P past
// the 8 input blocks, 4-7 over the inputs of 0-3 (transformed already).
template <class T>
T* SplitBlock(T* work, Eigen::Index p, Eigen::Index l) {
  const Eigen::Index m = p / PrunedInverse::kSplitBlocks;
  return l < 4 ? work + p + l * m : work + (l - 4) * m;
}

struct Cx {
  double re, im;
};
inline Cx operator+(Cx a, Cx b) { return {a.re + b.re, a.im + b.im}; }
inline Cx operator-(Cx a, Cx b) { return {a.re - b.re, a.im - b.im}; }
inline Cx operator*(Cx a, Cx b) { return {a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re}; }
inline Cx TimesI(Cx a) { return {-a.im, a.re}; }

// One n of CombineSplit: y[q] = sum_l t^l z_l[n] exp(2 pi i q l / 8), t = w^n.
inline void Radix8(const double* const z[8], Eigen::Index n, Cx t, double scale, Cx y[8]) {
  const auto at = [&](int l) { return Cx{z[l][2 * n], z[l][2 * n + 1]}; };
  const Cx t2 = t * t, t3 = t2 * t, t4 = t2 * t2, t5 = t4 * t, t6 = t3 * t3, t7 = t4 * t3;
  const Cx z0 = at(0), z1 = at(1) * t, z2 = at(2) * t2, z3 = at(3) * t3, z4 = at(4) * t4,
           z5 = at(5) * t5, z6 = at(6) * t6, z7 = at(7) * t7;
  // Two inverse DFTs of 4 (the even and the odd l), then the step across them.
  const Cx a0 = z0 + z4, a1 = z0 - z4, a2 = z2 + z6, a3 = TimesI(z2 - z6);
  const Cx b0 = z1 + z5, b1 = z1 - z5, b2 = z3 + z7, b3 = TimesI(z3 - z7);
  const Cx e[4] = {a0 + a2, a1 + a3, a0 - a2, a1 - a3};
  const double r = std::numbers::sqrt2 / 2.0;
  const Cx o[4] = {b0 + b2, (b1 + b3) * Cx{r, r}, TimesI(b0 - b2), (b1 - b3) * Cx{-r, r}};
  for (int q = 0; q < 4; ++q) {
    y[q] = {scale * (e[q].re + o[q].re), scale * (e[q].im + o[q].im)};
    y[q + 4] = {scale * (e[q].re - o[q].re), scale * (e[q].im - o[q].im)};
  }
}

#if defined(__x86_64__) && defined(__GNUC__)
#define PODID_SPLIT_AVX2 1
// CombineSplit two n to a vector, each output stream written 32 bytes a
// store. Hand-written: GCC vectorised neither the scalar loop nor its
// target clones, and one n at a time the pass took about 0.2 ms of a D = 1
// scale's 0.45 at fCWT's 10^5 samples, more than the split saved.
__attribute__((target("avx2,fma"))) inline __m256d MulAvx2(__m256d a, __m256d b) {
  const __m256d b_re = _mm256_movedup_pd(b);
  const __m256d b_im = _mm256_permute_pd(b, 0xF);
  return _mm256_fmaddsub_pd(a, b_re, _mm256_mul_pd(_mm256_permute_pd(a, 0x5), b_im));
}
__attribute__((target("avx2,fma"))) inline __m256d TimesIAvx2(__m256d a) {
  return _mm256_xor_pd(_mm256_permute_pd(a, 0x5), _mm256_set_pd(0.0, -0.0, 0.0, -0.0));
}
// Outputs n + q M, q < outputs (<= 8), of every n in [n0, n1), n1 - n0 even.
__attribute__((target("avx2,fma"))) void CombineRunAvx2(const double* const z[8],
                                                        const double* tw,
                                                        Eigen::Index m,
                                                        Eigen::Index n0,
                                                        Eigen::Index n1,
                                                        int outputs,
                                                        double scale,
                                                        double* out) {
  const double r = std::numbers::sqrt2 / 2.0;
  const __m256d w1 = _mm256_set_pd(r, r, r, r), w3 = _mm256_set_pd(r, -r, r, -r);
  const __m256d factor = _mm256_set1_pd(scale);
  for (Eigen::Index n = n0; n < n1; n += 2) {
    const __m256d t1 = _mm256_loadu_pd(tw + 2 * n);
    const __m256d t2 = MulAvx2(t1, t1), t3 = MulAvx2(t2, t1), t4 = MulAvx2(t2, t2);
    const __m256d t5 = MulAvx2(t4, t1), t6 = MulAvx2(t3, t3), t7 = MulAvx2(t4, t3);
    const __m256d z0 = _mm256_loadu_pd(z[0] + 2 * n);
    const __m256d z1 = MulAvx2(_mm256_loadu_pd(z[1] + 2 * n), t1);
    const __m256d z2 = MulAvx2(_mm256_loadu_pd(z[2] + 2 * n), t2);
    const __m256d z3 = MulAvx2(_mm256_loadu_pd(z[3] + 2 * n), t3);
    const __m256d z4 = MulAvx2(_mm256_loadu_pd(z[4] + 2 * n), t4);
    const __m256d z5 = MulAvx2(_mm256_loadu_pd(z[5] + 2 * n), t5);
    const __m256d z6 = MulAvx2(_mm256_loadu_pd(z[6] + 2 * n), t6);
    const __m256d z7 = MulAvx2(_mm256_loadu_pd(z[7] + 2 * n), t7);
    const __m256d a0 = _mm256_add_pd(z0, z4), a1 = _mm256_sub_pd(z0, z4);
    const __m256d a2 = _mm256_add_pd(z2, z6), a3 = TimesIAvx2(_mm256_sub_pd(z2, z6));
    const __m256d b0 = _mm256_add_pd(z1, z5), b1 = _mm256_sub_pd(z1, z5);
    const __m256d b2 = _mm256_add_pd(z3, z7), b3 = TimesIAvx2(_mm256_sub_pd(z3, z7));
    const __m256d e[4] = {_mm256_add_pd(a0, a2), _mm256_add_pd(a1, a3), _mm256_sub_pd(a0, a2),
                          _mm256_sub_pd(a1, a3)};
    const __m256d o[4] = {_mm256_add_pd(b0, b2), MulAvx2(_mm256_add_pd(b1, b3), w1),
                          TimesIAvx2(_mm256_sub_pd(b0, b2)), MulAvx2(_mm256_sub_pd(b1, b3), w3)};
    for (int q = 0; q < 4 && q < outputs; ++q) {
      _mm256_storeu_pd(out + 2 * (n + q * m), _mm256_mul_pd(_mm256_add_pd(e[q], o[q]), factor));
    }
    for (int q = 0; q < 4 && q + 4 < outputs; ++q) {
      _mm256_storeu_pd(out + 2 * (n + (q + 4) * m),
                       _mm256_mul_pd(_mm256_sub_pd(e[q], o[q]), factor));
    }
  }
}
#endif

// Outputs n + q M < times of every n in [n0, n1), one n at a time: the n
// CombineRunAvx2 leaves (an odd one at a run's end), or all without AVX2.
void CombineTail(const double* const z[8],
                 const double* tw,
                 Eigen::Index m,
                 Eigen::Index n0,
                 Eigen::Index n1,
                 Eigen::Index times,
                 double scale,
                 double* out) {
  Cx y[8];
  for (Eigen::Index n = n0; n < n1; ++n) {
    Radix8(z, n, Cx{tw[2 * n], tw[2 * n + 1]}, scale, y);
    for (Eigen::Index q = 0; q < 8 && n + q * m < times; ++q) {
      out[2 * (n + q * m)] = y[q].re;
      out[2 * (n + q * m) + 1] = y[q].im;
    }
  }
}

}  // namespace

fftw_plan PrunedInverse::SplitPlan(bool* measured) const {
  PODID_CHECK(Splittable(p_));
  return BatchedBackwardPlan(static_cast<int>(p_ / kSplitBlocks), 1, measure_, measured);
}

void PrunedInverse::ExecuteSplit(const Complex* spectrum,
                                 const ScaleFilter& filter,
                                 Eigen::Index first_bin,
                                 Eigen::Index bins,
                                 fftw_plan plan,
                                 Complex* work) const {
  PODID_CHECK(Splittable(p_) && bins >= 1 && bins <= p_);
  PODID_CHECK(first_bin >= -((p_ - 1) / 2) && first_bin + bins - 1 <= p_ / 2);
  const Eigen::Index m = p_ / kSplitBlocks;
  // The band as runs of k = b mod P: [k_begin, k_end) holding band entries
  // from i_begin on (one run, or two when the band starts below bin 0).
  struct Run {
    Eigen::Index k_begin, k_end, i_begin;
  };
  Run runs[2];
  int count = 0;
  if (first_bin < 0) {
    runs[count++] = {p_ + first_bin, p_ + std::min<Eigen::Index>(first_bin + bins, 0), 0};
  }
  if (first_bin + bins > 0) {
    const Eigen::Index k0 = std::max<Eigen::Index>(first_bin, 0);
    runs[count++] = {k0, first_bin + bins, k0 - first_bin};
  }
  if (count == 2) std::swap(runs[0], runs[1]);  // in k order
  // Zero slots: the k outside the runs, block by block (k = 8 j + l, j in
  // [ceil((s - l) / 8), ceil((e - l) / 8)) for k in [s, e)).
  const auto clear = [&](Eigen::Index s, Eigen::Index e) {
    for (Eigen::Index l = 0; l < kSplitBlocks; ++l) {
      const Eigen::Index j0 = (s - l + kSplitBlocks - 1) / kSplitBlocks;
      const Eigen::Index j1 = (e - l + kSplitBlocks - 1) / kSplitBlocks;
      if (j1 > j0) std::fill(work + l * m + j0, work + l * m + j1, Complex(0.0, 0.0));
    }
  };
  Eigen::Index k = 0;
  for (int r = 0; r < count; ++r) {
    clear(k, runs[r].k_begin);
    k = runs[r].k_end;
  }
  clear(k, p_);
  // The band a chunk at a time into the free half P past the blocks, then
  // dealt to the blocks' slots.
  Complex* chunk = work + p_;
  const Eigen::Index chunk_bins = std::min(ScaleFilter::kChunkBins, 4 * m);
  for (int r = 0; r < count; ++r) {
    for (Eigen::Index k0 = runs[r].k_begin; k0 < runs[r].k_end; k0 += chunk_bins) {
      const Eigen::Index n = std::min(chunk_bins, runs[r].k_end - k0);
      FillBins(spectrum, filter, first_bin, runs[r].i_begin + (k0 - runs[r].k_begin), n, chunk);
      // Block by block: each block's slots written in order (the chunk,
      // read with stride 8, is in the L1 cache).
      for (Eigen::Index l = 0; l < kSplitBlocks; ++l) {
        const Eigen::Index t0 = (l - k0 % kSplitBlocks + kSplitBlocks) % kSplitBlocks;
        Complex* to = work + l * m + (k0 + t0) / kSplitBlocks;
        for (Eigen::Index t = t0; t < n; t += kSplitBlocks) *to++ = chunk[t];
      }
    }
  }
  for (Eigen::Index l = 0; l < kSplitBlocks; ++l) {
    fftw_execute_dft(plan, AsFftw(work + l * m), AsFftw(SplitBlock(work, p_, l)));
  }
}

void PrunedInverse::CombineSplit(const Complex* work,
                                 Eigen::Index times,
                                 double scale,
                                 Complex* out) const {
  PODID_CHECK(Splittable(p_) && times >= 0 && times <= p_);
  const Eigen::Index m = p_ / kSplitBlocks;
  const double* z[kSplitBlocks];
  for (Eigen::Index l = 0; l < kSplitBlocks; ++l) {
    z[l] = reinterpret_cast<const double*>(SplitBlock(work, p_, l));
  }
  const auto* tw = reinterpret_cast<const double*>(twiddle_.data());
  auto* y = reinterpret_cast<double*>(out);
  const Eigen::Index end = std::min(m, times);
#if defined(PODID_SPLIT_AVX2)
  static const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  if (avx2) {
    // Runs of n with the same count of outputs below `times`: n writes
    // y_(n + q M) for q < c where times - c M <= n < times - (c - 1) M.
    Eigen::Index n = 0;
    for (int c = 8; c >= 1 && n < end; --c) {
      const Eigen::Index run_end = std::clamp<Eigen::Index>(times - (c - 1) * m, n, end);
      const Eigen::Index even_end = n + (run_end - n) / 2 * 2;
      CombineRunAvx2(z, tw, m, n, even_end, c, scale, y);
      CombineTail(z, tw, m, even_end, run_end, times, scale, y);
      n = run_end;
    }
    return;
  }
#endif
  CombineTail(z, tw, m, 0, end, times, scale, y);
}

void PrunedInverse::FillSlots(const Complex* spectrum,
                              const ScaleFilter& filter,
                              Eigen::Index first_bin,
                              Eigen::Index bins,
                              Eigen::Index m,
                              Complex* block) {
  PODID_CHECK(bins >= 0 && bins <= m);
  const Eigen::Index slot0 = ((first_bin % m) + m) % m;
  const Eigen::Index head = std::min(bins, m - slot0);
  FillBins(spectrum, filter, first_bin, 0, head, block + slot0);
  if (bins > head) FillBins(spectrum, filter, first_bin, head, bins - head, block);
}

void PrunedInverse::Gather(const Complex* blocks,
                           Eigen::Index d,
                           Eigen::Index first,
                           Eigen::Index times,
                           double scale,
                           Complex* column) const {
  PODID_CHECK(d >= 1 && d <= kMaxDecimation && p_ % d == 0 && first >= 0 && times >= 0 &&
              first + times <= p_);
  const auto* in = reinterpret_cast<const double*>(blocks);
  auto* out = reinterpret_cast<double*>(column);
#if defined(__SSE2__)
  // The output (16 bytes per value, 300 x 10^5 values in fCWT's case) is far
  // larger than any cache: stream it past the cache instead of reading each
  // line before writing it.
  const __m128d factor = _mm_set1_pd(scale);
  InterleaveBlocks(d, p_ / d, first, times, [&](Eigen::Index j, Eigen::Index i) {
    _mm_stream_pd(out + 2 * j, _mm_mul_pd(_mm_loadu_pd(in + 2 * i), factor));
  });
#else
  InterleaveBlocks(d, p_ / d, first, times, [&](Eigen::Index j, Eigen::Index i) {
    out[2 * j] = in[2 * i] * scale;
    out[2 * j + 1] = in[2 * i + 1] * scale;
  });
#endif
}

void PrunedInverse::FenceStreams() {
#if defined(__SSE2__)
  _mm_sfence();
#endif
}

void PrunedInverse::GatherFloat(const Complex* blocks,
                                Eigen::Index d,
                                Eigen::Index first,
                                Eigen::Index times,
                                double scale,
                                std::complex<float>* column) const {
  PODID_CHECK(d >= 1 && d <= kMaxDecimation && p_ % d == 0 && first >= 0 && times >= 0 &&
              first + times <= p_);
  const auto* in = reinterpret_cast<const double*>(blocks);
#if defined(__SSE2__) && defined(__x86_64__)
  // Streamed past the cache as Gather does, a complex float (8 bytes) a
  // 64-bit non-temporal store. Pairs of outputs in 16-byte streaming stores
  // were not faster (fCWT's case at 10^5, measured plans, 3 interleaved
  // rounds: 141-142 against 133-142 ms).
  auto* out = reinterpret_cast<long long*>(column);
  const __m128d factor = _mm_set1_pd(scale);
  InterleaveBlocks(d, p_ / d, first, times, [&](Eigen::Index j, Eigen::Index i) {
    const __m128 rounded = _mm_cvtpd_ps(_mm_mul_pd(_mm_loadu_pd(in + 2 * i), factor));
    _mm_stream_si64(out + j, _mm_cvtsi128_si64(_mm_castps_si128(rounded)));
  });
#else
  InterleaveBlocks(d, p_ / d, first, times, [&](Eigen::Index j, Eigen::Index i) {
    column[j] = std::complex<float>(static_cast<float>(in[2 * i] * scale),
                                    static_cast<float>(in[2 * i + 1] * scale));
  });
#endif
}

void PrunedInverse::GatherMagnitude(const Complex* blocks,
                                    Eigen::Index d,
                                    Eigen::Index first,
                                    Eigen::Index times,
                                    double scale,
                                    float* scratch,
                                    float* magnitude) const {
  PODID_CHECK(d >= 1 && d <= kMaxDecimation && p_ % d == 0 && first >= 0 && times >= 0 &&
              first + times <= p_);
  if (times == 0) return;
  // |y| of the scaled transform (no overflow), rounded once to float.
  if (d == 1) {
    MagnitudesToFloat(blocks + first, times, scale, magnitude);
    return;
  }
  // The entries q the output reads, block by block, then interleaved.
  const Eigen::Index m = p_ / d;
  const Eigen::Index q0 = first / d, q1 = std::min(m, (first + times - 1) / d + 1);
  for (Eigen::Index r = 0; r < d; ++r) {
    MagnitudesToFloat(blocks + r * m + q0, q1 - q0, scale, scratch + r * m + q0);
  }
  InterleaveBlocks(d, m, first, times,
                   [&](Eigen::Index j, Eigen::Index i) { magnitude[j] = scratch[i]; });
}

}  // namespace podid::wavelet::internal
