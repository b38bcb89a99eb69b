// The band-limited CWT in blocks of output times (band_transform.hpp).
#include "band_transform.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <stdexcept>
#include <string>

#include "podid/core/error.hpp"
#include "podid/core/target_clones.hpp"
#include "ridge_cost.hpp"
#include "signal_check.hpp"

namespace podid::wavelet::internal {
namespace {

using Complex = std::complex<double>;
constexpr double kPi = std::numbers::pi;
using V4 = double __attribute__((vector_size(32)));
using V4Bits = unsigned long long __attribute__((vector_size(32)));

// sum_i a[i] |w[i]|, i < n, in GCC vectors of 4 (two sums in flight).
PODID_CLONES_V3 double WeightedSum(const double* a, const double* w, Eigen::Index n) {
  const V4 magnitude_bits = (V4)(V4Bits{} + 0x7fffffffffffffffULL);
  V4 s0{}, s1{};
  Eigen::Index i = 0;
  for (; i + 8 <= n; i += 8) {
    V4 a0, a1, w0, w1;
    std::memcpy(&a0, a + i, sizeof a0);
    std::memcpy(&a1, a + i + 4, sizeof a1);
    std::memcpy(&w0, w + i, sizeof w0);
    std::memcpy(&w1, w + i + 4, sizeof w1);
    s0 += a0 * (V4)((V4Bits)w0 & (V4Bits)magnitude_bits);
    s1 += a1 * (V4)((V4Bits)w1 & (V4Bits)magnitude_bits);
  }
  const V4 s = s0 + s1;
  double sum = (s[0] + s[1]) + (s[2] + s[3]);
  for (; i < n; ++i) sum += a[i] * std::abs(w[i]);
  return sum;
}

// A block's inverse length at least this many times its two overlaps: the
// overlap then costs at most 1/4 of the transform. Not more: shorter blocks
// keep a block's costs (times x frequencies) nearer the cache, which paid
// more than the overlap cost (4 against 8: the Silverbox evaluation 1.08x,
// the 10^6-sample ridge 1.13x; docs/benchmark-log.md, "Shorter ridge blocks").
constexpr Eigen::Index kOverlapShare = 4;

}  // namespace

BandTransform::BandTransform(const CwtOptions& options)
    : options_(options), reference_(options) {
  kappa_ = options_.wavelet.ScaleFrequencyConstant();
  time_spread_ = options_.wavelet.TimeSpread();
  options_.wavelet.Band(options_.band_tolerance, &band_low_, &band_high_);
  frequencies_Hz_ = options_.frequencies.Frequencies_Hz();
  scales_s_ = kappa_ / (2.0 * kPi) * frequencies_Hz_.cwiseInverse();
}

Eigen::Index BandTransform::block_times(Eigen::Index b) const {
  return std::min(block_times_, times_ - b * block_times_);
}

// Bins kept over all scales for an FFT of `length` points; *widest: the widest band.
Eigen::Index BandTransform::FilterBins(Eigen::Index length, double step_s, Eigen::Index* widest) const {
  const double bin = 2.0 * kPi / (static_cast<double>(length) * step_s);
  const Eigen::Index lowest = -((length - 1) / 2), highest = length / 2;
  Eigen::Index total = 0;
  *widest = 1;
  for (Eigen::Index k = 0; k < scales_s_.size(); ++k) {
    const double to_bin = 1.0 / (scales_s_(k) * bin);
    const Eigen::Index a = std::max(lowest, static_cast<Eigen::Index>(std::ceil(band_low_ * to_bin)));
    const Eigen::Index b = std::min(highest, static_cast<Eigen::Index>(std::floor(band_high_ * to_bin)));
    total += std::max<Eigen::Index>(0, b - a + 1);
    *widest = std::max<Eigen::Index>(*widest, b - a + 1);
  }
  return total;
}

BandTransform::Shape BandTransform::Plan(Eigen::Index samples, double step_s, double max_block_cells) const {
  Shape z;
  const FftLengths lengths = reference_.Lengths(samples, step_s);  // the full record's grid
  z.p = lengths.real_forward.front();
  z.m = lengths.complex_backward.front();
  z.d = z.p / z.m;
  z.times = (samples - 1) / z.d + 1;
  const double freqs = static_cast<double>(scales_s_.size());
  Eigen::Index widest = 0;
  const double radius = SupportRadius(
      time_spread_, options_.wavelet.family == WaveletFamily::kMorse, options_.band_tolerance);
  const double support_samples = std::ceil(radius * scales_s_.maxCoeff() / step_s);
  // One block for a small scalogram, and for a wavelet longer than the record
  // (overlaps of more than the record save nothing; at a step such as 1e-300 s
  // the support in samples overflowed the index): the memory budget decides.
  if (static_cast<double>(z.times) * freqs <= max_block_cells ||
      !(support_samples < static_cast<double>(samples))) {
    z.blocks = 1;
    z.block_times = z.times;
    z.pb = z.p;
    z.mb = z.m;
    z.filter_bins = FilterBins(z.p, step_s, &widest);
    return z;
  }
  const auto support = static_cast<Eigen::Index>(support_samples);
  const Eigen::Index overlap = (support + z.d) / z.d;  // output steps, > support / D
  z.h = overlap * z.d;
  const Eigen::Index by_cells =
      std::max<Eigen::Index>(1, static_cast<Eigen::Index>(max_block_cells / freqs));
  // The cheapest FFT per kept output time, the overlaps thrown away: at the
  // Silverbox's 2 x 218, 2048 points keep 1612 times against 1792's 1356 (FFTW
  // 1.76 against 2.25 ns a point, estimated plans; docs/benchmark-log.md, "Ridge
  // blocks by cost per kept time"). Capped by max_block_cells: as for a record.
  Eigen::Index mb =
      FastBlockLength(std::max<Eigen::Index>(kOverlapShare * 2 * overlap, 1024), 2 * overlap);
  const bool capped = mb - 2 * overlap > by_cells;
  if (capped) mb = FastFftLength(2 * overlap + by_cells);
  // The block's bands must fit its inverse length (they scale with Pb as M's with P).
  for (;;) {
    FilterBins(z.d * mb, step_s, &widest);
    if (widest <= mb) break;
    mb = capped ? FastFftLength(mb + 1) : FastBlockLength(mb + 1, 2 * overlap);
  }
  z.mb = mb;
  z.pb = z.d * mb;
  z.block_times = std::max<Eigen::Index>(1, std::min(mb - 2 * overlap, z.times));
  z.blocks = (z.times + z.block_times - 1) / z.block_times;
  z.filter_bins = FilterBins(z.pb, step_s, &widest);
  return z;
}

double BandTransform::PlannedBytes(Eigen::Index samples,
                                   double step_s,
                                   double max_block_cells,
                                   Eigen::Index* times,
                                   Eigen::Index* block_times) const {
  const Shape z = Plan(samples, step_s, max_block_cells);
  *times = z.times;
  *block_times = z.block_times;
  return 8.0 * static_cast<double>(z.filter_bins) + 28.0 * static_cast<double>(z.pb) + 8.0 +
         32.0 * static_cast<double>(z.mb) +
         (z.blocks > 1 ? 8.0 * static_cast<double>(samples) : 0.0);
}

double BandTransform::Bytes() const {
  Eigen::Index bins = 0;
  for (const auto& f : filters_) bins += static_cast<Eigen::Index>(f.size());
  return 8.0 * static_cast<double>(bins) + 24.0 * static_cast<double>(pb_) +
         32.0 * static_cast<double>(mb_) +
         8.0 * static_cast<double>(magnitude_.size() + signal_.size());
}

bool BandTransform::Layout(Eigen::Index samples, double step_s, double max_block_cells) {
  if (IsLaidOut(samples, step_s, max_block_cells)) return false;
  const Shape z = Plan(samples, step_s, max_block_cells);
  n_ = samples;
  step_s_ = step_s;
  max_block_cells_ = max_block_cells;
  p_ = z.p;
  m_ = z.m;
  d_ = z.d;
  times_ = z.times;
  blocks_ = z.blocks;
  block_times_ = z.block_times;
  h_ = z.h;
  pb_ = z.pb;
  mb_ = z.mb;
  loaded_ = -1;
  bin_rad_per_s_ = 2.0 * kPi / (static_cast<double>(pb_) * step_s_);
  const Eigen::Index lowest = -((pb_ - 1) / 2), highest = pb_ / 2;
  const bool energy = options_.wavelet.normalisation == Normalisation::kEnergy;
  const Eigen::Index scales = scales_s_.size();
  band_first_.assign(static_cast<std::size_t>(scales), 0);
  filters_.assign(static_cast<std::size_t>(scales), {});
  for (Eigen::Index k = 0; k < scales; ++k) {
    const double s = scales_s_(k);
    const double to_bin = 1.0 / (s * bin_rad_per_s_);
    const Eigen::Index a = std::max(lowest, static_cast<Eigen::Index>(std::ceil(band_low_ * to_bin)));
    const Eigen::Index b = std::min(highest, static_cast<Eigen::Index>(std::floor(band_high_ * to_bin)));
    PODID_CHECK(b - a + 1 <= mb_);  // the band never folds onto itself
    const double norm = (energy ? std::sqrt(s) : 1.0) / static_cast<double>(pb_);
    auto& filter = filters_[static_cast<std::size_t>(k)];
    for (Eigen::Index bin = a; bin <= b; ++bin) {
      filter.push_back(norm * options_.wavelet.FourierTransform(s * bin * bin_rad_per_s_));
    }
    band_first_[static_cast<std::size_t>(k)] = a;
  }
  const bool measure = options_.planning == FftPlanning::kMeasure;
  forward_ = RealForwardPlan(static_cast<int>(pb_), measure);
  // Out of place (a batch of one): FFTW's in-place plans copy through a buffer.
  backward_ = BatchedBackwardPlan(static_cast<int>(mb_), 1, measure);
  segment_ = AllocateReal(static_cast<std::size_t>(pb_));
  spectrum_ = AllocateComplex(static_cast<std::size_t>(pb_ / 2 + 1));
  // |X_b| for the bins some band reaches (|b| for the negative ones): up to
  // about 2.2 times the highest frequency, not Nyquist.
  Eigen::Index reach = 0;
  for (Eigen::Index k = 0; k < scales; ++k) {
    const Eigen::Index a = band_first_[static_cast<std::size_t>(k)];
    const auto size = static_cast<Eigen::Index>(filters_[static_cast<std::size_t>(k)].size());
    if (size > 0) reach = std::max({reach, -a, a + size - 1});
  }
  magnitude_.resize(reach + 1);
  own_ = MakeScratch();
  signal_.resize(blocks_ > 1 ? n_ : 0);
  return true;
}

void BandTransform::SetSignal(const Eigen::Ref<const Eigen::VectorXd>& signal) {
  PODID_CHECK(signal.size() == n_);
  loaded_ = -1;
  exponent_ = PeakExponent(signal);
  // One block: CwtTransform's padded sequence, built as it builds it.
  double* x = blocks_ == 1 ? segment_.get() : signal_.data();
  // 2^-e is a normal double for |e| <= 1000: multiplying is exact like ldexp, and cheaper.
  if (std::abs(exponent_) <= 1000) {
    const double factor = std::ldexp(1.0, -exponent_);
    for (Eigen::Index i = 0; i < n_; ++i) x[i] = signal(i) * factor;
  } else {
    for (Eigen::Index i = 0; i < n_; ++i) x[i] = std::ldexp(signal(i), -exponent_);
  }
  if (options_.remove_mean) {
    const double mean = Eigen::Map<const Eigen::VectorXd>(x, n_).mean();
    for (Eigen::Index i = 0; i < n_; ++i) x[i] -= mean;
  }
  if (blocks_ > 1) return;
  const Eigen::Index r = (p_ - n_ + 1) / 2;
  if (options_.padding == Padding::kReflect && r <= n_ - 2 && p_ - n_ - r <= n_ - 2) {
    // Mirror's values without its modulo: one reflection at each end.
    for (Eigen::Index i = n_; i < n_ + r; ++i) x[i] = x[2 * n_ - 2 - i];
    for (Eigen::Index i = n_ + r; i < p_; ++i) x[i] = x[p_ - i];
  } else if (options_.padding == Padding::kReflect) {
    for (Eigen::Index i = n_; i < n_ + r; ++i) x[i] = x[Mirror(i, n_)];
    for (Eigen::Index i = n_ + r; i < p_; ++i) x[i] = x[Mirror(i - p_, n_)];
  } else if (options_.padding == Padding::kZero) {
    std::fill(x + n_, x + p_, 0.0);
  }
}

double BandTransform::Extension(Eigen::Index i) const {
  switch (options_.padding) {
    case Padding::kReflect:
      return signal_(Mirror(i, n_));
    case Padding::kZero:
      return i >= 0 && i < n_ ? signal_(i) : 0.0;
    case Padding::kPeriodic:
      return signal_(((i % n_) + n_) % n_);
  }
  return 0.0;
}

void BandTransform::LoadBlock(Eigen::Index b) {
  PODID_CHECK(b >= 0 && b < blocks_);
  if (blocks_ > 1) {
    const Eigen::Index first = b * block_times_ * d_ - h_;
    double* x = segment_.get();
    for (Eigen::Index q = 0; q < pb_; ++q) {
      const Eigen::Index i = first + q;
      x[q] = i >= 0 && i < n_ ? signal_(i) : Extension(i);
    }
  } else if (loaded_ == 0) {
    return;
  }
  fftw_execute_dft_r2c(forward_, segment_.get(), AsFftw(spectrum_.get()));
  loaded_ = b;
}

void BandTransform::MagnitudeBounds(double* bound) {
  PODID_CHECK(loaded_ >= 0);
  // |X_b| for the bins the bands reach.
  Magnitudes(spectrum_.get(), magnitude_.size(), magnitude_.data());
  const double* magnitude = magnitude_.data();
  for (std::size_t k = 0; k < filters_.size(); ++k) {
    const auto& filter = filters_[k];
    const Eigen::Index a = band_first_[k], size = static_cast<Eigen::Index>(filter.size());
    const Eigen::Index negative = std::min<Eigen::Index>(size, std::max<Eigen::Index>(0, -a));
    double sum = 0.0;
    for (Eigen::Index i = 0; i < negative; ++i) sum += magnitude[-(a + i)] * std::abs(filter[i]);
    bound[k] =
        sum + WeightedSum(magnitude + a + negative, filter.data() + negative, size - negative);
  }
}

const Complex* BandTransform::Synthesise(Eigen::Index k, bool derivative) const {
  return SynthesiseInto(k, derivative, &own_);
}

BandTransform::Scratch BandTransform::MakeScratch() const {
  Scratch scratch;
  scratch.work = AllocateComplex(static_cast<std::size_t>(mb_));
  scratch.inverse = AllocateComplex(static_cast<std::size_t>(mb_));
  return scratch;
}

const Complex* BandTransform::Synthesise(Eigen::Index k, bool derivative, Scratch* scratch) const {
  return SynthesiseInto(k, derivative, scratch);
}

namespace {

// Zeroes w over the circular range [first, first + size) mod m except the
// band's [start, start + band) mod m (the band's slots are written next).
void ClearOutsideBand(Complex* w,
                      Eigen::Index m,
                      Eigen::Index first,
                      Eigen::Index size,
                      Eigen::Index start,
                      Eigen::Index band) {
  // Both ranges as at most two linear pieces each; the band's are disjoint.
  const Eigen::Index old_pieces[2][2] = {{first, std::min(first + size, m)},
                                         {0, std::max<Eigen::Index>(0, first + size - m)}};
  const Eigen::Index band_pieces[2][2] = {{start, std::min(start + band, m)},
                                          {0, std::max<Eigen::Index>(0, start + band - m)}};
  for (const auto& piece : old_pieces) {
    // piece minus the band pieces: walk it left to right, skipping their overlaps.
    Eigen::Index at = piece[0];
    while (at < piece[1]) {
      Eigen::Index stop = piece[1];
      bool inside = false;
      for (const auto& b : band_pieces) {
        if (b[0] < b[1] && at >= b[0] && at < b[1]) {
          at = b[1];
          inside = true;
          break;
        }
        if (b[0] > at && b[0] < stop) stop = b[0];
      }
      if (inside) continue;
      std::fill(w + at, w + stop, Complex(0.0, 0.0));
      at = stop;
    }
  }
}

}  // namespace

// Writes only the scratch's buffers: with distinct ones, calls run on several threads.
const Complex* BandTransform::SynthesiseInto(Eigen::Index k,
                                             bool derivative,
                                             Scratch* scratch) const {
  Complex* w = scratch->work.get();
  Complex* inverse = scratch->inverse.get();
  PODID_CHECK(loaded_ >= 0 && k >= 0 && k < scales_s_.size());
  const auto& filter = filters_[static_cast<std::size_t>(k)];
  const Eigen::Index a = band_first_[static_cast<std::size_t>(k)];
  const Complex* x = spectrum_.get();
  const Eigen::Index size = static_cast<Eigen::Index>(filter.size());
  const double* gain = filter.data();
  // Bin b lands at b mod Mb: at the decimated times the exponentials are
  // Mb-periodic in b, and the band (<= Mb bins) never folds onto itself. The
  // band's slots are written, the rest zeroed; negative bins are the
  // conjugates of positive ones (a real signal).
  const Eigen::Index start = ((a % mb_) + mb_) % mb_;
  if (scratch->dirty_size < 0) {
    ClearOutsideBand(w, mb_, 0, mb_, start, size);
  } else {
    ClearOutsideBand(w, mb_, scratch->dirty_first, scratch->dirty_size, start, size);
  }
  scratch->dirty_first = start;
  scratch->dirty_size = size;
  const auto slot = [&](Eigen::Index i) { return start + i < mb_ ? start + i : start + i - mb_; };
  const Eigen::Index negative = std::min<Eigen::Index>(size, std::max<Eigen::Index>(0, -a));
  if (derivative) {
    for (Eigen::Index i = 0; i < size; ++i) {
      const Eigen::Index bin = a + i;
      const Complex value = i < negative ? std::conj(x[-bin]) : x[bin];
      w[slot(i)] = value * Complex(0.0, gain[i] * static_cast<double>(bin) * bin_rad_per_s_);
    }
  } else {
    for (Eigen::Index i = 0; i < negative; ++i) w[slot(i)] = std::conj(x[-(a + i)]) * gain[i];
    // The positive bins in at most two contiguous runs: up to the buffer's
    // end, then from slot 0 (a per-bin slot test kept the wrapped band scalar).
    const Eigen::Index split = std::clamp(mb_ - start, negative, size);  // the first i that wraps
    const auto run = [&](Eigen::Index from, Eigen::Index to, Complex* out) {
      const Complex* in = x + (a + from);
      for (Eigen::Index i = from; i < to; ++i, ++in, ++out) *out = *in * gain[i];
    };
    run(negative, split, w + start + negative);
    run(split, size, w + (start + split - mb_));
  }
  fftw_execute_dft(backward_, AsFftw(w), AsFftw(inverse));
  return inverse + h_ / d_;
}

}  // namespace podid::wavelet::internal
