#include "podid/ident/objective.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <new>
#include <sstream>
#include <utility>

#include "mode_ridges.hpp"
#include "podid/core/error.hpp"
#include "podid/core/recording.hpp"
#include "podid/pod/noise.hpp"

namespace podid::ident {
namespace {

PodOptions MeasuredPodOptions(bool remove_mean) {
  PodOptions options;  // all modes, so that swapped modes can be matched by MAC
  options.remove_mean = remove_mean;
  options.compute_time_modes = true;
  return options;
}

std::string JoinNames(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) out += (i ? "," : "") + names[i];
  return out;
}

}  // namespace

ObjectiveWeights ObjectiveWeights::Preset(std::string_view name) {
  if (name == "full") return {1.0, 1.0, 1.0, 0.0};
  if (name == "time-free") return {1.0, 1.0, 0.0, 0.0};
  if (name == "wavelet") return {1.0, 1.0, 0.0, 1.0};
  ThrowInvalid("objective", "one of full, time-free, wavelet", Excerpt(name));
}

ObjectiveWeights ObjectiveWeights::Parse(std::string_view terms,
                                         std::string_view weights,
                                         std::string_view terms_name,
                                         std::string_view weights_name) {
  auto split = [](std::string_view text) {
    std::vector<std::string> parts;
    std::string current;
    for (char c : text) {
      if (c == ',') {
        parts.push_back(current);
        current.clear();
      } else if (c != ' ') {
        current += c;
      }
    }
    parts.push_back(current);
    return parts;
  };
  const std::vector<std::string> names = split(terms);
  std::vector<double> values(names.size(), 1.0);
  if (!weights.empty()) {
    const std::vector<std::string> w = split(weights);
    if (w.size() != names.size()) {
      ThrowInvalid(
          weights_name,
          ToText(names.size()) + " weights (one per term of " + std::string(terms_name) + ")",
          ToText(w.size()) + " (\"" + std::string(weights) + "\")");
    }
    for (std::size_t i = 0; i < w.size(); ++i) {
      const double value = ParseNumber(w[i], weights_name, "non-negative numbers");
      if (!(value >= 0)) ThrowInvalid(weights_name, "non-negative numbers", "\"" + w[i] + "\"");
      if (value > kMaxObjectiveWeight) {
        ThrowInvalid(weights_name, "weights of at most " + ToText(kMaxObjectiveWeight),
                     "\"" + w[i] + "\"");
      }
      values[i] = value;
    }
  }
  ObjectiveWeights result{0.0, 0.0, 0.0, 0.0};
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string& n = names[i];
    if (n != "U" && n != "S" && n != "V" && n != "IF")
      ThrowInvalid(terms_name, "a list of U, S, V, IF", "\"" + n + "\"");
    // A repeated term's later weight silently replaced the earlier one.
    const auto earlier = names.begin() + static_cast<std::ptrdiff_t>(i);
    if (std::find(names.begin(), earlier, n) != earlier)
      ThrowInvalid(terms_name, "each term once", n + " twice");
    if (n == "U") result.u = values[i];
    else if (n == "S") result.s = values[i];
    else if (n == "V")
      result.v = values[i];
    else
      result.f = values[i];
  }
  if (result.u == 0 && result.s == 0 && result.v == 0 && result.f == 0) {
    ThrowInvalid(std::string(terms_name) + "/" + std::string(weights_name),
                 "at least one term with a positive weight", "none");
  }
  return result;
}

std::string ObjectiveWeights::ToString() const {
  std::ostringstream os;
  bool first = true;
  auto add = [&](double w, const char* name) {
    if (w == 0.0) return;
    if (!first) os << " + ";
    first = false;
    if (w != 1.0) os << w << " ";
    os << name;
  };
  add(u, "dU");
  add(s, "dS");
  add(v, "dV");
  add(f, "dIF");
  return os.str();
}

void ObjectiveOptions::SetWeights(const ObjectiveWeights& weights) {
  weightings = {{weights.ToString(), weights}};
}

