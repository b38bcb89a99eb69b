// RidgeFrequencyEstimator (podid/wavelet/ridge.hpp): the main ridge and its
// IF, streamed over blocks of output times (band_transform.hpp), or from the
// whole scalogram with keep_scalogram.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <semaphore>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include "band_transform.hpp"
#include "extent.hpp"
#include "moved_from.hpp"
#include "podid/core/error.hpp"
#include "podid/wavelet/ridge.hpp"
#include "ridge_cost.hpp"
#include "ridge_programme.hpp"
#include "ridge_sample.hpp"
#include "scale_screen.hpp"
#include "signal_check.hpp"

namespace podid::wavelet {
namespace {

using Complex = std::complex<double>;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = std::numbers::pi;
// Bytes of a RidgeTrack per output time (time, index, 4 doubles, 2 flags) and
// the streamed IF's per-time state (refined sample, |W|).
constexpr double kTrackBytesPerTime = 80.0;
// Output cells (times x scales) below which a share of a block's scales is
// not worth a second thread: the reference case's block (313 x 115 = 36k
// cells) took 1.01 ms wall per objective evaluation with it, 0.92 without.
constexpr Eigen::Index kMinThreadedCells = Eigen::Index{1} << 16;
// Times per transposed tile of the ridge cost (64 x 157 frequencies: 80 kB, in L2).
constexpr Eigen::Index kTile = 64;
// Scales transformed at once while screening on two threads (else one at a
// time: ScaleScreen's test is cheap until it can pass).
constexpr std::size_t kScreenBatch = 8;

}  // namespace

struct RidgeFrequencyEstimator::Impl {
  RidgeFrequencyOptions options;
  // keep_scalogram
  std::unique_ptr<CwtTransform> transform;
  // streamed
  std::unique_ptr<internal::BandTransform> band;
  std::unique_ptr<internal::RidgeProgramme> programme;
  Eigen::MatrixXcd kept;      // one block: W of every scale (block times x freqs), unscaled
  // One block, screen_scales and kPenalised: the screen, and which scales
  // `kept` holds (the rest were screened out; Track adds those it reads).
  std::unique_ptr<internal::ScaleScreen> screen;
  std::vector<char> transformed;
  std::vector<int> batch_slot;
  Eigen::Index transformed_count = 0;
  Eigen::MatrixXd cost;       // -log|W| of a block, |W|^2 of the last (block times x freqs)
  Eigen::MatrixXd columns[2];  // a pipeline's blocks of costs (powers: the last), frequency-major
  internal::BandTransform::Scratch scratch;  // the second thread's FFT buffers (Threaded)
  std::vector<int> all_scales;               // k at index k: every scale's slot is its own column
  Eigen::MatrixXd tile;       // kTile times of cost, frequency-major
  Eigen::MatrixXcd cache_w, cache_d;  // pass 2: W (unscaled) and dW/dt at the path's scales
  std::vector<int> slot_w, slot_d;    // scale -> column of cache_w / cache_d, -1: absent
  std::vector<internal::RidgeSample> samples;
  Eigen::VectorXd path_magnitude;  // |W| on the path, coefficient units
  Scalogram scalogram;
  RidgeTrack track;
  double output_scale = 1.0;

