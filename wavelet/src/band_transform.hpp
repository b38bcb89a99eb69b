#pragma once
// The CWT (band-limited or not: podid/wavelet/cwt.hpp, "Band-limited mode")
// of a record in blocks of output times, for ridges in bounded memory.
//
// The output grid is CwtTransform's: padded length P, inverse length M,
// decimation D = P / M, output time j at input sample j D. A record whose
// scalogram is small, or that is shorter than the wavelet's support, is one
// block laid out exactly as CwtTransform lays it out (the same padded
// sequence, filters and FFTs). A longer one is cut into
// blocks of L output times; block b transforms the input samples
// [b L D - H, b L D - H + Pb) of the record's extension (reflect: the infinite
// even extension; zero: zeros; periodic: the record repeated), with the
// overlap H >= the wavelet's support at the lowest frequency (the band
// tolerance's radius r s_max, see SupportRadius), a multiple of D, and
// Pb = D Mb. Inside a block the periodic wrap and the kernel's periodisation
// then reach no output time, so the block's W equals the full record's to
// about band_tolerance of the signal's peak (test BandTransform.*).

#include <Eigen/Core>
#include <complex>
#include <vector>

#include "extent.hpp"
#include "fftw_plans.hpp"
#include "podid/wavelet/cwt.hpp"

namespace podid::wavelet::internal {

class BandTransform {
 public:
  /// Full rate (D = 1) unless options.band_limited. Throws std::invalid_argument if !options.IsValid().
  explicit BandTransform(const CwtOptions& options);

  /// Lays out a record of `samples` (>= 4) at step_s; `max_block_cells`
  /// (output times x frequencies) decides when the record is cut into
  /// blocks. Returns whether the layout changed (plans and filters rebuilt).
  bool Layout(Eigen::Index samples, double step_s, double max_block_cells);

  /// Scales and shifts the record (dim samples of the layout) as CwtTransform
  /// does: exactly by a power of 2 to a peak in [1, 2), minus the mean if asked.
  void SetSignal(const Eigen::Ref<const Eigen::VectorXd>& signal);

  /// Forward FFT of block b's segment (blocks() of them).
  void LoadBlock(Eigen::Index b);
  /// W (derivative: dW/dt in 1/s) of scale k at the loaded block's output
  /// times, in the scaled signal's units: (dim block_times(b)), read in place
  /// from the inverse FFT's buffer (no copy), valid until the next call.
  const std::complex<double>* Synthesise(Eigen::Index k, bool derivative) const;
  /// bound[k] >= |W| of scale k at every output time of the loaded block, in
  /// Synthesise's units: sum over the band of |X_b| |filter_k(b)| (the
  /// inverse FFT's sum term by term), for every scale k.
  void MagnitudeBounds(double* bound);
  /// FFT buffers for Synthesise on another thread (the object's own serve
  /// one thread; the plans and the loaded spectrum are shared, read-only).
  struct Scratch {
    ComplexBuffer work, inverse;
    // work's slots [dirty_first, dirty_first + dirty_size) mod Mb may be
    // non-zero (the last band written; -1: all): only those outside the
    // next band need clearing (the inverse preserves its input).
    Eigen::Index dirty_first = 0, dirty_size = -1;
  };
  /// For the current layout (re-make it after a Layout() that returned true).
  Scratch MakeScratch() const;
  /// Synthesise with `scratch`'s buffers: the result lives in scratch->inverse.
  const std::complex<double>* Synthesise(Eigen::Index k, bool derivative, Scratch* scratch) const;

  Eigen::Index blocks() const { return blocks_; }
  Eigen::Index block_first(Eigen::Index b) const { return b * block_times_; }
  Eigen::Index block_times(Eigen::Index b) const;
  Eigen::Index max_block_times() const { return block_times_; }

  Eigen::Index times() const { return times_; }
  Eigen::Index decimation() const { return d_; }
  Eigen::Index padded_length() const { return p_; }   ///< the full record's P
  Eigen::Index inverse_length() const { return m_; }  ///< the full record's M
  Eigen::Index segment_length() const { return pb_; }  ///< Pb (P for one block)
  /// Bytes of the layout's buffers (filters, FFT buffers, the signal copy).
  double Bytes() const;
  /// Bytes Layout() would allocate, from closed forms (nothing allocated);
  /// *times, *block_times: the output times it would have, in all and per block.
  double PlannedBytes(Eigen::Index samples,
                      double step_s,
                      double max_block_cells,
                      Eigen::Index* times,
                      Eigen::Index* block_times) const;
  /// Whether Layout(samples, step_s, max_block_cells) would change nothing.
  bool IsLaidOut(Eigen::Index samples, double step_s, double max_block_cells) const {
    return samples == n_ && step_s == step_s_ && max_block_cells == max_block_cells_;
  }
  /// 2^e of SetSignal: W of the signal = 2^e W of the scaled one.
  int exponent() const { return exponent_; }

  const Eigen::VectorXd& frequencies_Hz() const { return frequencies_Hz_; }
  const Eigen::VectorXd& scales_s() const { return scales_s_; }
  const CwtOptions& options() const { return options_; }
  double kappa() const { return kappa_; }
  double time_spread() const { return time_spread_; }

 private:
  struct Shape {
    Eigen::Index p = 0, m = 0, d = 1, times = 0;      // the full record's grid
    Eigen::Index blocks = 1, block_times = 0, h = 0;  // h: overlap in input samples
    Eigen::Index pb = 0, mb = 0;                      // a block's lengths
    Eigen::Index filter_bins = 0;
  };
  Shape Plan(Eigen::Index samples, double step_s, double max_block_cells) const;
  Eigen::Index FilterBins(Eigen::Index length, double step_s, Eigen::Index* widest) const;
  double Extension(Eigen::Index i) const;  // the record's extension at input sample i
  const std::complex<double>* SynthesiseInto(Eigen::Index k,
                                             bool derivative,
                                             Scratch* scratch) const;

  CwtOptions options_;
  CwtTransform reference_;  // the full record's P and M (nothing planned)
  double kappa_ = 0.0, time_spread_ = 0.0, band_low_ = 0.0, band_high_ = 0.0;
  Eigen::VectorXd frequencies_Hz_, scales_s_;

  Eigen::Index n_ = 0, p_ = 0, m_ = 0, d_ = 1, times_ = 0;
  Eigen::Index blocks_ = 0, block_times_ = 0, h_ = 0, pb_ = 0, mb_ = 0;
  double step_s_ = 0.0, max_block_cells_ = 0.0, bin_rad_per_s_ = 0.0;
  int exponent_ = 0;
  Eigen::Index loaded_ = -1;
  std::vector<Eigen::Index> band_first_;
  std::vector<std::vector<double>> filters_;
  Eigen::VectorXd signal_;  // scaled (and centred) record
  fftw_plan forward_ = nullptr, backward_ = nullptr;
  RealBuffer segment_;
  ComplexBuffer spectrum_;
  Eigen::VectorXd magnitude_;  // MagnitudeBounds' |X_b|, b <= Pb / 2
  mutable Scratch own_;  // the inverse FFT's input and output for Synthesise(k, derivative)
};

}  // namespace podid::wavelet::internal