bool ObjectiveOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (weightings.empty()) return fail("weightings: expected at least one, got none");
  for (const NamedObjective& w : weightings) {
    const ObjectiveWeights& x = w.weights;
    for (double value : {x.u, x.s, x.v, x.f}) {
      if (!(value >= 0 && std::isfinite(value)))
        return fail("weighting " + w.name + ": expected finite weights >= 0, got " + ToText(value));
    }
    if (x.u == 0 && x.s == 0 && x.v == 0 && x.f == 0)
      return fail("weighting " + w.name + ": expected at least one positive weight, got none");
  }
  if (modes < 1) return fail("modes: expected >= 1, got " + ToText(modes));
  if (!(failure_value > 0 && std::isfinite(failure_value)))
    return fail("failure_value: expected a finite value > 0, got " + ToText(failure_value));
  std::string ridge_why;
  if (!ridge.IsValid(&ridge_why)) return fail("ridge: " + ridge_why);
  if (mode_bands.size() > static_cast<std::size_t>(modes)) {
    return fail("mode_bands: expected at most modes = " + ToText(modes) + " bands, got " +
                ToText(mode_bands.size()));
  }
  for (std::size_t k = 1; k < mode_bands.size(); ++k) {
    const FrequencyBand& b = mode_bands[k];
    if (!b.follow() && !(b.min_Hz > 0 && b.min_Hz < b.max_Hz && std::isfinite(b.max_Hz))) {
      return fail("mode_bands[" + ToText(k) + "] (mode " + ToText(k + 1) + "): expected 0 < min < max Hz, got " +
                  ToText(b.min_Hz) + ".." + ToText(b.max_Hz));
    }
  }
  if (!mode_bands.empty() && !mode_bands[0].follow()) {
    return fail("mode_bands[0]: mode 1's band is ridge's (fmin/fmax); expected it empty, got " +
                ToText(mode_bands[0].min_Hz) + ".." + ToText(mode_bands[0].max_Hz));
  }
  if (!(min_signal_fraction >= 0 && min_signal_fraction < 1)) {
    return fail("min_signal_fraction: expected 0 <= fraction < 1, got " + ToText(min_signal_fraction));
  }
  if (!(ridge_min_snr >= 0 && ridge_min_snr <= 1e3)) {
    return fail("ridge_min_snr: expected 0..1000, got " + ToText(ridge_min_snr));
  }
  return true;
}

double TermValues::Combine(const ObjectiveWeights& w, double failure_value) const {
  if (failed) return failure_value;
  double total = 0.0;
  if (w.u != 0) total += w.u * u;
  if (w.s != 0) total += w.s * s;
  if (w.v != 0) total += w.v * v;
  if (w.f != 0) total += w.f * f;
  return std::isfinite(total) ? total : failure_value;
}

EvaluationWorkspace::EvaluationWorkspace() = default;
EvaluationWorkspace::~EvaluationWorkspace() = default;
EvaluationWorkspace::EvaluationWorkspace(EvaluationWorkspace&&) noexcept = default;
EvaluationWorkspace& EvaluationWorkspace::operator=(EvaluationWorkspace&&) noexcept = default;

namespace {

std::atomic<unsigned long long> next_objective_id{1};

}  // namespace

