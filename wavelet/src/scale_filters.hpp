#pragma once
// Each scale's filter of the CWT, n(s) psi^(s w_b) / P over the scale's band
// of bins b = first .. first + bins - 1 (CwtTransform, podid/wavelet/cwt.hpp).
//
// Stored, or generated on demand where psi^ is one Gaussian (Morlet without
// the admissibility correction): g_b = A exp(-t_b^2 / 2), t_b = c b - omega0,
// from A, c and omega0. The stored filters of fCWT's case (300 scales) are 8 MB
// at 10^4 samples and 74 MB at 10^5, read at every transform, and the band
// fill waited on them (76 % of its samples on the filter's load, 1.1 ns a
// bin at 10^4); generated a chunk at a time, they stay in the L1 cache.
// Generation, all by products of ratios that are themselves geometric:
//  - bins 8 apart, g_(b+8) = g_b r_b with r_(b+8) = r_b exp(-64 c^2), 8 lanes
//    at a time, in blocks of 128 bins;
//  - a block's 8 lane starts from its first bin's g, rho = g_(b+1) / g_b and
//    r, and those from the previous block's by their own ratios;
//  - 0 where t < -32 (below 4.4e-223 of the peak): from t = -omega0 (bin 0)
//    the ratios up to the peak, exp(omega0^2 / 2), overflowed beyond
//    omega0 = 37.68 and W was NaN or 0;
//  - exactly (std::exp) at every 1024th bin from there, so 4 exp per 1024 bins (libm's
//    exp took about 14 ns a call here: restarts from it every 128 bins cost
//    as much as the table's loads they replaced): a value carries at most
//    about 530 roundings, 5.9e-14 of itself (test ScaleFilters.*, within 1e-13);
//    a band started at t = -32 on a coarse grid (omega0 100, 0.3 a bin)
//    reached 1.2e-13 in the SSE2 clone, beyond the |t| 2 eps (|t| + 2 centre)
//    that rounding t itself costs (test GeneratedFromBinZeroForEveryOmega0).

#include <Eigen/Core>
#include <vector>

#include "podid/wavelet/cwt.hpp"

namespace podid::wavelet::internal {

/// One scale's filter as the transforms read it: entries [begin, begin +
/// count) of its band (entry i is bin first + i), a chunk at a time.
class ScaleFilter {
 public:
  /// Most entries one Values call gives (its scratch: 8 KiB, in L1).
  static constexpr Eigen::Index kChunkBins = 1024;

  /// Stored values (entry i at values[i]).
  static ScaleFilter Stored(const double* values);
  /// amplitude exp(-t^2 / 2), t = step (first + i) - centre, generated.
  static ScaleFilter Gaussian(double amplitude, double step, double centre, Eigen::Index first);

  /// The filter at entries [begin, begin + count), count <= kChunkBins:
  /// into the stored values, or generated into scratch (kChunkBins doubles),
  /// the same values however a band is cut into calls.
  const double* Values(Eigen::Index begin, Eigen::Index count, double* scratch) const;
  /// Whether Values generates (into its scratch) rather than reads.
  bool generated() const { return generated_; }

  /// A generated filter's constants: A, c, omega0, the first bin and the
  /// ratios of its recurrences (scale_filters.cpp).
  struct Generator {
    double amplitude, step, centre;
    Eigen::Index first;
    Eigen::Index zeros;  // entries [0, zeros): t < -kTail, generated as 0 (scale_filters.cpp)
    double lane_rho, lane_ratio, ratio_step, block_g_step, block_rho_step, block_r_step;
  };

 private:
  bool generated_ = false;
  const double* stored_ = nullptr;
  Generator generator_{};
};

/// Every scale's band and filter.
class ScaleFilters {
 public:
  /// Whether `wavelet`'s filters are generated (one Gaussian) rather than stored.
  static bool Generated(const MorletWavelet& wavelet);
  /// Bytes of the filters: 8 per bin of every band if stored, none if generated.
  static double Bytes(const MorletWavelet& wavelet, Eigen::Index filter_bins);

  /// `scales` scales of `wavelet`, no band yet.
  void Reset(const MorletWavelet& wavelet, Eigen::Index scales);
  /// Scale k's band [first, last] (empty if last < first) and filter
  /// norm psi^(scale_s b bin_rad_per_s), as CwtTransform defines it.
  void Set(Eigen::Index k,
           Eigen::Index first,
           Eigen::Index last,
           double scale_s,
           double norm,
           double bin_rad_per_s);

  Eigen::Index scales() const { return static_cast<Eigen::Index>(first_.size()); }
  Eigen::Index first(Eigen::Index k) const { return first_[static_cast<std::size_t>(k)]; }
  Eigen::Index bins(Eigen::Index k) const { return bins_[static_cast<std::size_t>(k)]; }
  ScaleFilter Filter(Eigen::Index k) const;

 private:
  bool generated_ = false;
  MorletWavelet wavelet_;
  std::vector<Eigen::Index> first_, bins_;
  std::vector<std::vector<double>> stored_;
  std::vector<ScaleFilter> gaussian_;
};

}  // namespace podid::wavelet::internal
