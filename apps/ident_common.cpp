#include "ident_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <utility>

#include "mpi_session.hpp"
#include "podid/core/error.hpp"
#include "podid/core/io.hpp"
#include "podid/ident/measured_record.hpp"
#include "podid/wavelet/ridge.hpp"

namespace podid::cli {
namespace {

// A ridge band given on the command line (--fmin/--fmax, --mode-band K) that
// lies wholly outside the passband of the filter both records go through
// compares nothing but the filter's skirt: refused here, naming the options,
// before the data are decomposed (the library refuses it too, naming its
// fields, and notes a band partly outside: ident/src/mode_ridges.cpp).
// `filter_name` is the option or case key that set the filter.
void CheckBandInPassband(const std::string& where,
                         double low_Hz,
                         double high_Hz,
                         const FilterOptions& filter,
                         const std::string& filter_name) {
  const bool below = high_Hz <= filter.PassbandLow_Hz(), above = low_Hz >= filter.PassbandHigh_Hz();
  if (!below && !above) return;
  ThrowInvalid(where,
               "a ridge band reaching into the passband of " + filter_name + " (" +
                   filter.DescribePassband() +
                   ": the filter conditions the measured and the simulated records alike, and "
                   "beyond its cutoff both hold only its skirt)",
               ToText(low_Hz) + ".." + ToText(high_Hz) + " Hz, entirely " +
                   (above ? "above" : "below") + " it");
}

// "--lowpass 50", or the case's keys when the filter came from its [data].
std::string FilterName(const FilterOptions& filter,
                       const DataArguments& reading,
                       const std::string& case_path) {
  const bool from_options = reading.Conditioning().filter.type != FilterType::kNone;
  const std::string kind = ToString(filter.type);
  if (from_options) {
    return "--" + kind + " " +
           (filter.type == FilterType::kBandpass
                ? ToText(filter.low_Hz) + ":" + ToText(filter.high_Hz)
                : ToText(filter.type == FilterType::kLowpass ? filter.high_Hz : filter.low_Hz));
  }
  return "[data] filter = \"" + kind + "\", " +
         (filter.type == FilterType::kBandpass
              ? "band = [" + ToText(filter.low_Hz) + ", " + ToText(filter.high_Hz) + "]"
              : "cutoff = " +
                    ToText(filter.type == FilterType::kLowpass ? filter.high_Hz : filter.low_Hz)) +
         " of " + case_path;
}

}  // namespace

void ObjectiveArguments::AddTo(CLI::App& command) {
  input.AddTo(command);
  command.add_option("-m,--measured", measured,
                     "Measured time histories (.csv, .mat or .uff; default: the case's [data] file)");
  measured_reading.AddTo(command);
  command.add_option("--modes", modes, "Number of leading POMs in the objective (K)")->capture_default_str()
      ->check(IntegerIn(1, kMaxObjectiveModes));
  auto* corrected = command.add_flag("--noise-sigma", noise_sigma,
                   "Compare with the measured singular values less the white-noise energy "
                   "(estimated per sensor from second differences; the default when --modes > 1)");
  command.add_flag("--no-noise-sigma", no_noise_sigma,
                   "Compare with the measured singular values as they are, also when --modes > 1")
      ->excludes(corrected);
  command.add_option("--mode-band", mode_bands,
                     "Ridge band of mode K >= 2 (repeatable, each K once, HIGH <= Nyquist; default: the --fmin..--fmax width in octaves "
                     "centred on the mode's spectral peak)")
      ->type_name("K=LOW:HIGH");
  command
      .add_option(
          "--ridge-snr", ridge_snr,
          "Measured ridge samples below this multiple of the noise's rms |W| are not compared "
          "(0: compare all)")
      ->capture_default_str()
      ->check(NumberIn({0.0}, {1000.0}));
  command
      .add_option("--min-signal", min_signal,
                  "Modes 2..K whose measured energy is less than this fraction signal (the rest "
                  "white noise) "
                  "are not compared, nor the modes after them (0: compare all K)")
      ->capture_default_str()
      ->check(NumberIn({0.0}, {0.999}));
  command.add_flag("--raw-sigma", raw_sigma,
                   "Compare raw singular values (eq. 19) instead of relative ones");
  command.add_flag("--keep-mean", keep_mean,
                   "Do not subtract the channels' means before the POD (an offset is compared; "
                   "one channel: dS + dV is then the output error)");
  command.add_option("--fmin", fmin_Hz, "Lowest ridge frequency of the wavelet term (Hz)")
      ->capture_default_str()
      ->check(NumberIn({0.0, true}));
  command.add_option("--fmax", fmax_Hz, "Highest ridge frequency of the wavelet term (Hz)")
      ->capture_default_str()
      ->check(NumberIn({0.0, true}));
  command.add_option("--penalty", penalty_s, "Ridge penalty of the wavelet term (s)")
      ->capture_default_str()
      ->check(NumberIn({0.0}));
  wavelet.AddTo(command, " of the wavelet term");
  ridge_options = wavelet.options;
  for (const char* name : {"--fmin", "--fmax", "--penalty", "--mode-band", "--ridge-snr"}) {
    ridge_options.push_back(command.get_option(name));
  }
  command.add_option("--start", starts, "Start value of a parameter, e.g. --start knl=40 (repeatable)")
      ->type_name("NAME=VALUE");
}

void ObjectiveArguments::PrepareData() {
  for (std::string& set : measured_reading.CaseSets(measured)) input.sets.push_back(std::move(set));
}

std::unique_ptr<ident::ObjectiveFunction> ObjectiveArguments::Build(
    std::vector<ident::NamedObjective> weightings) const {
  (void)StartPairs();  // their syntax, before the data are read and simulated
  CaseDocument document = input.Load();
  if (document.ToSpec().data.file.empty()) {
    ThrowInvalid("-m", "a measured file (-m FILE, or [data] file in " + input.path + ")", "none");
  }
  // Conditioned, with time.start on the record's first stamp, as the Python
  // module prepares it (ident/measured_record.hpp).
  std::vector<std::string> notes;
  const TimeSeries data = ident::ReadMeasured(document, &notes);
  for (const std::string& note : notes) std::fprintf(stderr, "podid: note: %s\n", note.c_str());
  ident::ObjectiveOptions options;
  options.weightings = std::move(weightings);
  options.modes = modes;
  options.relative_sigma = !raw_sigma;
  options.remove_mean = !keep_mean;
  options.noise_corrected_sigma = noise_sigma      ? ident::ObjectiveOptions::SigmaNoise::kCorrected
                                  : no_noise_sigma ? ident::ObjectiveOptions::SigmaNoise::kRaw
                                                   : ident::ObjectiveOptions::SigmaNoise::kAuto;
  options.ridge_min_snr = ridge_snr;
  options.min_signal_fraction = min_signal;
  for (const std::string& band : mode_bands) {
    const std::string expected =
        "K=LOW:HIGH with 2 <= K <= --modes (" + ToText(modes) + ") and 0 < LOW < HIGH Hz, e.g. 2=100:400";
    const std::size_t eq = band.find('='), colon = band.find(':', eq == std::string::npos ? 0 : eq);
    if (eq == std::string::npos || colon == std::string::npos) ThrowInvalid("--mode-band", expected, Excerpt(band));
    const double mode = ParseNumber(band.substr(0, eq), "--mode-band", expected);
    const double low = ParseNumber(band.substr(eq + 1, colon - eq - 1), "--mode-band", expected);
    const double high = ParseNumber(band.substr(colon + 1), "--mode-band", expected);
    if (mode != std::floor(mode) || mode < 2 || mode > modes || !(low > 0 && low < high)) {
      ThrowInvalid("--mode-band", expected, Excerpt(band));
    }
    const auto k = static_cast<std::size_t>(mode);
    if (options.mode_bands.size() < k) options.mode_bands.resize(k);
    if (!options.mode_bands[k - 1].follow()) {  // the later one silently won
      ThrowInvalid("--mode-band", "each mode K at most once",
                   "mode " + ToText(mode) + " twice (" + Excerpt(band) + ")");
    }
    options.mode_bands[k - 1] = {low, high};
  }
  CheckBand(fmin_Hz, fmax_Hz);
  // The library would refuse a band above Nyquist in its field names
  // ("Cwt: frequencies.max_frequency_Hz"); only the wavelet term reads it.
  const double nyquist_Hz = 0.5 / data.step_s();
  const bool ridges =
      std::any_of(options.weightings.begin(), options.weightings.end(),
                  [](const ident::NamedObjective& o) { return o.weights.NeedsRidges(); });
  for (const CLI::Option* option : ridge_options) {
    if (!ridges && option->count() > 0) {  // it was silently ignored
      ThrowInvalid(option->get_name(),
                   "an objective with the wavelet (IF) term, which alone reads it (--objective "
                   "wavelet, or IF in --terms)",
                   "none with it");
    }
  }
  if (ridges) {
    const int voices = options.ridge.cwt.frequencies.voices_per_octave;
    CheckTwoFrequencies("--fmin/--fmax", fmin_Hz, fmax_Hz, voices);
    for (std::size_t k = 0; k < options.mode_bands.size(); ++k) {
      const ident::FrequencyBand& b = options.mode_bands[k];
      if (!b.follow())
        CheckTwoFrequencies("--mode-band " + ToText(k + 1), b.min_Hz, b.max_Hz, voices);
    }
    const FilterOptions filter = document.ToSpec().data.conditioning.filter;
    if (filter.type != FilterType::kNone) {
      const std::string name = FilterName(filter, measured_reading, input.path);
      CheckBandInPassband("--fmin/--fmax", fmin_Hz, fmax_Hz, filter, name);
      for (std::size_t k = 0; k < options.mode_bands.size(); ++k) {
        const ident::FrequencyBand& b = options.mode_bands[k];
        if (!b.follow())
          CheckBandInPassband("--mode-band " + ToText(k + 1), b.min_Hz, b.max_Hz, filter, name);
      }
    }
  }
  if (ridges && fmax_Hz > nyquist_Hz) {
    ThrowInvalid("--fmax",
                 "at most the measured data's Nyquist frequency, " + ToText(nyquist_Hz) +
                     " Hz (step " + ToText(data.step_s()) + " s)",
                 ToText(fmax_Hz) + " Hz");
  }
  for (std::size_t k = 0; ridges && k < options.mode_bands.size(); ++k) {
    if (!options.mode_bands[k].follow() && options.mode_bands[k].max_Hz > nyquist_Hz) {
      ThrowInvalid(
          "--mode-band",
          "HIGH at most the measured data's Nyquist frequency, " + ToText(nyquist_Hz) + " Hz",
          ToText(k + 1) + "=" + ToText(options.mode_bands[k].min_Hz) + ":" +
              ToText(options.mode_bands[k].max_Hz));
    }
  }
  options.ridge.cwt.frequencies.min_frequency_Hz = fmin_Hz;
  options.ridge.cwt.frequencies.max_frequency_Hz = fmax_Hz;
  options.ridge.ridge.penalty_s = penalty_s;
  wavelet.ApplyTo(&options.ridge.cwt.wavelet);
  options.ridge.cwt.threads = ridge_threads;
  std::unique_ptr<ident::ObjectiveFunction> objective;
  try {
    objective = std::make_unique<ident::ObjectiveFunction>(document, data, options);
  } catch (const std::invalid_argument& e) {
    // The library names its fields; these options set them.
    std::string what = e.what();
    for (const auto& [field, option] :
         {std::pair<const char*, const char*>{"RidgeOptions.penalty_s", "--penalty"},
          {"modes: expected at most the number of sensors",
           "--modes: expected at most the number of sensors"}}) {
      what = ReplaceAll(std::move(what), field, option);
    }
    throw std::invalid_argument(what);
  }
  // Under MPI every rank builds the objective; rank 0 speaks for them.
  if (mpi::Rank() == 0) {
    for (const std::string& note : objective->notes()) std::fprintf(stderr, "podid: note: %s\n", note.c_str());
  }
  return objective;
}

std::vector<std::pair<std::string, std::string>> ObjectiveArguments::StartPairs() const {
  std::vector<std::pair<std::string, std::string>> pairs;
  try {
    pairs = ParseSetArguments(starts);
  } catch (const std::invalid_argument& e) {  // its message names --set
    const std::string what = e.what();
    throw std::invalid_argument(what.rfind("--set ", 0) == 0 ? "--start " + what.substr(6) : what);
  }
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (pairs[j].first == pairs[i].first) {  // the last one silently won
        ThrowInvalid("--start", "each parameter at most once", pairs[i].first + " twice");
      }
    }
  }
  return pairs;
}

