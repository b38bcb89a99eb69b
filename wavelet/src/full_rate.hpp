#pragma once
// The full-rate CWT's scale loop (CwtTransform::Compute without band_limited):
// per scale, the filtered band of the spectrum and its pruned inverse
// (pruned_inverse.hpp) at the scale's own decimation D, written straight into
// the output column where the column has room for P values; for a long
// record's scales whose kernel is compact in time, overlap-save blocks
// instead (blocked_scales.hpp).

#include <Eigen/Core>
#include <complex>
#include <functional>
#include <vector>

#include "blocked_scales.hpp"
#include "fftw_plans.hpp"
#include "full_rate_output.hpp"
#include "pruned_inverse.hpp"
#include "scale_filters.hpp"

namespace podid::wavelet::internal {

class FullRateCwt {
 public:
  using Complex = std::complex<double>;
  /// Chunks per thread when threads > 1: enough to even out unequal threads,
  /// few enough that the chunk ends (whose last column cannot spill into the
  /// next chunk, so it is gathered instead of written in place) cost little.
  static constexpr std::size_t kChunksPerThread = 8;
  /// From this length on, a D = 1 scale that does not split (kSplitLength
  /// below) is transformed in place (in its
  /// column, or in the thread's output buffer when the column cannot take P
  /// values or the output is in single precision) instead of from a scratch buffer: once
  /// input and output (32 P bytes) outgrow a 2 MiB L2 cache the scratch's
  /// round trip dominates (FFTW 3.3.10, estimated plans: 0.96 against 1.13 ms
  /// at 102400 points; 0.079 against 0.070 ms at 10752, where the scratch
  /// stays in cache). Not with scripts/build-fftw.sh's FFTW: its out-of-place
  /// plans won on a Zen 5 (1 MiB L2), fCWT's case at 10^5 1.10x faster with
  /// patient plans, 1.00-1.09x with measured ones, where Debian's FFTW lost
  /// 0.95-0.98x (docs/benchmark-log.md, "Threads on the Zen 5, ...").
#if defined(PODID_FFTW_SIMD_CODELETS)
  static constexpr Eigen::Index kInPlaceLength = Eigen::Index{kMaxPlanLength} + 1;
#else
  static constexpr Eigen::Index kInPlaceLength = 65536;
#endif

  /// From this length on, a D = 1 scale is inverted by PrunedInverse's
  /// decimation in time (ExecuteSplit: 8 inverses of P / 8 that fit the L2
  /// cache, then one radix-8 pass written into the column) where P is
  /// Splittable, with scripts/build-fftw.sh's FFTW always, with Debian's when
  /// the inverse of P / 8 is measured (wisdom): its estimated plan lost.
  /// The 65 D = 1 scales of fCWT's case at 10^5 samples (P = 102400) on a
  /// Zen 5, against the path it replaces: Debian's FFTW 1.14x with measured
  /// plans, 0.80x with estimated ones; the AVX2 + AVX-512 build 1.04x
  /// measured, 1.58x estimated (docs/wavelet.md, "D = 1 scales of long
  /// records").
  static constexpr Eigen::Index kSplitLength = 65536;
  /// Whether the D = 1 scales at length p may be split (if their plan allows).
  static constexpr bool MaySplit(Eigen::Index p) {
    return p >= kSplitLength && PrunedInverse::Splittable(p);
  }
#if defined(PODID_FFTW_SIMD_CODELETS)
  static constexpr bool kSplitEstimated = true;
#else
  static constexpr bool kSplitEstimated = false;
#endif

  /// Bytes Layout() allocates: the twiddle table, the blocked scales'
  /// (BlockedScales::Bytes) and, per thread, the pruned inverse's scratch
  /// (PrunedInverse::WorkSize) and output (P).
  static double Bytes(Eigen::Index p, int threads, const BlockedScales::Grouping& blocked);

  /// Plans (one per distinct D) and buffers for padded length p and the
  /// scales' bands and filters (kept by reference: they must outlive the
  /// layout). The scales `blocked` groups are transformed by overlap-save
  /// blocks instead (blocked_scales.hpp; make_filters: every scale's filters
  /// at a block length). Scales are split into contiguous chunks of about
  /// equal cost (kChunksPerThread per thread), which `threads` threads take
  /// in turn.
  void Layout(Eigen::Index p,
              const ScaleFilters& filters,
              BlockedScales::Grouping blocked,
              const std::function<void(Eigen::Index, ScaleFilters*)>& make_filters,
              int threads,
              bool measure);

  /// Every scale of `spectrum` (P / 2 + 1 bins of the padded real signal
  /// `padded`, P values): column k of the output gets output_scale *
  /// W_k(0 .. times - 1), or its rounding to complex float, or its |W| as
  /// float. times <= P.
  void Compute(const Complex* spectrum,
               const double* padded,
               Eigen::Index times,
               double output_scale,
               const FullRateOutput& output) const;

 private:
  void RunScales(int thread,
                 int chunk,
                 const Complex* spectrum,
                 Eigen::Index times,
                 double output_scale,
                 const FullRateOutput& output) const;

  PrunedInverse inverse_;
  BlockedScales blocked_;
  const ScaleFilters* filters_ = nullptr;
  std::vector<Eigen::Index> decimation_;   // per scale
  std::vector<Eigen::Index> batch_;        // per scale: blocks per FFTW call
  std::vector<fftw_plan> plans_;           // per scale
  fftw_plan in_place_ = nullptr;           // length P in place, when P >= kInPlaceLength
  fftw_plan split_ = nullptr;              // the D = 1 scales' ExecuteSplit plan, if they split
  std::vector<Eigen::Index> chunk_begin_;  // chunks + 1: chunk c is [begin_c, begin_c+1)
  int threads_ = 1;
  int plan_alignment_ = 0;                 // fftw_alignment_of the planned arrays
  // Per thread.
  mutable std::vector<ComplexBuffer> input_, output_;
};

}  // namespace podid::wavelet::internal
