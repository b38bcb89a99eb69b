#pragma once
// Full-rate inverse DFT of a band-limited spectrum (a "pruned" inverse FFT),
// the kernel of the full-rate CWT (podid/wavelet/cwt.hpp).
//
// A scale's filtered spectrum Y_b is non-zero only on K consecutive bins
// b = a .. a + K - 1 (a signed), and all P outputs
//   y_j = sum_b Y_b w^(b j),  w = exp(2 pi i / P),  j = 0 .. P - 1,
// are wanted. For any D dividing P with M = P / D >= K, write j = q D + r
// (q < M, r < D): w^(b (q D + r)) = exp(2 pi i b q / M) w^(b r), so
//   y_(q D + r) = sum_b [Y_b w^(b r)] exp(2 pi i b q / M),
// D inverse DFTs of length M, the r-th of the band twiddled by w^(b r) and
// laid at slots b mod M (K <= M: no two bins share a slot); w^(b r) is the
// exact table value (at b r mod P) every 8th block and w^(b (r - 1)) w^b (a
// product with block r - 1, w^b read in order) in between. The blocks are
// twiddled and transformed a batch of G at a time (one FFTW plan of G
// inverses, G M points small enough to stay in the L2 cache with their
// outputs) into contiguous blocks of the output (block r holds y_r, y_(D+r),
// ..), and a gather pass interleaves them into the column, a plain copy.
// Cost: D M log M + D K complex products + one pass over P values instead of
// P log P. Exact: no approximation beyond rounding (at most 8 roundings per
// twiddled bin).

#include <Eigen/Core>
#include <complex>
#include <vector>

#include "fftw_plans.hpp"
#include "scale_filters.hpp"

namespace podid::wavelet::internal {

class PrunedInverse {
 public:
  using Complex = std::complex<double>;
  /// Largest decimation tried; beyond it the per-transform overhead of
  /// inverse DFTs shorter than P / 64 outweighs the shorter log factor.
  static constexpr Eigen::Index kMaxDecimation = 64;
  /// Points (complex doubles) of one batch of blocks: 16384 is 256 KiB, so a
  /// batch's input and output stay in a 2 MiB L2 cache beside the rest of
  /// the output buffer instead of making a round trip through memory.
  static constexpr Eigen::Index kBatchPoints = 16384;

  /// For length p >= 1 (<= 2^27): fills the twiddle table, plans nothing.
  void Reset(Eigen::Index p, bool measure);
  Eigen::Index length() const { return p_; }

  /// D for a band of `bins` bins at length p: the largest power of 2 dividing
  /// p, at most kMaxDecimation, with p / D >= bins (1 when bins > p / 2).
  /// Powers of 2 only: at most 7 plans per length (other divisors would add a
  /// plan for nearly every scale, each measured by `podid plan`).
  static Eigen::Index Decimation(Eigen::Index p, Eigen::Index bins);
  /// G for decimation d at length p: the largest divisor of d with
  /// G p / d <= kBatchPoints, at least 1 (so at D = 1 the whole length).
  static Eigen::Index Batch(Eigen::Index p, Eigen::Index d);
  /// Complex entries of Execute's scratch: a batch (<= P) and the band (<= P / 2).
  static constexpr Eigen::Index WorkSize(Eigen::Index p) { return p + p / 2 + 1; }
  /// The plan of `batch` inverses of length P / d (cached process-wide).
  fftw_plan Plan(Eigen::Index d, Eigen::Index batch) const;

  /// y_0 .. y_(P-1) of the band Y_(a+i) = X_(a+i) g_i, i < bins (g_i the
  /// filter's entry i, read a chunk at a time), into
  /// out (P entries) as D blocks of M: y_(q D + r) at out[r M + q] (for
  /// D = 1 simply y in order). spectrum: X_0 .. X_(P/2) of a real signal (X_-b =
  /// conj X_b), a >= -(P - 1) / 2, a + bins - 1 <= P / 2. work: WorkSize(P)
  /// entries of scratch (overwritten). `batch` divides d; `plan` is
  /// Plan(d, batch) (which preserves its input: block r - 1 must survive its
  /// transform), or at d = 1 an in-place plan of length P with work ==
  /// out (then P entries suffice); out and work must have fftw_malloc's
  /// alignment modulo 16 (any std::complex<double> array has it).
  void Execute(const Complex* spectrum,
               const ScaleFilter& filter,
               Eigen::Index first_bin,
               Eigen::Index bins,
               Eigen::Index d,
               Eigen::Index batch,
               fftw_plan plan,
               Complex* work,
               Complex* out) const;

