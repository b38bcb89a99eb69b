#include "podid/ident/objective.hpp"

#include <cmath>
#include <new>
#include <sstream>
#include <utility>

#include "podid/core/error.hpp"

namespace podid::ident {
namespace {

PodOptions MeasuredPodOptions() {
  PodOptions options;  // all modes, so that swapped modes can be matched by MAC
  options.remove_mean = true;
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
  ThrowInvalid("objective", "one of full, time-free, wavelet", "\"" + std::string(name) + "\"");
}

ObjectiveWeights ObjectiveWeights::Parse(std::string_view terms, std::string_view weights) {
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
      ThrowInvalid("--weights", ToText(names.size()) + " weights (one per term of --terms)",
                   ToText(w.size()) + " (\"" + std::string(weights) + "\")");
    }
    for (std::size_t i = 0; i < w.size(); ++i) {
      const double value = ParseNumber(w[i], "--weights", "non-negative numbers");
      if (!(value >= 0)) ThrowInvalid("--weights", "non-negative numbers", "\"" + w[i] + "\"");
      values[i] = value;
    }
  }
  ObjectiveWeights result{0.0, 0.0, 0.0, 0.0};
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string& n = names[i];
    if (n == "U") result.u = values[i];
    else if (n == "S") result.s = values[i];
    else if (n == "V") result.v = values[i];
    else if (n == "IF") result.f = values[i];
    else ThrowInvalid("--terms", "a list of U, S, V, IF", "\"" + n + "\"");
  }
  if (result.u == 0 && result.s == 0 && result.v == 0 && result.f == 0) {
    ThrowInvalid("--terms/--weights", "at least one term with a positive weight", "none");
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

bool ObjectiveOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (modes < 1) return fail("modes: expected >= 1, got " + ToText(modes));
  if (!(failure_value > 0 && std::isfinite(failure_value)))
    return fail("failure_value: expected a finite value > 0, got " + ToText(failure_value));
  std::string ridge_why;
  if (!ridge.IsValid(&ridge_why)) return fail("ridge: " + ridge_why);
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

ObjectiveFunction::ObjectiveFunction(const CaseDocument& case_document, const TimeSeries& measured,
                                     const ObjectiveOptions& options, bool weights_needing_ridges,
                                     std::vector<ParameterSpec> parameters)
    : document_(case_document), measured_(measured), options_(options) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("objective options: " + why);
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

  const CaseSpec spec = document_.ToSpec();
  const std::vector<std::string> channels = spec.sensors.ChannelNames();
  if (channels != measured.channel_names) {
    ThrowInvalid("measured data channels", JoinNames(channels) + " (the sensors of " + source + ")",
                 JoinNames(measured.channel_names));
  }
  if (options.modes > static_cast<int>(channels.size())) {
    ThrowInvalid("modes", "at most the number of sensors, " + ToText(channels.size()),
                 ToText(options.modes));
  }

  parameters_ = parameters.empty() ? spec.parameters : std::move(parameters);
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
  }
  // Setting every parameter at its start validates the keys against the case.
  try {
    SpecAt(StartValues());
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("identification parameters: ") + e.what());
  }

  measured_pod_ = ComputePod(measured_, MeasuredPodOptions());
  if (measured_pod_.IsDegenerate()) {
    ThrowInvalid("measured data", "a record with a nonzero POD", measured_pod_.message);
  }

  if (weights_needing_ridges) {
    // The record must hold the cone of influence at the lowest frequency:
    // 2 * coi_factor * sqrt(2) s(f_min).
    const auto& cwt = options_.ridge.cwt;
    const double s_min = cwt.wavelet.FrequencyToScale_s(cwt.frequencies.min_frequency_Hz);
    const double needed = 2.0 * cwt.coi_factor * wavelet::MorletWavelet::ConeOfInfluence_s(s_min);
    if (duration <= needed) {
      ThrowInvalid("measured data", "a record longer than " + ToText(needed) +
                       " s for the wavelet objective's lowest frequency " +
                       ToText(cwt.frequencies.min_frequency_Hz) +
                       " Hz (its cone of influence; raise --fmin or give a longer record)",
                   ToText(duration) + " s");
    }
    wavelet::RidgeFrequencyEstimator estimator(options_.ridge);
    for (int k = 0; k < options_.modes; ++k) {
      measured_ridges_.push_back(estimator.Estimate(measured_pod_.time_modes.col(k), step));
      if (measured_ridges_.back().InsideCoiCount() == 0) {
        ThrowInvalid("measured data", "a ridge of mode " + ToText(k + 1) +
                         " inside the cone of influence", "none (record too short for the band)");
      }
    }
  }
}