ObjectiveFunction::ObjectiveFunction(const CaseDocument& case_document, const TimeSeries& measured,
                                     const ObjectiveOptions& options,
                                     std::vector<ParameterSpec> parameters)
    : id_(next_objective_id.fetch_add(1)), document_(case_document), measured_(measured),
      options_(options) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("objective options: " + why);
  for (const NamedObjective& w : options_.weightings) {
    if (w.weights.u != 0) needed_.u = 1.0;
    if (w.weights.s != 0) needed_.s = 1.0;
    if (w.weights.v != 0) needed_.v = 1.0;
    if (w.weights.f != 0) needed_.f = 1.0;
  }
  const std::string& source = document_.source_name();
  if (measured.samples() < 4) {
    ThrowInvalid("measured data", "at least 4 samples", ToText(measured.samples()));
  }

  // The data decide the time grid: duration and step.
  const double step = measured.step_s();
  const double duration = (measured.samples() - 1) * step;
  const CaseSpec original = document_.ToSpec();
  if (std::abs(original.time.step_s - step) > 1e-9 * step) {
    notes_.push_back(source + ": time.step = " + ToText(original.time.step_s) +
                     " s replaced by the measured data's step " + ToText(step) + " s");
  }
  if (std::abs(original.time.duration_s - duration) > 0.5 * step) {
    notes_.push_back(source + ": time.duration = " + ToText(original.time.duration_s) +
                     " s replaced by the measured data's duration " + ToText(duration) + " s");
  }
  document_.SetNumber("time.step", step);
  document_.SetNumber("time.duration", duration);

  base_spec_ = document_.ToSpec();
  const std::vector<std::string> channels = base_spec_.sensors.ChannelNames();
  if (channels != measured.channel_names) {
    ThrowInvalid("measured data channels", JoinNames(channels) + " (the sensors of " + source + ")",
                 JoinNames(measured.channel_names));
  }
  if (options.modes > static_cast<int>(channels.size())) {
    ThrowInvalid("modes", "at most the number of sensors, " + ToText(channels.size()),
                 ToText(options.modes));
  }

  parameters_ = parameters.empty() ? base_spec_.parameters : std::move(parameters);
  if (parameters_.empty()) {
    ThrowInvalid(source, "at least one [[identify.parameter]] (or parameters given by the caller)",
                 "none");
  }
  for (const ParameterSpec& p : parameters_) {
    if (!CaseDocument::IsNumericKey(p.key)) {
      ThrowInvalid("parameter " + p.name, "a real-valued case-file key", "\"" + p.key + "\"");
    }
    if (!(p.lower < p.upper) || !(p.start >= p.lower && p.start <= p.upper)) {
      ThrowInvalid("parameter " + p.name, "lower <= start <= upper with lower < upper",
                   ToText(p.lower) + " <= " + ToText(p.start) + " <= " + ToText(p.upper));
    }
    try {
      bindings_.push_back(ModelParameter::Resolve(base_spec_, p.key));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("identification parameter " + p.name + ": " + e.what());
    }
    has_document_parameters_ = has_document_parameters_ || !bindings_.back().typed();
  }
  // Setting every parameter at its start validates the keys against the case.
  try {
    SpecAt(StartValues());
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("identification parameters: ") + e.what());
  }

  measured_pod_ = ComputePod(measured_, MeasuredPodOptions(options_.remove_mean));
  if (measured_pod_.IsDegenerate()) {
    ThrowInvalid("measured data", "a record with a nonzero POD", measured_pod_.message);
  }
  // White measurement noise per sensor: for the sigma correction and the
  // screening of the measured ridges (mode_ridges.hpp).
  Eigen::VectorXd noise_variance;
  if (measured_.samples() >= 8 && (options_.CorrectsSigma() || (needed_.f != 0 && options_.ridge_min_snr > 0) ||
                                    (options_.modes > 1 && options_.min_signal_fraction > 0))) {
    noise_variance = DifferenceNoiseVariance(measured_.SnapshotMatrix());
  }
  const PodResult raw_measured_pod = measured_pod_;
  compared_modes_ = options_.modes;
  const bool noise_known = noise_variance.size() > 0;
  const Eigen::VectorXd corrected =
      noise_known ? NoiseCorrectedSingularValues(measured_pod_, noise_variance) : Eigen::VectorXd();
  if (noise_known && options_.min_signal_fraction > 0) {
    for (int k = 1; k < options_.modes; ++k) {
      const double fraction = std::pow(corrected[k] / measured_pod_.singular_values[k], 2);
      if (!(fraction >= options_.min_signal_fraction)) {
        const std::string dropped = k + 1 == options_.modes ? "mode " + ToText(k + 1) + " is"
                                                            : "modes " + ToText(k + 1) + ".." + ToText(options_.modes) + " are";
        notes_.push_back(dropped + " not compared: mode " + ToText(k + 1) + "'s measured energy is " +
                         ToText(100 * fraction) + " % signal (sigma_" + ToText(k + 1) + " " +
                         ToText(measured_pod_.singular_values[k]) + ", " + ToText(corrected[k]) +
                         " without the white noise), below the " + ToText(100 * options_.min_signal_fraction) +
                         " % needed (min_signal_fraction, --min-signal)");
        compared_modes_ = k;
        break;
      }
    }
  }
  if (options_.CorrectsSigma() && noise_known) {
    notes_.push_back("measured sigma_1 corrected for white noise (std " +
                     ToText(std::sqrt(noise_variance.maxCoeff())) + " on the noisiest sensor): " +
                     ToText(measured_pod_.singular_values[0]) + " -> " + ToText(corrected[0]) + " (" +
                     ToText(100 * (corrected[0] / measured_pod_.singular_values[0] - 1)) + " %)");
    for (int k = 1; k < compared_modes_; ++k) {
      notes_.push_back("measured sigma_" + ToText(k + 1) + " corrected for white noise: " +
                       ToText(measured_pod_.singular_values[k]) + " -> " + ToText(corrected[k]));
    }
    // Only the compared modes: a mode whose corrected sigma is 0 is noise.
    for (int k = 0; k < compared_modes_; ++k) {
      if (corrected[k] > 0) measured_pod_.singular_values[k] = corrected[k];
    }
  }

  // Each mode's ridge band and measured ridge (one estimator per mode in the
  // workspace), checked against the filter both records go through.
  mode_ridge_options_.assign(compared_modes_, options_.ridge);
  if (needed_.f != 0) {
    internal::ModeRidges ridges =
        internal::PrepareModeRidges(raw_measured_pod, noise_variance, step, compared_modes_,
                                    options_, base_spec_.data.conditioning.filter);
    mode_ridge_options_ = std::move(ridges.options);
    measured_ridges_ = std::move(ridges.measured);
    for (std::string& note : ridges.notes) notes_.push_back(std::move(note));
  }
}

