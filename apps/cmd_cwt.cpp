// podid cwt: Morlet or Morse wavelet transform of one channel (or one POD time mode),
// its ridge, and the instantaneous frequency along it (docs/wavelet.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cli_common.hpp"
#include "commands.hpp"
#include "data_arguments.hpp"
#include "plot.hpp"
#include "podid/core/error.hpp"
#include "podid/core/io.hpp"
#include "podid/pod/pod.hpp"
#include "podid/wavelet/cwt.hpp"
#include "podid/wavelet/ridge.hpp"
#include "podid/wavelet/synthesis.hpp"
#include "wavelet_arguments.hpp"

namespace podid::cli {
namespace {

struct CwtArguments {
  std::string data;
  DataArguments reading;  // --variable, --channels, --rate, --step (docs/data-files.md)
  std::string channel;
  int pom = 0;
  GridArguments grid;  // --fmin, --fmax, --voices, --bins
  std::string ridge = "penalised";
  std::string if_from = "phase";
  int ridges = 1;
  double penalty_s = 0.05;
  // --wavelet, --omega0, --gamma, --beta, --normalisation, --scale-convention
  WaveletArguments wavelet;
  std::string padding = "zero";
  double coi_factor = 2.0;
  bool band_limited = false;
  bool synchrosqueeze = false;
  int threads = 1;
  double max_memory_MB = 2048.0;
  std::string output;
  std::string inverse;
  std::string scalogram;
  std::string plot;
};

// Channels named in the note on skipped constant channels.
constexpr int kListedSkipped = 8;

// The analysed signals and a label for each: one channel, every channel
// (--channel all) or one POD time mode.
std::vector<std::pair<std::string, Eigen::VectorXd>> SelectSignals(const CwtArguments& a,
                                                                   const TimeSeries& series) {
  if (a.channel == "all") {
    // A constant channel (a dead or unused one: the F-16 file has 113 of
    // 115) has no ridge: skipped with a note instead of failing the call.
    std::vector<std::pair<std::string, Eigen::VectorXd>> all;
    std::string skipped;
    int constant = 0;
    for (Eigen::Index c = 0; c < series.values.cols(); ++c) {
      const std::string& name = series.channel_names[static_cast<std::size_t>(c)];
      const auto column = series.values.col(c);
      if (column.size() > 0 && column.minCoeff() == column.maxCoeff()) {
        if (++constant <= kListedSkipped) skipped += (skipped.empty() ? "" : ", ") + name;
        continue;
      }
      all.emplace_back(name, column);
    }
    if (all.empty()) {
      ThrowInvalid("cwt --channel all of " + a.data, "at least one non-constant channel",
                   "all " + ToText(series.values.cols()) + " channels constant");
    }
    if (constant > 0) {
      std::fprintf(stderr, "podid: note: --channel all: %d constant channel%s skipped (no ridge): %s%s\n",
                   constant, constant > 1 ? "s" : "", Escaped(skipped).c_str(),
                   constant > kListedSkipped ? ", ..." : "");
    }
    return all;
  }
  if (!a.channel.empty()) {
    const int index = series.ChannelIndex(a.channel);
    if (index < 0) {
      std::string names;
      for (const auto& n : series.channel_names) names += (names.empty() ? "" : ", ") + n;
      ThrowInvalid("cwt --channel", "one of " + names + " or all", "\"" + a.channel + "\"");
    }
    return {{a.channel, series.values.col(index)}};
  }
  // --pom k: the k-th right-singular vector (time mode) of the POD of all channels.
  // The data have at most min(channels, samples) modes; checked here so the
  // message names --pom, not the POD's option.
  const Eigen::Index available = std::min(series.values.rows(), series.values.cols());
  if (available < a.pom) {
    ThrowInvalid("cwt --pom", "1.." + ToText(available) + " (the data's POD modes)", ToText(a.pom));
  }
  PodOptions options;
  options.max_modes = a.pom;
  const PodResult pod = ComputePod(series, options);
  if (pod.modes() < a.pom) {
    ThrowInvalid("cwt --pom", "1.." + ToText(pod.modes()) + " (the data's POD modes)",
                 ToText(a.pom));
  }
  return {{"POM " + ToText(a.pom) + " time mode (V column, energy " +
               ToText(std::round(1000.0 * pod.energy_fraction(a.pom - 1)) / 10.0) + " %)",
           pod.time_modes.col(a.pom - 1)}};
}

// How many of a ridge's usable IFs lie outside the grid's range, widened by
// half a grid step at each end (a tone at the top frequency reads a hair above
// it): the phase derivative measures the signal's frequency wherever the
// ridge is, and where the ridge holds to an edge of the grid, or lies between
// components or on noise, that frequency is outside the band analysed.
struct OutsideGrid {
  Eigen::Index below = 0, above = 0;
};
OutsideGrid CountOutsideGrid(const wavelet::RidgeTrack& track, const Eigen::VectorXd& grid_Hz) {
  const Eigen::Index n = grid_Hz.size();
  const double low_Hz = n > 1 ? grid_Hz(0) - 0.5 * (grid_Hz(1) - grid_Hz(0)) : grid_Hz(0);
  const double high_Hz =
      n > 1 ? grid_Hz(n - 1) + 0.5 * (grid_Hz(n - 1) - grid_Hz(n - 2)) : grid_Hz(n - 1);
  OutsideGrid out;
  for (Eigen::Index j = 0; j < track.size(); ++j) {
    if (!track.inside_coi(j)) continue;  // screened IFs (NaN) are outside the cone
    out.below += track.frequency_Hz(j) < low_Hz;
    out.above += track.frequency_Hz(j) > high_Hz;
  }
  return out;
}

// A transform's memory error in this command's options: the library names its
// fields (CwtOptions::memory_budget_bytes, min_frequency_Hz, band_limited).
std::string MemoryErrorInOptionNames(std::string what) {
  static constexpr std::pair<std::string_view, std::string_view> kNames[] = {
      {"CwtOptions::memory_budget_bytes", "--max-memory"},
      {"a higher min_frequency_Hz", "a higher --fmin"},
      {"or band_limited", "or --band-limited"},
  };
  for (const auto& [field, option] : kNames) what = ReplaceAll(std::move(what), field, option);
  return what;
}

// Prints the IF statistics of one ridge inside the cone of influence.
void PrintRidge(const wavelet::RidgeTrack& track, double coi_factor, const std::string& prefix) {
  double lo = INFINITY, hi = -INFINITY;
  Eigen::Index first = -1, last = -1, inside = 0;
  const auto counted = [&](Eigen::Index j) {
    return track.inside_coi(j) && std::isfinite(track.frequency_Hz(j));
  };
  for (Eigen::Index j = 0; j < track.size(); ++j) {
    if (!counted(j)) continue;
    const double f = track.frequency_Hz(j);
    lo = std::min(lo, f);
    hi = std::max(hi, f);
    if (first < 0) first = j;
    last = j;
    ++inside;
  }
  if (inside == 0) {
    std::printf("%sno ridge sample inside the cone of influence (coi_factor %.6g)\n",
                prefix.c_str(), coi_factor);
    return;
  }
  // Two passes on f / max |f|: a step of 1e-200 s puts the IF near 1e199 Hz,
  // whose squares overflow, and sum f^2 - n mean^2 cancels a small spread.
  const double scale = std::max({std::abs(lo), std::abs(hi), std::numeric_limits<double>::min()});
  double sum = 0.0, sum2 = 0.0;
  for (Eigen::Index j = 0; j < track.size(); ++j) {
    if (counted(j)) sum += track.frequency_Hz(j) / scale;
  }
  const double mean_scaled = sum / static_cast<double>(inside);
  for (Eigen::Index j = 0; j < track.size(); ++j) {
    if (!counted(j)) continue;
    const double d = track.frequency_Hz(j) / scale - mean_scaled;
    sum2 += d * d;
  }
  const double mean = mean_scaled * scale;
  const double sd = std::sqrt(sum2 / static_cast<double>(inside)) * scale;
  std::printf("%sIF inside the cone of influence (%ld of %ld samples, t = %.4g-%.4g s):\n",
              prefix.c_str(), static_cast<long>(inside), static_cast<long>(track.size()),
              track.time_s(first), track.time_s(last));
  std::printf("%s  mean %.6g Hz, std %.4g Hz, min %.6g Hz, max %.6g Hz\n", prefix.c_str(), mean,
              sd, lo, hi);
  std::printf("%s  first %.6g Hz (amplitude %.4g), last %.6g Hz (amplitude %.4g)\n",
              prefix.c_str(), track.frequency_Hz(first), track.amplitude(first),
              track.frequency_Hz(last), track.amplitude(last));
}

// A result beyond double precision (an input near 1.8e308) is a computation
// that failed, not a value to print or write: exit 2 naming the reason,
// before any file is staged. The library throws std::overflow_error for the
// in-band signal and the ridges' amplitudes; W and T are stored in units of
// coefficient_scale, so only |W| or |T| written out in signal units is
// checked here, thrown the same way for Run's one message. A NaN IF is no
// failure: it marks a screened sample (docs/wavelet.md).
void CheckFinite(const CwtArguments& a, const wavelet::Scalogram& kept) {
  if ((a.scalogram.empty() && a.plot.empty()) || kept.coefficients.size() == 0 ||
      std::isfinite(kept.coefficients.cwiseAbs().maxCoeff() * kept.coefficient_scale)) {
    return;
  }
  throw std::overflow_error(std::string(a.synchrosqueeze ? "|T|" : "|W|") +
                            " (--scalogram, --plot) overflowed double precision (above "
                            "1.8e308); scale the data down");
}

void Run(const CwtArguments& a) {
  CheckOutputs({{"data file", a.data}}, {{"-o", a.output},
                                         {"--inverse", a.inverse},
                                         {"--scalogram", a.scalogram},
                                         {"--plot", a.plot}});
  const TimeSeries series = a.reading.ReadConditioned(a.data);
  const auto signals = SelectSignals(a, series);
  // --channel all, whatever the count left after the constant channels: the
  // CSV's columns then always name their channel (one analysed channel wrote
  // plain `f_Hz` columns before, and took --scalogram and --plot).
  const bool several = a.channel == "all";
  if (several && (!a.scalogram.empty() || !a.plot.empty())) {
    ThrowInvalid("cwt --scalogram/--plot", "a single --channel or --pom",
                 "--channel all (" + ToText(signals.size()) + " channel" +
                     (signals.size() == 1 ? "" : "s") + " analysed)");
  }
  const double step_s = series.step_s();
  const double t0_s = series.time_s(0);
  if (a.grid.fmax_Hz > 0.5 / step_s) {
    ThrowInvalid("--fmax",
                 "at most the Nyquist frequency of " + a.data + " as read, " +
                     ToText(0.5 / step_s) + " Hz (step " + ToText(step_s) + " s)",
                 ToText(a.grid.fmax_Hz) + " Hz");
  }

  wavelet::RidgeFrequencyOptions options;
  wavelet::CwtOptions& cwt = options.cwt;
  cwt.band_limited = a.band_limited;
  a.wavelet.ApplyTo(&cwt.wavelet);
  cwt.padding = ParseOption("--padding", a.padding, wavelet::ParsePadding);
  cwt.coi_factor = a.coi_factor;
  cwt.threads = a.threads;
  // Without a scalogram to write or plot, --synchrosqueeze or --inverse, one ridge is streamed
  // (RidgeFrequencyEstimator: memory bounded by blocks, about 1 byte per
  // output cell, instead of 16-32 for the whole transform; the same ridge to
  // about band_tolerance, tests StreamedRidge.*); --threads >= 2 then runs
  // the next block's transform beside the ridge's dynamic programme.
  const bool streamed = a.ridges == 1 && a.scalogram.empty() && a.plot.empty() &&
                        !a.synchrosqueeze && a.inverse.empty();
  // The transform's budget is for W's 16 bytes a coefficient: the
  // synchrosqueezed T replaces W, its reassignment field takes 8 more,
  // --scalogram copies |W| or |T| (8 more) before writing, and the ridge
  // search over the whole transform (FindRidges) holds a cost (8) and a
  // back-pointer (1-4: 4 counted) a cell. Without the search's 12, 2000
  // samples x 9500 frequencies under --max-memory 300 peaked at 503 MB.
  const double cell_bytes = 16.0 + (a.synchrosqueeze ? 8.0 : 0.0) +
                            (a.scalogram.empty() ? 0.0 : 8.0) + (streamed ? 0.0 : 12.0);
  cwt.memory_budget_bytes = std::floor(a.max_memory_MB * 1048576.0 * 16.0 / cell_bytes);
  cwt.frequencies = a.grid.Grid();
  options.ridge.method = ParseOption("--ridge", a.ridge, wavelet::ParseRidgeMethod);
  options.ridge.estimator = ParseOption("--if", a.if_from, wavelet::ParseFrequencyEstimator);
  options.ridge.penalty_s = a.penalty_s;
  options.ridge.ridges = a.ridges;
  std::string why;
  if (!options.IsValid(&why) || !options.ridge.IsValid(&why)) {
    throw std::invalid_argument("cwt: " + why);
  }

  // One transform for every signal (same length and step: laid out once).
  std::unique_ptr<wavelet::CwtTransform> transform;
  std::unique_ptr<wavelet::RidgeFrequencyEstimator> estimator;
  if (streamed) {
    estimator = std::make_unique<wavelet::RidgeFrequencyEstimator>(options);
  } else {
    transform = std::make_unique<wavelet::CwtTransform>(cwt);
  }
  wavelet::Scalogram whole;
  wavelet::SynchrosqueezedTransform squeezed;  // --synchrosqueeze: the last signal's
  std::vector<std::vector<wavelet::RidgeTrack>> tracks;
  std::vector<Eigen::VectorXd> in_band;  // --inverse: each signal's
  for (std::size_t c = 0; c < signals.size(); ++c) {
    const auto& [label, signal] = signals[c];
    tracks.emplace_back();
    try {
      if (streamed) {
        tracks.back().push_back(estimator->Estimate(signal, step_s));
      } else {
        // --synchrosqueeze: T replaces W in place (16 bytes a coefficient less).
        wavelet::Scalogram& w = a.synchrosqueeze ? squeezed.sst : whole;
        transform->Compute(signal, step_s, &w);
        if (!a.inverse.empty()) in_band.push_back(wavelet::InverseCwt(w));
        if (a.synchrosqueeze) {
          wavelet::SynchrosqueezeInPlace(*transform, {}, &squeezed);
          tracks.back() = wavelet::SynchrosqueezedRidges(squeezed, options.ridge);
        } else {
          for (const Eigen::VectorXi& path : wavelet::FindRidges(w, options.ridge)) {
            tracks.back().push_back(wavelet::TrackRidge(w, path, options.ridge, transform.get()));
          }
        }
        CheckFinite(a, w);
      }
    } catch (const std::overflow_error& e) {  // a value beyond 1.8e308 (or CheckFinite's)
      throw CommandFailed("cwt: " + Escaped(label) + " of " + Escaped(a.data) + ": " + e.what() +
                          " (the input's peak magnitude is " +
                          ToText(signal.cwiseAbs().maxCoeff()) + "); no file written");
    } catch (const std::invalid_argument& e) {  // name the signal the error is about
      // Escaped as ThrowInvalid escapes (e.what() already is: escaping is idempotent).
      std::string what = e.what();
      const bool memory = what.find("memory_budget_bytes") != std::string::npos;
      if (memory) what = MemoryErrorInOptionNames(std::move(what));
      if (memory && cell_bytes > 16.0) {
        // The budget the transform saw is --max-memory's share for W.
        what += " [--max-memory " + ToText(a.max_memory_MB) + " MB x 16 / " + ToText(cell_bytes) +
                ": W's share of the " + ToText(cell_bytes) + " bytes a coefficient takes with" +
                (a.synchrosqueeze ? " --synchrosqueeze," : "") +
                (a.scalogram.empty() ? "" : " --scalogram,") + " the ridge search]";
      }
      throw std::invalid_argument(Escaped(label + " of " + a.data + ": ") + what);
    }
    // The grid (times, frequencies, decimation, cone) of either path.
    const wavelet::Scalogram& sg = streamed           ? estimator->scalogram()
                                   : a.synchrosqueeze ? squeezed.sst
                                                      : whole;
    // Record time, not time from the first sample: the data's t0 (a window
    // or a file whose time column does not start at 0).
    for (wavelet::RidgeTrack& track : tracks.back()) track.time_s.array() += t0_s;
    if (c == 0) {
      // Every channel's ridges are kept for the CSV: bound them too (about 64
      // bytes per channel, ridge and output time: the track and its CSV columns).
      // --inverse keeps 8 more bytes per channel and time.
      const double bytes = (64.0 * a.ridges + (a.inverse.empty() ? 0.0 : 8.0)) *
                           static_cast<double>(signals.size()) * static_cast<double>(sg.times());
      if (bytes > a.max_memory_MB * 1048576.0) {
        ThrowInvalid("cwt --max-memory",
                     "at least " + ToText(std::ceil(bytes / 1048576.0)) + " MB for " +
                         ToText(signals.size()) + " channels x " + ToText(a.ridges) + " ridges x " +
                         ToText(sg.times()) + " output times" +
                         (a.inverse.empty() ? "" : " and the in-band signals"),
                     ToText(a.max_memory_MB) +
                         " MB (fewer channels or ridges; --band-limited has fewer output times)");
      }
    }
    if (c == 0) {
      std::printf("podid cwt: %s of %s: %ld samples, step %.6g s (fs %.6g Hz)\n",
                  several ? ("all " + ToText(signals.size()) + " channel" +
                             (signals.size() == 1 ? " analysed" : "s"))
                                .c_str()
                          : label.c_str(),
                  a.data.c_str(), static_cast<long>(signal.size()), step_s, 1.0 / step_s);
      std::printf("%s (%s), %ld frequencies %.6g-%.6g Hz (%s), %s padding%s\n",
                  cwt.wavelet.Describe().c_str(), wavelet::ToString(cwt.wavelet.normalisation),
                  static_cast<long>(sg.frequencies()), sg.frequencies_Hz(0),
                  sg.frequencies_Hz(sg.frequencies() - 1),
                  a.grid.bins ? "linear" : (ToText(a.grid.voices) + " voices/octave").c_str(),
                  wavelet::ToString(cwt.padding),
                  !a.band_limited ? ""
                  : sg.decimation > 1
                      ? (", band-limited: every " + ToText(sg.decimation) + "th sample").c_str()
                      : ", band-limited: no decimation (the band reaches Nyquist)");
      std::printf("ridge: %s%s%s%s\n", wavelet::ToString(options.ridge.method),
                  options.ridge.method == wavelet::RidgeMethod::kPenalised
                      ? (" (penalty " + ToText(a.penalty_s) + " s)").c_str()
                      : "",
                  a.synchrosqueeze
                      ? " on the synchrosqueezed |T|, IF at the reassignment's fixed point"
                  : options.ridge.estimator == wavelet::FrequencyEstimator::kPhase
                      ? ", IF from the phase derivative"
                      : ", IF from the ridge's scale (refined between grid frequencies)",
                  a.ridges > 1 ? (", up to " + ToText(a.ridges) + " ridges").c_str() : "");
      // Below the lowest frequency whose cone holds a sample (the record's
      // middle) every coefficient is within an e-folding time of an edge:
      // |W| there is the padding's step, and a penalised ridge drawn to it
      // can stay at those frequencies well into the record.
      const double useful_Hz = sg.coi_frequency_Hz.size() > 0 ? sg.coi_frequency_Hz.minCoeff() : 0.0;
      const double record_s = static_cast<double>(signal.size() - 1) * step_s;
      if (a.coi_factor > 0.0 && sg.frequencies_Hz(sg.frequencies() - 1) < useful_Hz) {
        std::fprintf(stderr,
                     "podid: note: no coefficient of this %.4g s record is inside the cone of "
                     "influence (coi_factor %.4g) at any frequency of the grid (up to %.4g Hz; "
                     "the cone holds some from %.4g Hz): a longer record or a smaller "
                     "--coi-factor avoids it\n",
                     record_s, a.coi_factor, sg.frequencies_Hz(sg.frequencies() - 1), useful_Hz);
      } else if (a.coi_factor > 0.0 && sg.frequencies_Hz(0) < useful_Hz) {
        std::fprintf(
            stderr,
            "podid: note: below %.4g Hz no coefficient of this %.4g s record is inside the "
            "cone of influence (coi_factor %.4g): the ridge may follow the record's edges "
            "there; --fmin %.4g or a longer record avoids it\n",
            useful_Hz, record_s, a.coi_factor, useful_Hz);
      }
    }
    for (std::size_t r = 0; r < tracks.back().size(); ++r) {
      std::string prefix;
      if (several) prefix += label + ": ";
      if (a.ridges > 1) prefix += "ridge " + ToText(r + 1) + ": ";
      if (!prefix.empty()) std::printf("%s\n", prefix.substr(0, prefix.size() - 1).c_str());
      PrintRidge(tracks.back()[r], a.coi_factor, prefix.empty() ? "" : "  ");
      const OutsideGrid out = CountOutsideGrid(tracks.back()[r], sg.frequencies_Hz);
      if (out.below + out.above > 0) {
        const Eigen::Index n = sg.frequencies();
        std::fprintf(stderr,
                     "podid: note: %s%ld of %ld IFs inside the cone lie outside the grid's "
                     "%.6g-%.6g Hz (%ld below, %ld above): where the ridge holds to an edge of "
                     "the grid, or lies between components or on noise, the %s measures content "
                     "beyond the grid; widen --fmin/--fmax%s\n",
                     Escaped(prefix).c_str(), static_cast<long>(out.below + out.above),
                     static_cast<long>(tracks.back()[r].InsideCoiCount()), sg.frequencies_Hz(0),
                     sg.frequencies_Hz(n - 1), static_cast<long>(out.below),
                     static_cast<long>(out.above),
                     a.synchrosqueeze ? "reassigned frequency" : "phase derivative",
                     a.synchrosqueeze ? "" : ", or --if scale for IFs on the grid");
      }
    }
  }

  // Every file of the command is staged and published at the end, together:
  // a failure on a later one (gnuplot, a full disk) leaves none of them.
  OutputBatch batch;
  std::vector<std::string> written;  // "what -> path", printed once published
  if (!a.output.empty()) {
    // Columns f_Hz, amplitude, inside_coi per ridge (suffix 2, 3.. after the
    // first) and per channel (prefix "NAME_" with --channel all).
    TimeSeries ridge;
    ridge.time_s = tracks.front().front().time_s;
    std::vector<const wavelet::RidgeTrack*> columns;
    for (std::size_t c = 0; c < signals.size(); ++c) {
      for (std::size_t r = 0; r < tracks[c].size(); ++r) {
        const std::string pre = several ? signals[c].first + "_" : "";
        const std::string post = r > 0 ? ToText(r + 1) : "";
        for (const char* name : {"f_Hz", "amplitude", "inside_coi"}) {
          ridge.channel_names.push_back(pre + name + post);
        }
        columns.push_back(&tracks[c][r]);
      }
    }
    ridge.values.resize(ridge.time_s.size(), static_cast<Eigen::Index>(3 * columns.size()));
    for (std::size_t i = 0; i < columns.size(); ++i) {
      const auto col = static_cast<Eigen::Index>(3 * i);
      ridge.values.col(col) = columns[i]->frequency_Hz;
      ridge.values.col(col + 1) = columns[i]->amplitude;
      ridge.values.col(col + 2) = columns[i]->inside_coi.cast<double>();
    }
    WriteCsv(a.output, ridge, &batch);
    written.push_back("ridge -> " + a.output);
  }
  if (!a.inverse.empty()) {
    // Columns named by channel (or "pomK"), on the transform's output times.
    TimeSeries band;
    band.time_s = (a.synchrosqueeze ? squeezed.sst : whole).time_s.array() + t0_s;
    band.values.resize(band.time_s.size(), static_cast<Eigen::Index>(in_band.size()));
    for (std::size_t c = 0; c < in_band.size(); ++c) {
      band.channel_names.push_back(a.pom > 0 ? "pom" + ToText(a.pom) : signals[c].first);
      band.values.col(static_cast<Eigen::Index>(c)) = in_band[c];
    }
    WriteCsv(a.inverse, band, &batch);
    written.push_back("in-band signal -> " + a.inverse);
  }
  const std::string& label = signals.front().first;
  const wavelet::RidgeTrack& track = tracks.front().front();
  // --scalogram and --plot: the whole transform's |W|, or |T|.
  const wavelet::Scalogram& sg = a.synchrosqueeze ? squeezed.sst : whole;
  const char* const symbol = a.synchrosqueeze ? "|T|" : "|W|";
  if (!a.scalogram.empty()) {
    TimeSeries magnitude;
    magnitude.time_s = sg.time_s.array() + t0_s;
    for (Eigen::Index k = 0; k < sg.frequencies(); ++k) {
      char name[32];
      std::snprintf(name, sizeof name, "%.6gHz", sg.frequencies_Hz(k));
      magnitude.channel_names.push_back(name);
    }
    magnitude.values = sg.coefficients.cwiseAbs() * sg.coefficient_scale;
    WriteCsv(a.scalogram, magnitude, &batch);
    written.push_back(std::string(symbol) + " -> " + a.scalogram);
  }
  if (!a.plot.empty()) {
    // At most kPlotColumns times and kPlotRows frequencies, whatever the
    // record and --bins: gnuplot takes about 250 bytes a cell (2.3 GB at 9000
    // frequencies) and the data file 30, and the PNG has only 650 pixels of
    // height. Each row is the largest |W| of a group of adjacent frequencies,
    // at the group's middle one, so a ridge narrower than a group stays
    // visible where plain decimation could step over it.
    constexpr Eigen::Index kPlotColumns = 1000, kPlotRows = 500;
    const Eigen::Index stride =
        std::max<Eigen::Index>(1, (sg.times() + kPlotColumns - 1) / kPlotColumns);
    const Eigen::Index columns = (sg.times() + stride - 1) / stride;
    const Eigen::Index group =
        std::max<Eigen::Index>(1, (sg.frequencies() + kPlotRows - 1) / kPlotRows);
    const Eigen::Index rows = (sg.frequencies() + group - 1) / group;
    Eigen::VectorXd t(columns), f(rows);
    for (Eigen::Index r = 0; r < rows; ++r) {
      const Eigen::Index first = r * group, last = std::min(first + group, sg.frequencies()) - 1;
      f(r) = sg.frequencies_Hz((first + last) / 2);
    }
    Eigen::MatrixXd z(columns, rows);
    for (Eigen::Index i = 0; i < columns; ++i) {
      t(i) = t0_s + sg.time_s(i * stride);
      for (Eigen::Index r = 0; r < rows; ++r) {
        const Eigen::Index first = r * group;
        const Eigen::Index count = std::min(group, sg.frequencies() - first);
        z(i, r) = sg.coefficients.row(i * stride).segment(first, count).cwiseAbs().maxCoeff() *
                  sg.coefficient_scale;
      }
    }
    Eigen::VectorXd coi = sg.coi_frequency_Hz;
    const Eigen::VectorXd coi_time_s = sg.time_s.array() + t0_s;
    for (Eigen::Index j = 0; j < coi.size(); ++j) {
      if (!(coi(j) <= sg.frequencies_Hz(sg.frequencies() - 1))) coi(j) = NAN;
    }
    Eigen::VectorXd ridge_f = track.frequency_Hz;
    for (Eigen::Index j = 0; j < ridge_f.size(); ++j) {
      if (!track.inside_coi(j)) ridge_f(j) = NAN;
    }
    Axes axes;
    axes.title = std::string(symbol) + " of " + label + " (" + cwt.wavelet.Describe() +
                 (a.synchrosqueeze ? ", synchrosqueezed)" : ")");
    axes.x_label = "t (s)";
    axes.y_label = "f (Hz)";
    axes.log_y = !a.grid.bins;
    const PlotOutcome outcome = PlotHeatMap(
        a.plot, axes, symbol, t, f, z,
        {{"ridge IF (inside cone)", track.time_s, ridge_f}, {"cone of influence", coi_time_s, coi}},
        &batch);
    if (outcome == PlotOutcome::kWritten) written.push_back("plot -> " + a.plot);
  }
  batch.Commit();
  for (const std::string& line : written) std::printf("%s\n", line.c_str());
}

}  // namespace

void AddCwtCommand(CLI::App& app) {
  auto a = std::make_shared<CwtArguments>();
  CLI::App* command = app.add_subcommand(
      "cwt",
      "Morlet or Morse wavelet transform of one channel (--channel) or POD time mode (--pom):\n"
      "prints the instantaneous frequency (IF) along the ridge inside the cone of\n"
      "influence and writes the ridge (t, f_Hz, amplitude, inside_coi). docs/wavelet.md");
  command->add_option("data", a->data, "Time series (.csv, .mat or .uff; docs/data-files.md)")
      ->required()
      ->check(CLI::ExistingFile);
  a->reading.AddTo(*command);
  auto* channel = command->add_option("--channel", a->channel,
                                      "Channel name, e.g. w6, or all (every channel in one call; constant channels are skipped with a note)");
  auto* pom =
      command->add_option("--pom", a->pom, "Analyse the k-th POD time mode (right-singular vector)")
          ->check(IntegerIn(1, kMaxPomOption));
  channel->excludes(pom);
  pom->excludes(channel);
  a->grid.AddTo(*command, "Highest analysis frequency (Hz), <= Nyquist");
  command->add_option("--ridge", a->ridge, "Ridge method: max or penalised")->capture_default_str();
  auto* if_from =
      command
          ->add_option(
              "--if", a->if_from,
              "IF along the ridge: phase (the phase derivative of W: exact for a tone,\n"
              "follows content beyond the grid) or scale (the ridge's scale, refined by the\n"
              "parabola through log|W| at three scales: always on the grid)")
          ->capture_default_str();
  command
      ->add_option("--ridges", a->ridges,
                   "Extract this many ridges, strongest first, each excluding\n"
                   "half an octave either side of those before it")
      ->capture_default_str()
      ->check(IntegerIn(1, wavelet::kMaxRidges));
  command
      ->add_option("--penalty", a->penalty_s,
                   "Penalised ridge: cost (s) of a jump of one e-fold in frequency")
      ->capture_default_str()
      ->check(NumberIn({0.0}));
  a->wavelet.AddTo(*command);
  command->add_option("--padding", a->padding, "reflect, zero or periodic")->capture_default_str();
  command
      ->add_option("--coi-factor", a->coi_factor,
                   "Widen the cone of influence (1 = Torrence & Compo; 2 keeps the worst\n"
                   "border IF error over end phases below 0.3 %, docs/wavelet.md); 0: no cone")
      ->capture_default_str()
      ->check(NumberIn({0.0}, {wavelet::kMaxCoiFactor}));
  command
      ->add_option("--threads", a->threads,
                   "Threads over the scales; a streamed ridge uses two (the same result)")
      ->capture_default_str()
      ->check(IntegerIn(1, wavelet::kMaxCwtThreads));
  command
      ->add_option(
          "--max-memory", a->max_memory_MB,
          "Refuse transforms needing more than this many MB. One ridge without\n"
          "--scalogram/--plot/--synchrosqueeze/--inverse is streamed: about 1 byte per cell plus\n"
          "~43 per cell of a block; otherwise the coefficients take n_times x\n"
          "n_frequencies x 16 bytes, 8 more with --synchrosqueeze, 8 more with\n"
          "--scalogram; the ridges kept for -o about 64 bytes per channel, ridge and time,\n"
          "the in-band signals of --inverse 8 per channel and time)")
      ->check(NumberIn({wavelet::kMinMemoryLimit_MB}, {wavelet::kMaxMemoryLimit_MB}))
      ->capture_default_str();
  command->add_flag("--band-limited", a->band_limited,
                    "Decimated output (what identification uses); IF values are unchanged");
  auto* synchrosqueeze =
      command->add_flag("--synchrosqueeze", a->synchrosqueeze,
                        "Ridges of the synchrosqueezed transform |T| (Daubechies, Lu & Wu 2011):\n"
                        "the IF where the reassignment has its fixed point, not quantised to the\n"
                        "grid; --scalogram and --plot show |T|");
  if_from->excludes(synchrosqueeze);
  synchrosqueeze->excludes(if_from);
  command->add_option("-o,--output", a->output, "Ridge CSV: t,f_Hz,amplitude,inside_coi")
      ->check(NonEmptyPath());
  command
      ->add_option("--inverse", a->inverse,
                   "In-band part of each signal by the inverse CWT (2 Re sum_k W ds/s / C:\n"
                   "the components well inside --fmin..--fmax, no DC) as CSV: t, one column\n"
                   "per signal")
      ->check(NonEmptyPath());
  command
      ->add_option("--scalogram", a->scalogram,
                   "|W| (|T| with --synchrosqueeze) CSV: t, one column per frequency")
      ->check(NonEmptyPath());
  command->add_option("--plot", a->plot, "Scalogram PNG with the ridge (needs gnuplot)")
      ->check(NonEmptyPath());
  command->callback([a] {
    if (a->channel.empty() && a->pom == 0) {
      ThrowInvalid("cwt", "--channel NAME or --pom K", "neither");
    }
    Run(*a);
  });
}

}  // namespace podid::cli