Eigen::VectorXd ObjectiveFunction::StartValues() const {
  Eigen::VectorXd values(parameter_count());
  for (int i = 0; i < parameter_count(); ++i) values[i] = parameters_[i].start;
  return values;
}

CaseSpec ObjectiveFunction::SpecAt(const Eigen::VectorXd& values) const {
  PODID_CHECK(values.size() == parameter_count());
  CaseDocument document = document_;
  for (int i = 0; i < parameter_count(); ++i) {
    document.SetNumber(parameters_[i].key, parameters_[i].scale * values[i]);
  }
  return document.ToSpec();
}

SimulationResult ObjectiveFunction::SimulateAt(const Eigen::VectorXd& values) const {
  SimulateOptions options;
  options.add_noise = false;
  return Simulate(SpecAt(values), options);
}

TermValues ObjectiveFunction::Evaluate(const Eigen::VectorXd& values,
                                       const ObjectiveWeights& weights) const {
  EvaluationWorkspace workspace;
  return Evaluate(values, weights, &workspace);
}

TermValues ObjectiveFunction::Evaluate(const Eigen::VectorXd& values, const ObjectiveWeights& weights,
                                       EvaluationWorkspace* workspace) const {
  PODID_CHECK(workspace != nullptr);
  // The evaluation boundary: nothing may leave it as an exception (NLopt's C
  // callback and OpenMP regions call it). A failed point keeps the reason.
  auto failed = [](const char* prefix, const char* reason) noexcept {
    TermValues terms;
    terms.failed = true;
    try {
      terms.failure = std::string(prefix) + reason;
    } catch (...) {  // no memory for the reason: the point still fails
    }
    return terms;
  };
  try {
    return EvaluateOrThrow(values, weights, workspace);
  } catch (const std::invalid_argument& e) {
    return failed("", e.what());  // e.g. a value the case rejects, a zero response
  } catch (const std::bad_alloc&) {
    return failed("out of memory during the evaluation", "");
  } catch (const std::exception& e) {
    return failed("evaluation failed: ", e.what());
  } catch (...) {
    return failed("evaluation failed: unknown exception", "");
  }
}

TermValues ObjectiveFunction::EvaluateOrThrow(const Eigen::VectorXd& values,
                                              const ObjectiveWeights& weights,
                                              EvaluationWorkspace* workspace) const {
  TermValues terms;
  const SimulationResult sim = SimulateAt(values);
  if (!sim.summary.IsSolutionUsable()) {
    terms.failed = true;
    terms.failure = sim.summary.message;
    return terms;
  }
  if (!workspace->pod) workspace->pod = std::make_unique<PodSolver>(MeasuredPodOptions());
  PodResult pod = workspace->pod->Compute(sim.sensors);
  if (pod.IsDegenerate()) {  // e.g. no excitation: a zero response
    terms.failed = true;
    terms.failure = "simulated response: " + pod.message;
    return terms;
  }
  AlignToReference(measured_pod_, &pod);

  const int k = options_.modes;
  const PodResult& m = measured_pod_;
  if (weights.u != 0) terms.u = (pod.poms.leftCols(k) - m.poms.leftCols(k)).squaredNorm();
  if (weights.s != 0) {
    Eigen::ArrayXd diff = pod.singular_values.head(k).array() - m.singular_values.head(k).array();
    if (options_.relative_sigma) diff /= m.singular_values.head(k).array();
    terms.s = diff.square().sum();
  }
  if (weights.v != 0) terms.v = (pod.time_modes.leftCols(k) - m.time_modes.leftCols(k)).squaredNorm();
  if (weights.f != 0) {
    if (!workspace->ridge) {
      workspace->ridge = std::make_unique<wavelet::RidgeFrequencyEstimator>(options_.ridge);
    }
    double total = 0.0;
    for (int mode = 0; mode < k; ++mode) {
      const wavelet::RidgeTrack& sim_track =
          workspace->ridge->Estimate(pod.time_modes.col(mode), measured_.step_s());
      const wavelet::RidgeTrack& meas_track = measured_ridges_[mode];
      PODID_CHECK(sim_track.size() == meas_track.size());
      double sum = 0.0;
      int count = 0;
      for (Eigen::Index j = 0; j < sim_track.size(); ++j) {
        if (!sim_track.inside_coi[j] || !meas_track.inside_coi[j]) continue;
        const double rel = (sim_track.frequency_Hz[j] - meas_track.frequency_Hz[j]) / meas_track.frequency_Hz[j];
        sum += rel * rel;
        ++count;
      }
      if (count == 0) {
        terms.failed = true;
        terms.failure = "no ridge sample of mode " + ToText(mode + 1) + " inside the cone of influence";
        return terms;
      }
      total += sum * workspace->ridge->scalogram().decimation;
    }
    terms.f = total;
  }
  return terms;
}

}  // namespace podid::ident