ObjectiveFunction::ObjectiveFunction(const ObjectiveFunction& other)
    : id_(next_objective_id.fetch_add(1)), document_(other.document_), base_spec_(other.base_spec_),
      measured_(other.measured_), options_(other.options_), needed_(other.needed_),
      parameters_(other.parameters_), bindings_(other.bindings_),
      has_document_parameters_(other.has_document_parameters_), measured_pod_(other.measured_pod_),
      compared_modes_(other.compared_modes_),
      mode_ridge_options_(other.mode_ridge_options_), measured_ridges_(other.measured_ridges_),
      notes_(other.notes_) {}

ObjectiveFunction::~ObjectiveFunction() = default;

Eigen::VectorXd ObjectiveFunction::StartValues() const {
  Eigen::VectorXd values(parameter_count());
  for (int i = 0; i < parameter_count(); ++i) values[i] = parameters_[i].start;
  return values;
}

CaseSpec ObjectiveFunction::DocumentSpecAt(const Eigen::VectorXd& values) const {
  if (!has_document_parameters_) return base_spec_;
  CaseDocument document = document_;
  for (int i = 0; i < parameter_count(); ++i) {
    if (!bindings_[i].typed()) document.SetNumber(parameters_[i].key, parameters_[i].scale * values[i]);
  }
  return document.ToSpec();
}

PodOptions ObjectiveFunction::ResponsePodOptions() const {
  // The trailing modes of noise-free simulated data are below the Gram
  // method's accuracy; requiring them accurate sent every evaluation to the SVD.
  PodOptions options = MeasuredPodOptions(options_.remove_mean);
  options.accurate_modes = compared_modes_;
  return options;
}

int ObjectiveFunction::ParameterIndex(std::string_view name, std::string_view where) const {
  std::string names;
  for (int i = 0; i < parameter_count(); ++i) {
    if (parameters_[i].name == name) return i;
    names += (i ? ", " : "") + parameters_[i].name;
  }
  ThrowInvalid(where, "a parameter name (" + names + ")", Excerpt(name));
}

TimeSeries ObjectiveFunction::Conditioned(const TimeSeries& simulated) const {
  return ConditionSimulated(base_spec_, simulated);
}

CaseSpec ObjectiveFunction::SpecAt(const Eigen::VectorXd& values) const {
  if (values.size() != parameter_count()) {
    ThrowInvalid("parameter values", ToText(parameter_count()) + " values", ToText(values.size()));
  }
  CaseSpec spec = DocumentSpecAt(values);
  for (int i = 0; i < parameter_count(); ++i) {
    if (!bindings_[i].typed()) continue;
    std::string why;
    if (!bindings_[i].Set(parameters_[i].scale * values[i], &spec, &why)) {
      throw std::invalid_argument(why);
    }
  }
  return spec;
}

SimulationResult ObjectiveFunction::SimulateAt(const Eigen::VectorXd& values) const {
  SimulateOptions options;
  options.add_noise = false;
  const CaseSpec spec = SpecAt(values);
  SimulationResult result = Simulate(spec, options);
  if (result.summary.IsSolutionUsable()) result.sensors = ConditionSimulated(spec, result.sensors);
  return result;
}

SimulationResult ObjectiveFunction::SimulateAt(const Eigen::VectorXd& values, EvaluationWorkspace* workspace) const {
  if (workspace == nullptr) return SimulateAt(values);
  if (values.size() != parameter_count()) {
    ThrowInvalid("parameter values", ToText(parameter_count()) + " values", ToText(values.size()));
  }
  if (std::string why; !PrepareSimulator(values, workspace, &why)) throw std::invalid_argument(why);
  SimulationResult result = workspace->simulator->Run();
  if (result.summary.IsSolutionUsable()) result.sensors = ConditionSimulated(base_spec_, result.sensors);
  return result;
}

