#include "full_rate.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <system_error>
#include <thread>

#include "podid/core/error.hpp"

namespace podid::wavelet::internal {

double FullRateCwt::Bytes(Eigen::Index p, int threads, const BlockedScales::Grouping& blocked) {
  const auto work = static_cast<double>(PrunedInverse::WorkSize(p));
  return 16.0 * (static_cast<double>(p) + (work + static_cast<double>(p)) * threads) +
         BlockedScales::Bytes(blocked);
}

void FullRateCwt::Layout(Eigen::Index p,
                         const ScaleFilters& filters,
                         BlockedScales::Grouping blocked,
                         const std::function<void(Eigen::Index, ScaleFilters*)>& make_filters,
                         int threads,
                         bool measure) {
  PODID_CHECK(threads >= 1);
  inverse_.Reset(p, measure);
  blocked_.Layout(p, std::move(blocked), make_filters, measure);
  filters_ = &filters;
  const auto scales = static_cast<std::size_t>(filters.scales());
  decimation_.resize(scales);
  batch_.resize(scales);
  plans_.resize(scales);
  std::vector<double> cost(scales);
  // The D = 1 scales split (kSplitLength) when their plan allows, decided
  // once: whether there are such scales, then the plan.
  split_ = nullptr;
  if (MaySplit(p)) {
    for (std::size_t k = 0; k < scales; ++k) {
      const Eigen::Index bins = filters.bins(static_cast<Eigen::Index>(k));
      if (bins > 0 && !blocked_.Blocked(static_cast<Eigen::Index>(k)) &&
          PrunedInverse::Decimation(p, bins) == 1) {
        bool measured = false;
        fftw_plan plan = inverse_.SplitPlan(&measured);
        split_ = measured || kSplitEstimated ? plan : nullptr;
        break;
      }
    }
  }
  for (std::size_t k = 0; k < scales; ++k) {
    const Eigen::Index bins = filters.bins(static_cast<Eigen::Index>(k));
    const Eigen::Index d = PrunedInverse::Decimation(p, std::max<Eigen::Index>(bins, 1));
    decimation_[k] = d;
    batch_[k] = PrunedInverse::Batch(p, d);
    // A blocked scale needs no pruned plan (nor its measuring), nor does a
    // D = 1 scale that splits or, from kInPlaceLength on, runs on in_place_.
    plans_[k] = blocked_.Blocked(static_cast<Eigen::Index>(k)) ||
                        (d == 1 && (split_ != nullptr || p >= kInPlaceLength))
                    ? nullptr
                    : inverse_.Plan(d, batch_[k]);
    // FFT flops plus the twiddle pass, in units of complex products.
    cost[k] = blocked_.Blocked(static_cast<Eigen::Index>(k))
                  ? blocked_.Cost(static_cast<Eigen::Index>(k))
                  : static_cast<double>(p) * std::log2(static_cast<double>(p / d) + 1.0) +
                        static_cast<double>(d * bins);
  }
  // Contiguous chunks of about equal cost (a thread writes a chunk's columns
  // in order, so a column may spill into the next ones of the same chunk).
  // With several threads, kChunksPerThread chunks each, taken in turn from a
  // counter: a thread slowed down (a busy core, an expensive scale) takes
  // fewer chunks instead of making the others wait.
  const std::size_t chunks =
      threads == 1 ? 1 : std::min(scales, static_cast<std::size_t>(threads) * kChunksPerThread);
  chunk_begin_.assign(chunks + 1, static_cast<Eigen::Index>(scales));
  chunk_begin_[0] = 0;
  double total = 0.0;
  for (double c : cost) total += c;
  double sum = 0.0;
  std::size_t next = 1;
  for (std::size_t k = 0; k < scales && next < chunks; ++k) {
    sum += cost[k];
    while (next < chunks && sum >= total * static_cast<double>(next) / static_cast<double>(chunks)) {
      chunk_begin_[next++] = static_cast<Eigen::Index>(k) + 1;
    }
  }
  threads_ = threads;
  in_place_ = p >= kInPlaceLength && split_ == nullptr
                  ? ComplexBackwardPlan(static_cast<int>(p), measure)
                  : nullptr;
  input_.clear();
  output_.clear();
  for (int t = 0; t < threads; ++t) {
    input_.push_back(AllocateComplex(static_cast<std::size_t>(PrunedInverse::WorkSize(p))));
    output_.push_back(AllocateComplex(static_cast<std::size_t>(p)));
  }
  plan_alignment_ = fftw_alignment_of(reinterpret_cast<double*>(output_.front().get()));
}

void FullRateCwt::Compute(const Complex* spectrum,
                          const double* padded,
                          Eigen::Index times,
                          double output_scale,
                          const FullRateOutput& output) const {
  PODID_CHECK(times >= 1 && times <= inverse_.length());
  PODID_CHECK((output.complex != nullptr) + (output.complex_float != nullptr) +
                  (output.magnitude != nullptr) ==
              1);
  const auto chunks = static_cast<int>(chunk_begin_.size()) - 1;
  const Eigen::Index blocks = blocked_.blocks();
  std::atomic<Eigen::Index> next_block{0}, loaded{0};
  std::atomic<int> next_chunk{0};
  const auto work = [&](int thread) {
    // The blocked scales' block spectra first, shared out like the chunks
    // (1.3 ms of one thread's 89 at 10^5 in fCWT's case), then every thread
    // waits for the last one: about one block's forward FFT.
    Complex* segment = input_[static_cast<std::size_t>(thread)].get();
    for (Eigen::Index b = next_block++; b < blocks; b = next_block++) {
      blocked_.LoadBlock(b, padded, segment);
      loaded.fetch_add(1, std::memory_order_release);
    }
    while (loaded.load(std::memory_order_acquire) < blocks) std::this_thread::yield();
    for (int c = next_chunk++; c < chunks; c = next_chunk++) {
      RunScales(thread, c, spectrum, times, output_scale, output);
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::min(threads_, chunks); ++t) {
    try {
      pool.emplace_back(work, t);
    } catch (const std::system_error&) {
      break;  // no more threads: the running ones take the remaining chunks
    }
  }
  work(0);
  for (auto& thread : pool) thread.join();
}

// A blocked scale's scratch, and a block's segment, is the thread's input_ buffer.
static_assert(PrunedInverse::WorkSize(BlockedScales::kMinPaddedLength) >= BlockedScales::kWorkSize);
static_assert(BlockedScales::kWorkSize >= BlockedScales::kMaxLength);

// Nothing here throws: PODID_CHECK aborts, and the buffers exist already.
void FullRateCwt::RunScales(int thread,
                            int chunk,
                            const Complex* spectrum,
                            Eigen::Index times,
                            double output_scale,
                            const FullRateOutput& output) const {
  const auto t = static_cast<std::size_t>(thread);
  const Eigen::Index p = inverse_.length();
  const auto c = static_cast<std::size_t>(chunk);
  const Eigen::Index end = chunk_begin_[c + 1];
  Complex* input = input_[t].get();
  Complex* own_output = output_[t].get();
  for (Eigen::Index k = chunk_begin_[c]; k < end; ++k) {
    const Eigen::Index a = filters_->first(k);
    const Eigen::Index bins = filters_->bins(k);
    Complex* column = output.complex == nullptr ? nullptr : output.complex + k * times;
    if (bins == 0) {  // the whole band beyond Nyquist: W = 0
      if (output.magnitude != nullptr) {
        std::fill_n(output.magnitude + k * times, times, 0.0f);
      } else if (output.complex_float != nullptr) {
        std::fill_n(output.complex_float + k * times, times, std::complex<float>(0.0f, 0.0f));
      } else {
        std::fill_n(column, times, Complex(0.0, 0.0));
      }
      continue;
    }
    if (blocked_.Blocked(k)) {  // input_ holds 1.5 P >= BlockedScales::kWorkSize entries
      blocked_.Run(k, times, output_scale, input, output);
      continue;
    }
    const Eigen::Index d = decimation_[static_cast<std::size_t>(k)];
    const ScaleFilter filter = filters_->Filter(k);
    if (d == 1 && split_ != nullptr) {  // the radix-8 pass writes `times` outputs: any column
      inverse_.ExecuteSplit(spectrum, filter, a, bins, split_, input);
      if (column != nullptr) {
        inverse_.CombineSplit(input, times, output_scale, column);
        continue;
      }
      inverse_.CombineSplit(input, times, 1.0, own_output);
      if (output.magnitude != nullptr) {
        inverse_.GatherMagnitude(own_output, 1, 0, times, output_scale,
                                 reinterpret_cast<float*>(input), output.magnitude + k * times);
      } else {
        inverse_.GatherFloat(own_output, 1, 0, times, output_scale,
                             output.complex_float + k * times);
      }
      continue;
    }
    // At D = 1 the column itself takes all P outputs when P values from its
    // start stay inside this chunk's later columns (overwritten when their
    // turn comes): no copy.
    const bool direct = d == 1 && column != nullptr && (end - k) * times >= p &&
                        fftw_alignment_of(reinterpret_cast<double*>(column)) == plan_alignment_;
    Complex* out = direct ? column : own_output;
    if (d == 1 && in_place_ != nullptr) {  // in place: in the column or the thread's buffer
      inverse_.Execute(spectrum, filter, a, bins, 1, 1, in_place_, out, out);
    } else {
      inverse_.Execute(spectrum, filter, a, bins, d, batch_[static_cast<std::size_t>(k)],
                       plans_[static_cast<std::size_t>(k)], input, out);
    }
    if (output.magnitude != nullptr) {
      // Execute's work is free again: it serves as scratch for P floats.
      inverse_.GatherMagnitude(out, d, 0, times, output_scale, reinterpret_cast<float*>(input),
                               output.magnitude + k * times);
    } else if (output.complex_float != nullptr) {
      inverse_.GatherFloat(out, d, 0, times, output_scale, output.complex_float + k * times);
    } else if (!direct) {
      inverse_.Gather(out, d, 0, times, output_scale, column);
    } else if (output_scale != 1.0) {
      for (Eigen::Index j = 0; j < times; ++j) column[j] *= output_scale;
    }
  }
  // The chunk's streamed columns before the join hands them to the caller.
  PrunedInverse::FenceStreams();
}

}  // namespace podid::wavelet::internal