Eigen::VectorXd ObjectiveArguments::Start(const ident::ObjectiveFunction& objective) const {
  Eigen::VectorXd start = objective.StartValues();
  for (const auto& [name, value_text] : StartPairs()) {
    const int index = objective.ParameterIndex(name, "--start " + name);
    const double value = ParseNumber(value_text, "--start " + name);
    const ParameterSpec& p = objective.parameters()[index];
    if (!(value >= p.lower && value <= p.upper)) {
      ThrowInvalid("--start " + name, "a value in the bounds [" + ToText(p.lower) + ", " + ToText(p.upper) + "]",
                   value_text);
    }
    start[index] = value;
  }
  return start;
}

nlohmann::json RidgesJson(const ident::ObjectiveFunction& objective) {
  nlohmann::json ridges = nlohmann::json::array();
  for (std::size_t k = 0; k < objective.measured_ridges().size(); ++k) {
    const wavelet::RidgeFrequencyOptions& o = objective.mode_ridge_options(static_cast<int>(k));
    ridges.push_back({{"mode", k + 1},
                      {"min_frequency_Hz", o.cwt.frequencies.min_frequency_Hz},
                      {"max_frequency_Hz", o.cwt.frequencies.max_frequency_Hz},
                      {"wavelet", o.cwt.wavelet.Describe()},
                      {"normalisation", wavelet::ToString(o.cwt.wavelet.normalisation)},
                      {"scale_convention", wavelet::ToString(o.cwt.wavelet.convention)},
                      {"penalty_s", o.ridge.penalty_s},
                      {"samples_compared", objective.measured_ridges()[k].InsideCoiCount()}});
  }
  return ridges;
}

ident::ObjectiveWeights WeightsFrom(const std::string& objective, const std::string& terms,
                                    const std::string& weights) {
  if (!terms.empty()) return ident::ObjectiveWeights::Parse(terms, weights, "--terms", "--weights");
  if (!weights.empty()) ThrowInvalid("--weights", "--terms with it", "--weights alone");
  return ident::ObjectiveWeights::Preset(objective);
}

}  // namespace podid::cli