Evaluation ObjectiveFunction::Evaluate(const Eigen::VectorXd& values) const noexcept {
  return Evaluate(values, nullptr);
}

Evaluation ObjectiveFunction::Evaluate(const Eigen::VectorXd& values,
                                       EvaluationWorkspace* workspace) const noexcept {
  // The evaluation boundary: nothing may leave it as an exception (NLopt's C
  // callback and OpenMP regions call it). A failed point keeps the reason.
  Evaluation result;
  auto failed = [&](const char* prefix, const char* reason) noexcept {
    result.terms = TermValues{};
    result.terms.failed = true;
    try {
      result.terms.failure = std::string(prefix) + reason;
    } catch (...) {  // no memory for the reason: the point still fails
    }
  };
  try {
    std::unique_ptr<EvaluationWorkspace> local;
    if (workspace == nullptr) {
      local = std::make_unique<EvaluationWorkspace>();
      workspace = local.get();
    }
    EvaluateOrThrow(values, workspace, &result);
  } catch (const std::invalid_argument& e) {
    failed("", e.what());  // e.g. a value the case rejects, a zero response
  } catch (const std::bad_alloc&) {
    failed("out of memory during the evaluation", "");
  } catch (const std::exception& e) {
    failed("evaluation failed: ", e.what());
  } catch (...) {
    failed("evaluation failed: unknown exception", "");
  }
  try {
    result.values.resize(options_.weightings.size());
    for (std::size_t k = 0; k < result.values.size(); ++k) {
      result.values[k] = result.terms.Combine(options_.weightings[k].weights, options_.failure_value);
    }
    // A weighted sum that is not finite (a weight of 1e308 overflows it) is
    // a failure with its reason, not a usable point of value failure_value.
    const double infinity = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < result.values.size() && !result.terms.failed; ++k) {
      if (!std::isfinite(result.terms.Combine(options_.weightings[k].weights, infinity))) {
        const TermValues& t = result.terms;
        result.terms.failed = true;
        result.terms.failure = "weighting " + options_.weightings[k].name + " (" +
                               options_.weightings[k].weights.ToString() +
                               "): the weighted sum is not finite (dU " + ToText(t.u) + ", dS " +
                               ToText(t.s) + ", dV " + ToText(t.v) + ", dIF " + ToText(t.f) + ")";
        for (double& value : result.values) value = options_.failure_value;
      }
    }
  } catch (...) {  // no memory for the values
    result.values.clear();
    result.terms.failed = true;
  }
  return result;
}

// The workspace's simulator at `values`: a kDocument parameter rebuilds the
// case, a typed one invalidates only what it changes (Simulator::Set).
bool ObjectiveFunction::PrepareSimulator(const Eigen::VectorXd& values, EvaluationWorkspace* workspace,
                                         std::string* why) const {
  EvaluationWorkspace& w = *workspace;
  if (w.owner != id_) {  // a workspace of another objective: start afresh
    w = EvaluationWorkspace{};
    w.owner = id_;
  }
  if (has_document_parameters_) {
    Eigen::VectorXd document_values = values;
    for (int i = 0; i < parameter_count(); ++i) {
      if (bindings_[i].typed()) document_values[i] = 0.0;
    }
    if (!w.simulator || w.document_values.size() != values.size() ||
        w.document_values != document_values) {
      CaseSpec spec = DocumentSpecAt(values);
      w.document_values.resize(0);  // until the new case is in place
      if (w.simulator) {
        w.simulator->Reset(std::move(spec));
      } else {
        w.simulator = std::make_unique<Simulator>(std::move(spec));
      }
      w.document_values = document_values;
    }
  } else if (!w.simulator) {
    w.simulator = std::make_unique<Simulator>(base_spec_);
  }
  for (int i = 0; i < parameter_count(); ++i) {
    if (!bindings_[i].typed()) continue;
    if (!w.simulator->Set(bindings_[i], parameters_[i].scale * values[i], why)) return false;
  }
  return true;
}

