#include "ident_common.hpp"

#include <cstdio>

#include "podid/core/error.hpp"
#include "podid/core/io.hpp"

namespace podid::cli {

void ObjectiveArguments::AddTo(CLI::App& command) {
  input.AddTo(command);
  command.add_option("-m,--measured", measured, "Measured time histories (.csv, .mat or .uff)")->required();
  measured_reading.AddTo(command);
  command.add_option("--modes", modes, "Number of leading POMs in the objective (K)")->capture_default_str()
      ->check(IntegerIn(1, kMaxObjectiveModes));
  command.add_flag("--raw-sigma", raw_sigma,
                   "Compare raw singular values (eq. 19) instead of relative ones");
  command.add_option("--fmin", fmin_Hz, "Lowest ridge frequency of the wavelet term (Hz)")->capture_default_str();
  command.add_option("--fmax", fmax_Hz, "Highest ridge frequency of the wavelet term (Hz)")->capture_default_str();
  command.add_option("--penalty", penalty_s, "Ridge penalty of the wavelet term (s)")->capture_default_str();
  command.add_option("--start", starts, "Start value of a parameter, e.g. --start knl=40 (repeatable)")
      ->type_name("NAME=VALUE");
}

std::unique_ptr<ident::ObjectiveFunction> ObjectiveArguments::Build(bool needs_ridges) const {
  const CaseDocument document = input.Load();
  const TimeSeries data = measured_reading.Read(measured);
  ident::ObjectiveOptions options;
  options.modes = modes;
  options.relative_sigma = !raw_sigma;
  options.ridge.cwt.frequencies.min_frequency_Hz = fmin_Hz;
  options.ridge.cwt.frequencies.max_frequency_Hz = fmax_Hz;
  options.ridge.ridge.penalty_s = penalty_s;
  auto objective = std::make_unique<ident::ObjectiveFunction>(document, data, options, needs_ridges);
  for (const std::string& note : objective->notes()) std::fprintf(stderr, "podid: note: %s\n", note.c_str());
  return objective;
}

Eigen::VectorXd ObjectiveArguments::Start(const ident::ObjectiveFunction& objective) const {
  Eigen::VectorXd start = objective.StartValues();
  for (const auto& [name, value_text] : ParseSetArguments(starts)) {
    int index = -1;
    std::string names;
    for (int i = 0; i < objective.parameter_count(); ++i) {
      if (objective.parameters()[i].name == name) index = i;
      names += (i ? ", " : "") + objective.parameters()[i].name;
    }
    if (index < 0) ThrowInvalid("--start " + name, "a parameter name (" + names + ")", "\"" + name + "\"");
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

ident::ObjectiveWeights WeightsFrom(const std::string& objective, const std::string& terms,
                                    const std::string& weights) {
  if (!terms.empty()) return ident::ObjectiveWeights::Parse(terms, weights);
  if (!weights.empty()) ThrowInvalid("--weights", "--terms with it", "--weights alone");
  return ident::ObjectiveWeights::Preset(objective);
}

}  // namespace podid::cli
