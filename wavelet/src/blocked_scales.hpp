#pragma once
// The full-rate CWT of a long record, by overlap-save blocks, at the scales
// whose wavelet is compact in time (FullRateCwt, full_rate.hpp).
//
// The full-rate path transforms a scale with inverse FFTs that span the
// whole padded length P (P / D points each at decimation D). For a long
// record those outgrow the L2 cache: at 10^5 samples the inverse and its
// gather make a round trip through memory per scale. A scale whose band lies
// strictly inside the spectrum (not cut at Nyquist, nor at -P / 2) has a
// kernel that is compact in time: below band_tolerance of its peak beyond
// H = SupportRadius (extent.hpp) samples. Its W at output times [j B, j B + B)
// is then the circular convolution, over a segment of L = B + 2 H samples
// of the padded sequence starting at j B - H (mod P), with the kernel
// periodised by L instead of P: the two periodisations differ only by the
// kernel's tail beyond H, below band_tolerance of its peak. Per block: the
// segment's spectrum (one forward FFT of L, shared by every scale of a
// group), the band times the filter sampled at L points, an inverse FFT of
// L (in the L1/L2 cache) and B outputs written once.
// One scale of fCWT's case at 10^5 samples, stand-alone: 0.23-0.29 ms in
// blocks for 2-13 Hz against 0.43-0.55 ms in place at P; the whole case
// 1.2x faster (docs/benchmark-log.md, "Overlap-save blocks for compact
// scales").
//
// A narrow band is inverted at L as PrunedInverse does at P: D' inverses of
// L / D' (D' = `inner`, up to the scale's D), the band twiddled for each,
// and the block's outputs interleaved from them: FFTW took 1.02 ns a point
// for 16 x 512 points against 2.17 for one 8192-point inverse (its
// per-point cost grows with the length beyond the log, the L1 cache).
//
// Scales are grouped by their decimation D at P (an octave each): a group
// shares one block grid, with H its largest support, L from {2048, 4096,
// 8192} and D' the cheapest per kept sample ((FftCostModel(L / D') + the
// twiddle pass) L / (L - 2 H)), at most 2 H = L / 2 thrown away. Scales
// whose band reaches Nyquist (the kernel is then cut by a step in
// frequency, with 1 / t tails), records shorter than kMinPaddedLength (their
// inverses stay in cache) and groups that would not be cheaper than the
// pruned inverse keep that path.

#include <Eigen/Core>
#include <complex>
#include <functional>
#include <vector>

#include "fftw_plans.hpp"
#include "full_rate_output.hpp"
#include "pruned_inverse.hpp"
#include "scale_filters.hpp"

namespace podid::wavelet::internal {

class BlockedScales {
 public:
  using Complex = std::complex<double>;
  /// Shortest padded length blocked: below it a scale's inverse (16 P bytes
  /// at most) and its output stay in a 1 MiB L2 cache.
  static constexpr Eigen::Index kMinPaddedLength = 65536;
  /// The block lengths tried (powers of 2: FFTW's fastest per point in L1/L2).
  static constexpr Eigen::Index kLengths[] = {2048, 4096, 8192};
  static constexpr Eigen::Index kMaxLength = 8192;
  /// Complex entries of Run's scratch: PrunedInverse::Execute's work and
  /// output at kMaxLength, and the scale's filter (up to kMaxLength + 1
  /// doubles).
  static constexpr Eigen::Index kWorkSize =
      PrunedInverse::WorkSize(kMaxLength) + kMaxLength + kMaxLength / 2 + 1;

  /// What the grouping needs of scale k.
  struct Scale {
    Eigen::Index decimation = 1;  ///< D at P (PrunedInverse::Decimation)
    bool inside = false;          ///< band strictly inside (-P / 2, P / 2): not cut
    double support = 0.0;         ///< kernel radius in samples (to band_tolerance)
  };
  /// One block grid: segments of `length` at hop `hop`, `overlap` = H.
  struct Group {
    Eigen::Index decimation = 1, length = 0, overlap = 0, hop = 0, blocks = 0;
    /// Largest decimation D' of a block's inverse (<= decimation; a scale's
    /// own is InnerDecimation).
    Eigen::Index inner = 1;
    /// Bins 0 .. bins - 1 of each segment's spectrum are kept: every band of
    /// the group at this length lies in (-bins, bins) (a negative bin is read
    /// as the conjugate of its positive one). Set by the caller (KeepBins).
    Eigen::Index bins = 0;
  };
  struct Grouping {
    std::vector<Group> groups;
    std::vector<int> group;  ///< per scale: its group, -1 if not blocked
  };
  /// The grouping for padded length p and `times` output times (pure: the
  /// same for Layout and CwtTransform::Lengths).
  static Grouping Plan(Eigen::Index p, Eigen::Index times, const std::vector<Scale>& scales);
  /// D' of a scale of `group` whose band at the group's length is bins
  /// first .. first + bins - 1: at most group.inner, with L / D' >= bins
  /// (PrunedInverse::Decimation), 1 for a band Execute does not take.
  static Eigen::Index InnerDecimation(const Group& group, Eigen::Index first, Eigen::Index bins);
  /// Bytes Layout allocates for `grouping` (its groups' bins set): the kept
  /// bins of the block spectra and the twiddle tables;
  /// the filters are the caller's.
  static double Bytes(const Grouping& grouping);

  /// Lays out `grouping`; make_filters(L, &filters) fills every scale's band
  /// and filter at padded length L (CwtTransform's SetFilters).
  void Layout(Eigen::Index p,
              Grouping grouping,
              const std::function<void(Eigen::Index, ScaleFilters*)>& make_filters,
              bool measure);
  bool Blocked(Eigen::Index k) const {
    return !grouping_.group.empty() && grouping_.group[static_cast<std::size_t>(k)] >= 0;
  }
  bool empty() const { return grouping_.groups.empty(); }
  /// Cost of scale k in complex products (FullRateCwt's chunking).
  double Cost(Eigen::Index k) const;

  /// Blocks over all groups: LoadBlock's indices 0 .. blocks() - 1.
  Eigen::Index blocks() const;
  /// Block `index` (the groups' blocks in turn) of the padded sequence (P
  /// values, the transform's scaled signal): its segment's kept spectrum.
  /// segment: kMaxLength complex of scratch. Distinct blocks may be loaded by
  /// threads at once; every block before Run. Does not throw.
  void LoadBlock(Eigen::Index index, const double* padded, Complex* segment) const;
  /// Scale k (Blocked) at output times 0 .. times - 1 into `output`'s column
  /// k, times output_scale; work: kWorkSize complex of scratch. The column is
  /// written with streaming stores: PrunedInverse::FenceStreams() before
  /// another thread reads it. Does not throw.
  void Run(Eigen::Index k,
           Eigen::Index times,
           double output_scale,
           Complex* work,
           const FullRateOutput& output) const;

 private:
  struct Grid {  // one per block length
    Eigen::Index length = 0;
    PrunedInverse inverse;         // the D' > 1 inverses and every gather
    ScaleFilters filters;          // every scale's band and filter at this length
    fftw_plan forward = nullptr;   // in place
  };
  const Grid& GridOf(Eigen::Index length) const;

  Eigen::Index p_ = 0;
  Grouping grouping_;
  std::vector<Eigen::Index> inner_;  // per scale: its D' (1 if not blocked)
  std::vector<fftw_plan> plans_;     // per blocked scale: D' inverses of L / D' (input preserved)
  std::vector<Grid> grids_;
  mutable std::vector<ComplexBuffer> spectra_;  // per group: blocks x bins (LoadBlock)
};

}  // namespace podid::wavelet::internal