void ObjectiveFunction::EvaluateOrThrow(const Eigen::VectorXd& values, EvaluationWorkspace* workspace,
                                        Evaluation* result) const {
  TermValues& terms = result->terms;
  auto fail = [&terms](std::string why) {
    terms.failed = true;
    terms.failure = std::move(why);
  };
  if (values.size() != parameter_count()) {
    return fail("parameter values: expected " + ToText(parameter_count()) + " values, got " +
                ToText(values.size()));
  }
  EvaluationWorkspace& w = *workspace;
  if (std::string why; !PrepareSimulator(values, &w, &why)) return fail(std::move(why));
  // The measured record's conditioning ([data] detrend, filter), applied alike
  // to the simulated one (recording.hpp). Without it the POD reads the
  // simulator's recording in place (RunInPlace: no copy of the record).
  const bool condition = !base_spec_.data.conditioning.IsIdentity();
  SimulationResult conditioned;
  if (condition) {
    conditioned = w.simulator->Run();
    if (!conditioned.summary.IsSolutionUsable()) return fail(conditioned.summary.message);
    conditioned.sensors = ConditionSimulated(base_spec_, conditioned.sensors);
  } else {
    const SimulationSummary& summary = w.simulator->RunInPlace();
    if (!summary.IsSolutionUsable()) return fail(summary.message);
  }
  if (!w.pod) {
    // V after the alignment, of the compared modes only (1 of 6 on the
    // reference beam; all six and their flips were 5 % of an evaluation).
    PodOptions options = ResponsePodOptions();
    options.compute_time_modes = false;
    w.pod = std::make_unique<PodSolver>(options);
  }
  if (condition) {
    w.pod->Compute(conditioned.sensors);
  } else {
    w.pod->ComputeFromSamples(w.simulator->sensor_values());
  }
  w.pod->SwapResult(&w.pod_result);  // no copy; the solver refills the old buffers next time
  PodResult& pod = w.pod_result;
  result->pod_method = pod.method;
  if (pod.IsDegenerate()) return fail("simulated response: " + pod.message);  // e.g. no excitation
  AlignToReference(measured_pod_, &pod, &w.alignment);

  const int k = compared_modes_;
  if (needed_.v != 0 || needed_.f != 0) w.pod->TimeModes(pod, k, &w.time_modes);
  const Eigen::MatrixXd& v = w.time_modes;
  const PodResult& m = measured_pod_;
  if (needed_.u != 0) terms.u = (pod.poms.leftCols(k) - m.poms.leftCols(k)).squaredNorm();
  if (needed_.s != 0) {
    Eigen::ArrayXd diff = pod.singular_values.head(k).array() - m.singular_values.head(k).array();
    if (options_.relative_sigma) diff /= m.singular_values.head(k).array();
    terms.s = diff.square().sum();
  }
  if (needed_.v != 0) terms.v = (v - m.time_modes.leftCols(k)).squaredNorm();
  if (needed_.f != 0) {
    if (static_cast<int>(measured_ridges_.size()) != k) {
      return fail("the measured ridges were not prepared");  // an invariant of the constructor
    }
    if (w.mode_ridges.size() != static_cast<std::size_t>(k)) {
      w.mode_ridges.clear();
      for (int mode = 0; mode < k; ++mode) {
        w.mode_ridges.push_back(std::make_unique<wavelet::RidgeFrequencyEstimator>(mode_ridge_options_[mode]));
      }
    }
    double total = 0.0;
    for (int mode = 0; mode < k; ++mode) {
      wavelet::RidgeFrequencyEstimator& estimator = *w.mode_ridges[mode];
      const wavelet::RidgeTrack& sim_track = estimator.Estimate(v.col(mode), measured_.step_s());
      const wavelet::RidgeTrack& meas_track = measured_ridges_[mode];
      if (sim_track.size() != meas_track.size()) {
        return fail("the simulated ridge of mode " + ToText(mode + 1) + " has " +
                    ToText(sim_track.size()) + " samples, the measured one " + ToText(meas_track.size()));
      }
      double sum = 0.0;
      int count = 0;
      for (Eigen::Index j = 0; j < sim_track.size(); ++j) {
        if (!sim_track.inside_coi[j] || !meas_track.inside_coi[j]) continue;
        const double rel = (sim_track.frequency_Hz[j] - meas_track.frequency_Hz[j]) / meas_track.frequency_Hz[j];
        sum += rel * rel;
        ++count;
      }
      if (count == 0) {
        return fail("no ridge sample of mode " + ToText(mode + 1) + " inside the cone of influence");
      }
      total += sum * estimator.scalogram().decimation;
    }
    terms.f = total;
  }
}

}  // namespace podid::ident