  void LayOut(Eigen::Index n, double step_s);
  bool Threaded() const { return options.cwt.threads >= 2; }
  bool Pipelined() const;
  void Streamed(const Eigen::Ref<const Eigen::VectorXd>& signal);
  void BlockCost(Eigen::Index block, Eigen::MatrixXd* into, bool threaded, bool power);
  void ScreenedBlockCost(Eigen::Index count, Eigen::MatrixXd* into, bool threaded);
  void KeepPathScales(const Eigen::VectorXi& path);
  void PushBlock(Eigen::Index count, const Eigen::MatrixXd& from, bool last);
  bool PipelinedPass();
  template <class Store>
  void SynthesiseScales(const std::vector<int>& slot,
                        bool derivative,
                        Eigen::Index count,
                        bool threaded,
                        const Store& store);
  void BlockScales(Eigen::Index first, Eigen::Index count, const Eigen::VectorXi& path);
  void Track(const Eigen::VectorXi& path);
};

void RidgeFrequencyEstimator::Impl::LayOut(Eigen::Index n, double step_s) {
  internal::BandTransform& b = *band;
  const Eigen::Index freqs = b.frequencies_Hz().size();
  const bool maximum = options.ridge.method == RidgeMethod::kMaximum;
  // Checked before anything is allocated: transform buffers, the block's
  // cost and W (kept W for one block, the IF's caches for several), the
  // back-pointers and the track.
  if (b.IsLaidOut(n, step_s, options.block_cells)) return;
  // At the input step: the programme's (decimated) step is longer, its jump
  // costs smaller.
  const Eigen::VectorXd x = b.frequencies_Hz().array().log();  // the programme's and the screen's
  internal::CheckRidgePenalty(options.ridge.penalty_s, step_s, x);
  Eigen::Index times = 0, block_times = 0;
  const double planned = b.PlannedBytes(n, step_s, options.block_cells, &times, &block_times);
  const double block_cells = static_cast<double>(block_times) * static_cast<double>(freqs);
  // Threads: a second set of FFT buffers (32 bytes per inverse point, at
  // most 8/7 of a block's times); a pipeline, two frequency-major blocks of costs.
  const bool threaded = Threaded(), pipeline = threaded && block_times < times;
  const double bytes = planned + 40.0 * block_cells +
                       (threaded ? 40.0 * static_cast<double>(block_times) : 0.0) +
                       (pipeline ? 16.0 * block_cells : 0.0) +
                       internal::RidgeProgramme::Bytes(freqs, times, maximum) +
                       kTrackBytesPerTime * static_cast<double>(times);
  if (bytes > options.cwt.memory_budget_bytes) {
    ThrowInvalid("RidgeFrequency: memory",
                 "at most " + ToText(options.cwt.memory_budget_bytes) +
                     " bytes (CwtOptions::memory_budget_bytes)",
                 ToText(bytes) + " bytes for " + ToText(times) + " output times x " + ToText(freqs) +
                     " frequencies (back-pointers, blocks of " + ToText(block_cells) +
                     " cells, FFT buffers; fewer frequencies or band_limited)");
  }
  b.Layout(n, step_s, options.block_cells);
  Scalogram& sg = scalogram;
  sg.wavelet = options.cwt.wavelet;
  sg.frequencies_Hz = b.frequencies_Hz();
  sg.scales_s = b.scales_s();
  sg.decimation = static_cast<int>(b.decimation());
  sg.step_s = step_s * static_cast<double>(b.decimation());
  sg.input_samples = n;
  sg.time_s = Eigen::VectorXd::LinSpaced(b.times(), 0.0, static_cast<double>(b.times() - 1)) * sg.step_s;
  sg.coefficients.resize(0, 0);
  sg.magnitude.resize(0, 0);
  sg.coefficients_float.resize(0, 0);
  sg.coi_frequency_Hz.resize(b.times());
  for (Eigen::Index j = 0; j < b.times(); ++j) {
    const Eigen::Index sample = j * b.decimation();
    const double edge_s = static_cast<double>(std::min(sample, n - 1 - sample)) * step_s;
    sg.coi_frequency_Hz(j) =
        internal::ConeFrequency_Hz(options.cwt.coi_factor, b.kappa(), b.time_spread(), edge_s);
  }
  programme =
      std::make_unique<internal::RidgeProgramme>(x, options.ridge.penalty_s / sg.step_s, maximum);
  const Eigen::Index block = b.max_block_times();
  cost.resize(block, freqs);
  if (Pipelined()) {
    for (Eigen::MatrixXd& c : columns) c.resize(freqs, block);
  } else {
    for (Eigen::MatrixXd& c : columns) c.resize(0, 0);
  }
  scratch = Threaded() ? b.MakeScratch() : internal::BandTransform::Scratch{};
  all_scales.resize(static_cast<std::size_t>(freqs));
  for (Eigen::Index k = 0; k < freqs; ++k)
    all_scales[static_cast<std::size_t>(k)] = static_cast<int>(k);
  tile.resize(freqs, kTile);
  if (b.blocks() == 1) {
    kept.resize(block, freqs);
  } else {
    kept.resize(0, 0);
  }
  if (b.blocks() == 1 && options.screen_scales && !maximum) {
    screen = std::make_unique<internal::ScaleScreen>(x, options.ridge.penalty_s / sg.step_s);
  } else {
    screen.reset();
  }
  transformed.assign(static_cast<std::size_t>(freqs), 1);
  batch_slot.assign(static_cast<std::size_t>(freqs), -1);
  slot_w.assign(static_cast<std::size_t>(freqs), -1);
  slot_d.assign(static_cast<std::size_t>(freqs), -1);
}

// Several blocks and cwt.threads >= 2: pass 1 runs as a pipeline, the next
// block's transform and costs on a second thread while this one runs the
// dynamic programme (41-47 % of the time on long records, serial by nature).
// One block and threads: its scales are shared by two threads.
bool RidgeFrequencyEstimator::Impl::Pipelined() const { return Threaded() && band->blocks() > 1; }

void RidgeFrequencyEstimator::Impl::Streamed(const Eigen::Ref<const Eigen::VectorXd>& signal) {
  internal::BandTransform& b = *band;
  b.SetSignal(signal);
  const bool unscaled = std::abs(b.exponent()) <= internal::kMaxUnscaledExponent;
  output_scale = unscaled ? std::ldexp(1.0, b.exponent()) : 1.0;
  scalogram.coefficient_scale = unscaled ? 1.0 : std::ldexp(1.0, b.exponent());
  programme->Reset(b.times());
  if (!Pipelined() || !PipelinedPass()) {
    for (Eigen::Index block = 0; block < b.blocks(); ++block) {
      const bool last = block + 1 == b.blocks();
      BlockCost(block, &cost, Threaded(), last);
      PushBlock(b.block_times(block), cost, last);
    }
  }
  Track(programme->Path());
}

// -log|W| (power: |W|^2, for PushLastPowers) of every scale at the block's
// output times into *into's columns, on two threads if `threaded`. Throws
// nothing (PODID_CHECK aborts; every buffer exists): it may run on the
// pipeline's thread.
void RidgeFrequencyEstimator::Impl::BlockCost(Eigen::Index block,
                                              Eigen::MatrixXd* into,
                                              bool threaded,
                                              bool power) {
  internal::BandTransform& b = *band;
  b.LoadBlock(block);
  const Eigen::Index count = b.block_times(block);
  const bool keep = b.blocks() == 1;
  if (keep && power && screen) {
    ScreenedBlockCost(count, into, threaded);
    return;
  }
  transformed_count = static_cast<Eigen::Index>(all_scales.size());
  if (keep) std::fill(transformed.begin(), transformed.end(), 1);
  SynthesiseScales(all_scales, false, count, threaded, [&](int k, const Complex* w) {
    if (power) {
      internal::RidgePower(w, count, 1.0, into->col(k).data());
    } else {
      internal::RidgeCost(w, count, 1.0, into->col(k).data());
    }
    // Unscaled: Track multiplies by output_scale (a power of 2, exact).
    if (keep) std::copy(w, w + count, kept.col(k).data());
  });
}

// BlockCost's one block with screen_scales: the scales in order of their
// |W| bound, in batches, until ScaleScreen shows the rest off the optimal
// path; those get their bound as a stand-in power (no transform, nothing in
// `kept`). Throws nothing.
void RidgeFrequencyEstimator::Impl::ScreenedBlockCost(Eigen::Index count,
                                                      Eigen::MatrixXd* into,
                                                      bool threaded) {
  internal::BandTransform& b = *band;
  b.MagnitudeBounds(screen->bounds());
  screen->Start(count);
  const std::vector<int>& order = screen->order();
  std::fill(transformed.begin(), transformed.end(), 0);
  // Batches only where SynthesiseScales shares them with a second thread.
  const bool shared =
      threaded && static_cast<Eigen::Index>(kScreenBatch) * count >= kMinThreadedCells;
  const std::size_t batch = shared ? kScreenBatch : 1;
  std::size_t next = 0;
  while (next < order.size()) {
    const std::size_t end = std::min(order.size(), next + batch);
    const auto store = [&](int k, const Complex* w) {
      internal::RidgePower(w, count, 1.0, into->col(k).data());
      std::copy(w, w + count, kept.col(k).data());
    };
    if (batch == 1) {
      store(order[next], b.Synthesise(order[next], false));
    } else {
      std::fill(batch_slot.begin(), batch_slot.end(), -1);
      for (std::size_t o = next; o < end; ++o)
        batch_slot[static_cast<std::size_t>(order[o])] = order[o];
      SynthesiseScales(batch_slot, false, count, threaded, store);
    }
    for (std::size_t o = next; o < end; ++o) {
      screen->Add(order[o], into->col(order[o]).data());
      transformed[static_cast<std::size_t>(order[o])] = 1;
    }
    next = end;
    if (screen->RestExcluded(next)) break;
  }
  transformed_count = static_cast<Eigen::Index>(next);
  for (std::size_t o = next; o < order.size(); ++o) {
    into->col(order[o]).head(count).setConstant(screen->StandIn(order[o]));
  }
}

// One block: W of the scales Track reads (the path's and either side) that
// screening left out of `kept`.
void RidgeFrequencyEstimator::Impl::KeepPathScales(const Eigen::VectorXi& path) {
  const int freqs = static_cast<int>(transformed.size());
  std::fill(batch_slot.begin(), batch_slot.end(), -1);
  bool missing = false;
  for (Eigen::Index j = 0; j < path.size(); ++j) {
    const int k = path(j);
    if (k < 0) continue;
    for (int c = std::max(0, k - 1); c <= std::min(freqs - 1, k + 1); ++c) {
      if (transformed[static_cast<std::size_t>(c)] != 0) continue;
      transformed[static_cast<std::size_t>(c)] = 1;
      batch_slot[static_cast<std::size_t>(c)] = c;
      missing = true;
    }
  }
  if (!missing) return;
  const Eigen::Index count = band->block_times(0);
  SynthesiseScales(batch_slot, false, count, Threaded(),
                   [&](int k, const Complex* w) { std::copy(w, w + count, kept.col(k).data()); });
}

// The programme reads a time column: transpose tiles of kTile times into
// frequency-major order (a strided read of a large block would miss the
// cache at every frequency). The last block (powers) goes to PushLastPowers
// whole, which reads a few cells a column (strided). Throws nothing.
void RidgeFrequencyEstimator::Impl::PushBlock(Eigen::Index count,
                                              const Eigen::MatrixXd& from,
                                              bool last) {
  const Eigen::Index freqs = from.cols();
  if (last) {
    programme->PushLastPowers(from.data(), count, from.rows(), 1);
    return;
  }
  for (Eigen::Index i0 = 0; i0 < count; i0 += kTile) {
    const Eigen::Index tile_times = std::min(kTile, count - i0);
    tile.leftCols(tile_times) = from.block(i0, 0, tile_times, freqs).transpose();
    for (Eigen::Index i = 0; i < tile_times; ++i) programme->Push(tile.col(i).data());
  }
}

// Pass 1 as a two-stage pipeline over two frequency-major cost buffers: the
// second thread computes a block's costs and transposes them (by tiles, as
// PushBlock), so this thread, the critical path, only runs the programme.
// The same columns are pushed in the same order: the same path bit for bit.
// False (nothing done) when no thread can be started.
bool RidgeFrequencyEstimator::Impl::PipelinedPass() {
  const Eigen::Index blocks = band->blocks();
  std::counting_semaphore<2> free_slots(2), filled(0);
  std::thread producer;
  try {
    producer = std::thread([&]() noexcept {
      for (Eigen::Index block = 0; block < blocks; ++block) {
        free_slots.acquire();
        BlockCost(block, &cost, false, block + 1 == blocks);
        const Eigen::Index count = band->block_times(block), freqs = cost.cols();
        Eigen::MatrixXd& to = columns[block % 2];
        for (Eigen::Index i0 = 0; i0 < count; i0 += kTile) {
          const Eigen::Index tile_times = std::min(kTile, count - i0);
          to.middleCols(i0, tile_times) = cost.block(i0, 0, tile_times, freqs).transpose();
        }
        filled.release();
      }
    });
  } catch (const std::system_error&) {
    return false;
  }
  for (Eigen::Index block = 0; block < blocks; ++block) {
    filled.acquire();
    const Eigen::MatrixXd& from = columns[block % 2];
    if (block + 1 == blocks) {
      programme->PushLastPowers(from.data(), band->block_times(block), 1, from.rows());
    } else {
      for (Eigen::Index i = 0; i < band->block_times(block); ++i)
        programme->Push(from.col(i).data());
    }
    free_slots.release();
  }
  producer.join();
  return true;
}

// Pass 2, block `first`..: W at k - 1, k, k + 1 and dW/dt at k and the
// vertex's neighbour, for the path's k in the block (several blocks only).
void RidgeFrequencyEstimator::Impl::BlockScales(Eigen::Index first, Eigen::Index count,
                                                const Eigen::VectorXi& path) {
  internal::BandTransform& b = *band;
  const int freqs = static_cast<int>(b.frequencies_Hz().size());
  std::fill(slot_w.begin(), slot_w.end(), -1);
  int used = 0;
  for (Eigen::Index i = 0; i < count; ++i) {
    const int k = path(first + i);
    if (k < 0) continue;
    for (int c = std::max(0, k - 1); c <= std::min(freqs - 1, k + 1); ++c) {
      if (slot_w[static_cast<std::size_t>(c)] < 0) slot_w[static_cast<std::size_t>(c)] = used++;
    }
  }
  cache_w.resize(count, used);
  SynthesiseScales(slot_w, false, count, Threaded(), [&](int u, const Complex* w) {
    std::copy(w, w + count, cache_w.col(u).data());
  });
}

// store(slot[k], W or dW/dt of scale k) for every scale k with slot[k] >= 0
// (`count` output times each), the scales shared with a second thread if
// `threaded` and the work is large enough (each thread its own FFT buffers;
// store writes the slot's own column, and throws nothing).
template <class Store>
void RidgeFrequencyEstimator::Impl::SynthesiseScales(const std::vector<int>& slot,
                                                     bool derivative,
                                                     Eigen::Index count,
                                                     bool threaded,
                                                     const Store& store) {
  const internal::BandTransform& b = *band;
  const std::size_t scales = slot.size();
  const auto selected = static_cast<std::size_t>(
      std::count_if(slot.begin(), slot.end(), [](int u) { return u >= 0; }));
  std::size_t cut = scales;  // this thread takes the scales below it, the other the rest
  std::thread other;
  if (threaded && selected >= 2 &&
      static_cast<Eigen::Index>(selected) * count >= kMinThreadedCells) {
    cut = 0;
    for (std::size_t seen = 0; seen < selected / 2; ++cut) seen += slot[cut] >= 0 ? 1 : 0;
    try {
      other = std::thread([&, cut]() noexcept {
        for (std::size_t k = cut; k < scales; ++k) {
          if (slot[k] >= 0)
            store(slot[k], b.Synthesise(static_cast<Eigen::Index>(k), derivative, &scratch));
        }
      });
    } catch (const std::system_error&) {  // no thread: all here
      cut = scales;
    }
  }
  for (std::size_t k = 0; k < cut; ++k) {
    if (slot[k] >= 0) store(slot[k], b.Synthesise(static_cast<Eigen::Index>(k), derivative));
  }
  if (other.joinable()) other.join();
}

void RidgeFrequencyEstimator::Impl::Track(const Eigen::VectorXi& path) {
  internal::BandTransform& b = *band;
  const Scalogram& sg = scalogram;
  const RidgeOptions& ro = options.ridge;
  const Eigen::Index times = b.times();
  const int freqs = static_cast<int>(b.frequencies_Hz().size());
  const Eigen::VectorXd& s = b.scales_s();
  const double kappa = sg.wavelet.RidgeAngularFrequency();
  RidgeTrack& t = track;
  t.time_s = sg.time_s;
  t.frequency_index = path;
  t.frequency_Hz.setConstant(times, kNaN);
  t.grid_frequency_Hz.setConstant(times, kNaN);
  t.amplitude.setConstant(times, kNaN);
  t.inside_coi.setConstant(times, false);
  t.screened.setConstant(times, false);
  path_magnitude.setZero(times);
  samples.resize(static_cast<std::size_t>(times));
  if (b.blocks() == 1) KeepPathScales(path);
  const bool phase = ro.estimator == FrequencyEstimator::kPhase;
  for (Eigen::Index block = 0; block < b.blocks(); ++block) {
    const Eigen::Index first = b.block_first(block), count = b.block_times(block);
    if (b.blocks() > 1) {
      b.LoadBlock(block);
      BlockScales(first, count, path);
    }
    const Eigen::MatrixXcd& w = b.blocks() > 1 ? cache_w : kept;
    const auto at = [&](Eigen::Index i, int k) -> Complex {
      return (b.blocks() > 1 ? w(i, slot_w[static_cast<std::size_t>(k)]) : w(i, k)) * output_scale;
    };
    // Refined samples, and the scales whose dW/dt the phase IF needs.
    std::fill(slot_d.begin(), slot_d.end(), -1);
    int used = 0;
    for (Eigen::Index i = 0; i < count; ++i) {
      const Eigen::Index j = first + i;
      const int k = path(j);
      if (k < 0) continue;
      t.inside_coi(j) = sg.InsideCoi(j, k);
      t.grid_frequency_Hz(j) = sg.frequencies_Hz(k);
      const internal::RidgeSample& r = samples[static_cast<std::size_t>(j)] =
          internal::RefineRidgeSample(sg.wavelet, s, k, at(i, k > 0 ? k - 1 : k), at(i, k),
                                      at(i, k + 1 < freqs ? k + 1 : k), sg.coefficient_scale,
                                      ro.parabolic_refinement);
      t.amplitude(j) = r.amplitude;
      path_magnitude(j) = std::abs(at(i, k));
      if (!phase) {
        t.frequency_Hz(j) = ro.parabolic_refinement ? kappa / (2.0 * kPi * r.vertex_s) : sg.frequencies_Hz(k);
        continue;
      }
      for (int c : {k, r.neighbour}) {
        if (slot_d[static_cast<std::size_t>(c)] < 0) slot_d[static_cast<std::size_t>(c)] = used++;
      }
    }
    if (!phase) continue;
    cache_d.resize(count, used);
    SynthesiseScales(slot_d, true, count, Threaded(), [&](int u, const Complex* w) {
      cache_d.col(u) = Eigen::Map<const Eigen::VectorXcd>(w, count) * output_scale;
    });
    for (Eigen::Index i = 0; i < count; ++i) {
      const Eigen::Index j = first + i;
      const int k = path(j);
      if (k < 0) continue;
      const internal::RidgeSample& r = samples[static_cast<std::size_t>(j)];
      const double fk = internal::PhaseFrequency_Hz(at(i, k), cache_d(i, slot_d[static_cast<std::size_t>(k)]));
      if (r.neighbour == k) {
        t.frequency_Hz(j) = fk;
      } else {
        const int n = r.neighbour;
        const double fn = internal::PhaseFrequency_Hz(at(i, n), cache_d(i, slot_d[static_cast<std::size_t>(n)]));
        t.frequency_Hz(j) = fk + (fn - fk) * (r.vertex_s - s(k)) / (s(n) - s(k));
      }
    }
  }
  // Screening (TrackRidge): |W| on the path at most min_relative_magnitude of its peak.
  const double peak = path_magnitude.maxCoeff();
  for (Eigen::Index j = 0; j < times; ++j) {
    if (path(j) >= 0 && path_magnitude(j) <= ro.min_relative_magnitude * peak) {
      t.screened(j) = true;
      t.inside_coi(j) = false;
      t.frequency_Hz(j) = kNaN;
    }
  }
  internal::CheckTrackFinite(t, "RidgeFrequencyEstimator");
}

RidgeFrequencyEstimator::RidgeFrequencyEstimator(const RidgeFrequencyOptions& options)
    : impl_(std::make_unique<Impl>()) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument(why);
  impl_->options = options;
  impl_->options.ridge.ridges = 1;
  if (options.keep_scalogram) {
    impl_->transform = std::make_unique<CwtTransform>(options.cwt);
  } else {
    impl_->band = std::make_unique<internal::BandTransform>(options.cwt);
  }
}

