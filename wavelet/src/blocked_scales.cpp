#include "blocked_scales.hpp"

#include <algorithm>
#include <cmath>

#include "podid/core/error.hpp"

namespace podid::wavelet::internal {
namespace {

// The pruned inverse's passes beyond its FFTs, per output and in units of
// a radix-2 pass (FftCostModel's): the twiddled band fill, the gather out
// of its blocks (P values beyond the L2 cache, read back) and the column's
// write.
constexpr double kPrunedPasses = 2.0;
// A block's band twiddled for each of its D' inverses (D' products a bin,
// D' x bins <= L), in radix-2 passes: 1.5 leaves D' = 2 out, which FFTW
// made no faster at 2048 points (1.39 against 1.29 ns a point).
constexpr double kTwiddlePasses = 1.5;

}  // namespace

BlockedScales::Grouping BlockedScales::Plan(Eigen::Index p,
                                            Eigen::Index times,
                                            const std::vector<Scale>& scales) {
  PODID_CHECK(p >= 1 && times >= 1 && times <= p);
  Grouping out;
  out.group.assign(scales.size(), -1);
  if (p < kMinPaddedLength) return out;
  for (Eigen::Index d = 1; d <= PrunedInverse::kMaxDecimation; d *= 2) {
    double radius = 0.0;
    bool any = false;
    for (const Scale& s : scales) {
      if (s.inside && s.decimation == d) {
        any = true;
        radius = std::max(radius, s.support);
      }
    }
    if (!any || !(radius < static_cast<double>(kMaxLength) / 4.0)) continue;
    const auto h = static_cast<Eigen::Index>(std::ceil(radius));
    // The cheapest length per kept sample that throws away at most half.
    Group group{.decimation = d};
    double best = 0.0;
    for (Eigen::Index length : kLengths) {
      if (4 * h > length) continue;
      for (Eigen::Index inner = 1; inner <= d; inner *= 2) {
        const double cost = (FftCostModel(length / inner) + (inner > 1 ? kTwiddlePasses : 0.0)) *
                            static_cast<double>(length) / static_cast<double>(length - 2 * h);
        if (group.length == 0 || cost < best) {
          best = cost;
          group.length = length;
          group.inner = inner;
        }
      }
    }
    if (group.length == 0 || best > FftCostModel(p / d) + kPrunedPasses) continue;
    group.overlap = h;
    group.hop = group.length - 2 * h;
    group.blocks = (times + group.hop - 1) / group.hop;
    const auto index = static_cast<int>(out.groups.size());
    out.groups.push_back(group);
    for (std::size_t k = 0; k < scales.size(); ++k) {
      if (scales[k].inside && scales[k].decimation == d) out.group[k] = index;
    }
  }
  return out;
}

Eigen::Index BlockedScales::InnerDecimation(const Group& group,
                                            Eigen::Index first,
                                            Eigen::Index bins) {
  const Eigen::Index l = group.length;
  if (bins < 1 || first < -((l - 1) / 2) || first + bins - 1 > l / 2) return 1;
  return std::min(group.inner, PrunedInverse::Decimation(l, bins));
}

double BlockedScales::Bytes(const Grouping& grouping) {
  if (grouping.groups.empty()) return 0.0;
  double points = 0.0;
  std::vector<Eigen::Index> lengths;
  for (const Group& g : grouping.groups) {
    points += static_cast<double>(g.blocks) * static_cast<double>(g.bins);
    if (std::find(lengths.begin(), lengths.end(), g.length) == lengths.end()) {
      lengths.push_back(g.length);
      points += static_cast<double>(g.length);  // twiddle table
    }
  }
  return 16.0 * points;
}

void BlockedScales::Layout(Eigen::Index p,
                           Grouping grouping,
                           const std::function<void(Eigen::Index, ScaleFilters*)>& make_filters,
                           bool measure) {
  p_ = p;
  grouping_ = std::move(grouping);
  grids_.clear();
  spectra_.clear();
  std::vector<Eigen::Index> lengths;
  for (const Group& g : grouping_.groups) {
    if (std::find(lengths.begin(), lengths.end(), g.length) == lengths.end()) {
      lengths.push_back(g.length);
    }
    PODID_CHECK(g.bins >= 1 && g.bins <= g.length / 2 + 1);
    spectra_.push_back(AllocateComplex(static_cast<std::size_t>(g.blocks * g.bins)));
  }
  grids_.resize(lengths.size());
  for (std::size_t i = 0; i < lengths.size(); ++i) {
    Grid& grid = grids_[i];
    grid.length = lengths[i];
    grid.inverse.Reset(grid.length, measure);
    make_filters(grid.length, &grid.filters);
    grid.forward = ComplexForwardPlan(static_cast<int>(grid.length), measure);
  }
  // Every blocked band within its group's kept bins (the fill reads no
  // other), and each scale's D' with its plan.
  inner_.assign(grouping_.group.size(), 1);
  plans_.assign(grouping_.group.size(), nullptr);
  for (std::size_t k = 0; k < grouping_.group.size(); ++k) {
    if (grouping_.group[k] < 0) continue;
    const Group& g = grouping_.groups[static_cast<std::size_t>(grouping_.group[k])];
    const Grid& grid = GridOf(g.length);
    const auto scale = static_cast<Eigen::Index>(k);
    const Eigen::Index first = grid.filters.first(scale), bins = grid.filters.bins(scale);
    PODID_CHECK(first > -g.bins && first + bins - 1 < g.bins);
    inner_[k] = InnerDecimation(g, first, bins);
    // D' = 1: the out-of-place inverse of L (the same plan as
    // PrunedInverse::Plan(1, 1), preserving its input).
    plans_[k] = grid.inverse.Plan(inner_[k], PrunedInverse::Batch(g.length, inner_[k]));
  }
}

const BlockedScales::Grid& BlockedScales::GridOf(Eigen::Index length) const {
  for (const Grid& grid : grids_) {
    if (grid.length == length) return grid;
  }
  PODID_CHECK(false);
  return grids_.front();
}

double BlockedScales::Cost(Eigen::Index k) const {
  const Group& g =
      grouping_.groups[static_cast<std::size_t>(grouping_.group[static_cast<std::size_t>(k)])];
  const auto length = static_cast<double>(g.length);
  const auto inner = static_cast<double>(inner_[static_cast<std::size_t>(k)]);
  return static_cast<double>(g.blocks) * length *
         (std::log2(length / inner) + 1.0 + (inner > 1.0 ? kTwiddlePasses : 0.0));
}

Eigen::Index BlockedScales::blocks() const {
  Eigen::Index total = 0;
  for (const Group& group : grouping_.groups) total += group.blocks;
  return total;
}

void BlockedScales::LoadBlock(Eigen::Index index, const double* padded, Complex* segment) const {
  std::size_t g = 0;
  while (index >= grouping_.groups[g].blocks) index -= grouping_.groups[g++].blocks;
  const Group& group = grouping_.groups[g];
  const Grid& grid = GridOf(group.length);
  // Samples index hop - H .. of the padded sequence, periodic with period P.
  Eigen::Index i = ((index * group.hop - group.overlap) % p_ + p_) % p_;
  for (Eigen::Index t = 0; t < group.length; ++t) {
    segment[t] = Complex(padded[i], 0.0);
    if (++i == p_) i = 0;
  }
  fftw_execute_dft(grid.forward, AsFftw(segment), AsFftw(segment));
  std::copy_n(segment, group.bins, spectra_[g].get() + index * group.bins);
}

void BlockedScales::Run(Eigen::Index k,
                        Eigen::Index times,
                        double output_scale,
                        Complex* work,
                        const FullRateOutput& output) const {
  const auto g = static_cast<std::size_t>(grouping_.group[static_cast<std::size_t>(k)]);
  const Group& group = grouping_.groups[g];
  const Grid& grid = GridOf(group.length);
  const Eigen::Index a = grid.filters.first(k);
  const Eigen::Index bins = grid.filters.bins(k);
  const Eigen::Index inner = inner_[static_cast<std::size_t>(k)];
  const Eigen::Index batch = PrunedInverse::Batch(group.length, inner);  // Layout's plan
  // Execute's work, its output (a block's L outputs, as D' blocks of L / D')
  // and the filter's values.
  Complex* band = work;
  Complex* inverse = work + PrunedInverse::WorkSize(group.length);
  auto* values = reinterpret_cast<double*>(inverse + group.length);  // bins <= L + 1
  PODID_CHECK(bins <= group.length + 1);
  // A generated filter once for all blocks, not once a block (the same
  // values however a band is cut into calls: scale_filters.hpp).
  ScaleFilter filter = grid.filters.Filter(k);
  if (filter.generated()) {
    for (Eigen::Index i = 0; i < bins; i += ScaleFilter::kChunkBins) {
      filter.Values(i, std::min(ScaleFilter::kChunkBins, bins - i), values + i);
    }
    filter = ScaleFilter::Stored(values);
  }
  // At D' = 1 the band's slots are rewritten block by block; the
  // out-of-place inverse preserves its input, so the others stay zero from
  // this one clearing.
  if (inner == 1) std::fill_n(band, group.length, Complex(0.0, 0.0));
  for (Eigen::Index j = 0; j < group.blocks; ++j) {
    const Eigen::Index first = j * group.hop;
    const Eigen::Index n = std::min(group.hop, times - first);
    if (n <= 0) break;
    const Complex* spectrum = spectra_[g].get() + j * group.bins;
    if (inner == 1) {
      PrunedInverse::FillSlots(spectrum, filter, a, bins, group.length, band);
      fftw_execute_dft(plans_[static_cast<std::size_t>(k)], AsFftw(band), AsFftw(inverse));
    } else {
      grid.inverse.Execute(spectrum, filter, a, bins, inner, batch,
                           plans_[static_cast<std::size_t>(k)], band, inverse);
    }
    // Outputs H .. H + n - 1 of the block: no wrap reaches them.
    if (output.magnitude != nullptr) {
      // Execute's work is free again: scratch for L floats (D' = 1 reads none).
      grid.inverse.GatherMagnitude(inverse, inner, group.overlap, n, output_scale,
                                   reinterpret_cast<float*>(band),
                                   output.magnitude + k * times + first);
    } else if (output.complex_float != nullptr) {
      grid.inverse.GatherFloat(inverse, inner, group.overlap, n, output_scale,
                               output.complex_float + k * times + first);
    } else {
      grid.inverse.Gather(inverse, inner, group.overlap, n, output_scale,
                          output.complex + k * times + first);
    }
  }
}

}  // namespace podid::wavelet::internal
