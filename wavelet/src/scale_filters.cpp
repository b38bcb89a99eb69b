#include "scale_filters.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "podid/core/error.hpp"
#include "podid/core/target_clones.hpp"

namespace podid::wavelet::internal {
namespace {

using V8 = double __attribute__((vector_size(64)));
constexpr Eigen::Index kLanes = 8;
constexpr Eigen::Index kBlock = 128;   // bins of one block of the 8 lanes
constexpr Eigen::Index kExact = 1024;  // bins between two exact (std::exp) starts
// Entries with t < -kTail are 0 (exactly, below e^-512 = 4.4e-223 of the
// peak). From the band's bin 0, t = -omega0, a start's ratios up to the peak
// reached exp(omega0^2 / 2): inf beyond omega0 = 37.68 (DBL_MAX = e^709.8),
// with g = A exp(-omega0^2 / 2) 0 beyond about 38.5, so W was NaN or 0.
// From t >= -32 the ratios stay below e^512 and g above A e^-512, normal for
// A >= 1e-85 (A = n(s) psi^(omega0) / P: above 1e-17 below Nyquist at any
// accepted step and length).
constexpr double kTail = 32.0;

// Entries [begin, end) of the generated filter into out (entry begin at
// out[0]). Exact starts at f.zeros plus multiples of kExact, so any cut of a
// band gives the same values. One GCC vector of 8 lanes: one AVX-512 register in
// the v4 clone, two AVX2 ones in the v3 clone, four SSE2 ones otherwise.
PODID_CLONES_V4 void Generate(const ScaleFilter::Generator& f,
                              Eigen::Index begin,
                              Eigen::Index end,
                              double* out) {
  const double c = f.step, c8 = static_cast<double>(kLanes) * c,
               cb = static_cast<double>(kBlock) * c;
  // The far lower tail (entries before f.zeros) is 0; exact starts from there.
  const Eigen::Index zeros = std::clamp(f.zeros, begin, end);
  std::fill(out, out + (zeros - begin), 0.0);
  const Eigen::Index from = std::max(begin, f.zeros);
  for (Eigen::Index e0 = from - (from - f.zeros) % kExact; e0 < end; e0 += kExact) {
    // At the block's first bin b: g_b, rho_b = g_(b+1) / g_b, r_b = g_(b+8) /
    // g_b and block_g = g_(b+128) / g_b; each block's from the last one's.
    const double t0 = c * static_cast<double>(f.first + e0) - f.centre;
    double g0 = f.amplitude * std::exp(-0.5 * t0 * t0);
    double rho0 = std::exp(-c * t0 - 0.5 * c * c);
    double r0 = std::exp(-c8 * t0 - 0.5 * c8 * c8);
    double block_g = std::exp(-cb * t0 - 0.5 * cb * cb);
    const Eigen::Index segment_end = std::min(end, e0 + kExact);
    for (Eigen::Index b0 = e0; b0 < segment_end; b0 += kBlock) {
      if (b0 + kBlock > begin) {
        V8 g, r;
        double g_lane = g0, rho = rho0, r_lane = r0;
        for (Eigen::Index j = 0; j < kLanes; ++j) {
          g[j] = g_lane;
          r[j] = r_lane;
          g_lane *= rho;
          rho *= f.lane_rho;
          r_lane *= f.lane_ratio;
        }
        // The block's entries, the part in [begin, end) kept.
        double block[kBlock];
        const bool whole = b0 >= begin && b0 + kBlock <= end;
        double* to = whole ? out + (b0 - begin) : block;
        const Eigen::Index size = std::min(kBlock, end - b0);
        Eigen::Index i = 0;
        for (; i + kLanes <= size; i += kLanes) {
          std::memcpy(to + i, &g, sizeof g);
          g *= r;
          r *= f.ratio_step;
        }
        for (Eigen::Index j = 0; i < size; ++i, ++j) to[i] = g[j];
        if (!whole) {
          const Eigen::Index from = std::max(begin, b0);
          std::memcpy(out + (from - begin), block + (from - b0),
                      static_cast<std::size_t>(b0 + size - from) * sizeof(double));
        }
      }
      g0 *= block_g;
      block_g *= f.block_g_step;
      rho0 *= f.block_rho_step;
      r0 *= f.block_r_step;
    }
  }
}

}  // namespace

ScaleFilter ScaleFilter::Stored(const double* values) {
  ScaleFilter f;
  f.stored_ = values;
  return f;
}

ScaleFilter ScaleFilter::Gaussian(double amplitude,
                                  double step,
                                  double centre,
                                  Eigen::Index first) {
  PODID_CHECK(step > 0.0 && std::isfinite(step) && std::isfinite(centre));
  ScaleFilter f;
  f.generated_ = true;
  const double c = step, c8 = static_cast<double>(kLanes) * c, cb = static_cast<double>(kBlock) * c;
  // The first entry with t >= -kTail, by the t Generate computes.
  const auto t = [&](Eigen::Index e) { return c * static_cast<double>(first + e) - centre; };
  const double guess = std::ceil((centre - kTail) / c) - static_cast<double>(first);
  Eigen::Index zeros = guess > 0.0 ? static_cast<Eigen::Index>(std::min(guess, 0x1p62)) : 0;
  while (zeros > 0 && t(zeros - 1) >= -kTail) --zeros;
  while (t(zeros) < -kTail) ++zeros;
  f.generator_ = Generator{amplitude,          step, centre, first, zeros,
                           std::exp(-c * c),     // rho_(b+1) / rho_b
                           std::exp(-c8 * c),    // r_(b+1) / r_b
                           std::exp(-c8 * c8),   // r_(b+8) / r_b
                           std::exp(-cb * cb),   // block_g_(b+128) / block_g_b
                           std::exp(-cb * c),    // rho_(b+128) / rho_b
                           std::exp(-cb * c8)};  // r_(b+128) / r_b
  return f;
}

const double* ScaleFilter::Values(Eigen::Index begin, Eigen::Index count, double* scratch) const {
  PODID_CHECK(begin >= 0 && count >= 0 && count <= kChunkBins);
  if (!generated_) return stored_ + begin;
  Generate(generator_, begin, begin + count, scratch);
  return scratch;
}

bool ScaleFilters::Generated(const MorletWavelet& wavelet) {
  return wavelet.family == WaveletFamily::kMorlet && !wavelet.admissibility_correction;
}

double ScaleFilters::Bytes(const MorletWavelet& wavelet, Eigen::Index filter_bins) {
  return Generated(wavelet) ? 0.0 : 8.0 * static_cast<double>(filter_bins);
}

void ScaleFilters::Reset(const MorletWavelet& wavelet, Eigen::Index scales) {
  PODID_CHECK(scales >= 0);
  generated_ = Generated(wavelet);
  wavelet_ = wavelet;
  const auto count = static_cast<std::size_t>(scales);
  first_.assign(count, 0);
  bins_.assign(count, 0);
  stored_.assign(generated_ ? 0 : count, {});
  gaussian_.assign(generated_ ? count : 0, ScaleFilter{});
}

void ScaleFilters::Set(Eigen::Index k,
                       Eigen::Index first,
                       Eigen::Index last,
                       double scale_s,
                       double norm,
                       double bin_rad_per_s) {
  PODID_CHECK(k >= 0 && k < scales());
  const auto at = static_cast<std::size_t>(k);
  first_[at] = first;
  bins_[at] = std::max<Eigen::Index>(0, last - first + 1);
  if (generated_) {
    // psi^(u) = psi^(omega0) exp(-(u - omega0)^2 / 2) without the correction.
    gaussian_[at] = ScaleFilter::Gaussian(norm * wavelet_.FourierTransform(wavelet_.omega0),
                                          scale_s * bin_rad_per_s, wavelet_.omega0, first);
    return;
  }
  auto& filter = stored_[at];
  filter.clear();
  filter.reserve(static_cast<std::size_t>(bins_[at]));
  for (Eigen::Index bin = first; bin <= last; ++bin) {
    filter.push_back(norm * wavelet_.FourierTransform(scale_s * bin * bin_rad_per_s));
  }
}

ScaleFilter ScaleFilters::Filter(Eigen::Index k) const {
  PODID_CHECK(k >= 0 && k < scales());
  const auto at = static_cast<std::size_t>(k);
  return generated_ ? gaussian_[at] : ScaleFilter::Stored(stored_[at].data());
}

}  // namespace podid::wavelet::internal