RidgeFrequencyEstimator::~RidgeFrequencyEstimator() = default;
RidgeFrequencyEstimator::RidgeFrequencyEstimator(RidgeFrequencyEstimator&&) noexcept = default;
RidgeFrequencyEstimator& RidgeFrequencyEstimator::operator=(RidgeFrequencyEstimator&&) noexcept = default;

namespace {
constexpr const char* kOwner = "RidgeFrequencyEstimator";
}  // namespace

const Scalogram& RidgeFrequencyEstimator::scalogram() const {
  return internal::CheckedImpl(impl_, kOwner).scalogram;
}

Eigen::Index RidgeFrequencyEstimator::blocks() const {
  const Impl& s = internal::CheckedImpl(impl_, kOwner);
  return s.band ? s.band->blocks() : 0;
}

Eigen::Index RidgeFrequencyEstimator::transformed_scales() const {
  const Impl& s = internal::CheckedImpl(impl_, kOwner);
  return s.band ? s.transformed_count : 0;
}

const RidgeTrack& RidgeFrequencyEstimator::Estimate(const Eigen::Ref<const Eigen::VectorXd>& signal,
                                                    double step_s) {
  Impl& s = internal::CheckedImpl(impl_, kOwner);
  if (s.transform) {
    s.transform->Compute(signal, step_s, &s.scalogram);
    const std::vector<Eigen::VectorXi> paths = FindRidges(s.scalogram, s.options.ridge);
    s.track = TrackRidge(s.scalogram, paths.front(), s.options.ridge, s.transform.get());
    return s.track;
  }
  internal::CheckSignal(signal, step_s, s.options.cwt.frequencies);
  s.LayOut(signal.size(), step_s);
  s.Streamed(signal);
  return s.track;
}

}  // namespace podid::wavelet