  /// Blocks of the decimation in time that ExecuteSplit and CombineSplit
  /// apply to the widest bands (D = 1) of long records.
  static constexpr Eigen::Index kSplitBlocks = 8;
  /// Whether length p can be split: P / 8 complex values a multiple of 64
  /// bytes, so every block keeps the alignment of the scratch (FFTW's plans
  /// need it) and no two blocks share a cache line.
  static constexpr bool Splittable(Eigen::Index p) { return p >= 1024 && p % 32 == 0; }
  /// The plan ExecuteSplit takes: one inverse of P / 8 (cached process-wide);
  /// *measured (if given) says whether it was measured (now or in the
  /// wisdom) rather than estimated.
  fftw_plan SplitPlan(bool* measured = nullptr) const;
  /// The same y as Execute at D = 1, for any band, by one radix-8 step of a
  /// decimation in time (docs/wavelet.md, "D = 1 scales of long records"):
  /// bin k = b mod P = 8 j + l of the band goes to slot j of block l, each of
  /// the 8 blocks of M = P / 8 is inverted on its own (200 KB at fCWT's 10^5
  /// samples: in the L2 cache, where one inverse of P is not), and
  /// CombineSplit takes the radix-8 step into the output. work: WorkSize(P)
  /// entries (the blocks' inverses stay there for CombineSplit); plan:
  /// SplitPlan(). Splittable(P) must hold.
  void ExecuteSplit(const Complex* spectrum,
                    const ScaleFilter& filter,
                    Eigen::Index first_bin,
                    Eigen::Index bins,
                    fftw_plan plan,
                    Complex* work) const;
  /// out[j] = scale * y_j, j < times <= P, from ExecuteSplit's work:
  ///   y_(n + q M) = sum_l w^(n l) Z_l(n) exp(2 pi i q l / 8),  n < M, q < 8,
  /// Z_l block l's inverse, w^n from the table, its powers by products (at
  /// most 3 roundings). Ordinary stores: streaming ones (as Gather's) made
  /// the 65 D = 1 scales of fCWT's case at 10^5 slower (29.6 against 26.9 ms).
  void CombineSplit(const Complex* work, Eigen::Index times, double scale, Complex* out) const;

  /// Y_(a+i) = X_(a+i) g_i (Execute's band, a = first_bin), i < bins <= m,
  /// at slots (a + i) mod m of `block`; the other slots are left as they are.
  static void FillSlots(const Complex* spectrum,
                        const ScaleFilter& filter,
                        Eigen::Index first_bin,
                        Eigen::Index bins,
                        Eigen::Index m,
                        Complex* block);

  /// column[j] = scale * y_(first + j), j < times (first + times <= P), from
  /// Execute's blocks at decimation d. Gather and GatherFloat stream the column past the cache
  /// (non-temporal stores, weakly ordered): FenceStreams() before another
  /// thread reads it. A fence a block made the overlap-save blocks wait for
  /// their stores to drain (BlockedScales::Run).
  void Gather(const Complex* blocks,
              Eigen::Index d,
              Eigen::Index first,
              Eigen::Index times,
              double scale,
              Complex* column) const;
  /// column[j] = complex<float>(scale * y_(first + j)), j < times: each part
  /// of the double product correctly rounded, as the complex output rounded.
  void GatherFloat(const Complex* blocks,
                   Eigen::Index d,
                   Eigen::Index first,
                   Eigen::Index times,
                   double scale,
                   std::complex<float>* column) const;
  /// Orders this thread's streaming stores before its later stores (an
  /// sfence): what a thread calls before the columns it gathered are handed
  /// to another.
  static void FenceStreams();
  /// magnitude[j] = float(scale |y_(first + j)|), j < times, from Execute's
  /// blocks (|y| = sqrt(re^2 + im^2), correctly rounded); scratch: P floats
  /// (Execute's work serves).
  void GatherMagnitude(const Complex* blocks,
                       Eigen::Index d,
                       Eigen::Index first,
                       Eigen::Index times,
                       double scale,
                       float* scratch,
                       float* magnitude) const;

 private:
  Eigen::Index p_ = 0;
  bool measure_ = false;
  std::vector<Complex> twiddle_;  // w^t, t = 0 .. P - 1
};

}  // namespace podid::wavelet::internal
