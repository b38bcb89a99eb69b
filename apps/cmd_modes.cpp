// podid modes: linear natural frequencies and damping ratios of a case.
#include <cstdio>
#include <memory>
#include <string>

#include "cli_common.hpp"
#include "commands.hpp"
#include "podid/core/beam_model.hpp"

namespace podid::cli {
namespace {

// The linear modes do not depend on the excitation: a force or base table
// set to type "none" (its other keys are then ignored) reads no force file
// and needs no [data] file for a "channel" force.
void IgnoreExcitation(CaseDocument& document) {
  if (document.Has("force.type")) document.Set("force.type", "\"none\"");
  for (int i = 0; document.Has("force." + std::to_string(i) + ".type"); ++i) {
    document.Set("force." + std::to_string(i) + ".type", "\"none\"");
  }
  if (document.Has("base.type")) document.Set("base.type", "\"none\"");
}

}  // namespace

void AddModesCommand(CLI::App& app) {
  auto args = std::make_shared<CaseArguments>();
  auto count = std::make_shared<int>(0);
  CLI::App* command = app.add_subcommand("modes",
                                         "Print the natural frequencies (Hz) and damping ratios of "
                                         "the case's linear model (beam or imported "
                                         "matrices); the excitation ([force], [base]) is not read");
  args->AddTo(*command);
  command->add_option("-n,--count", *count, "Number of modes to print, the lowest (default: all, by the dense solver)")
      ->check(IntegerIn(0, kMaxModesPrinted));
  command->callback([args, count] {
    CaseDocument document = args->Load();
    IgnoreExcitation(document);
    const CaseSpec spec = document.ToSpec();
    const BeamModel model = BeamModel::Build(spec);
    // Only the modes printed: a large model's lowest modes by the sparse solver.
    const ModalAnalysis modes =
        *count > 0 ? model.Modes(std::min(*count, model.dofs())) : model.Modes();
    const int n = static_cast<int>(modes.frequencies_Hz.size());
    if (spec.model.type == ModelType::kMatrices) {
      std::printf("%s: imported matrices, %d dofs\n", spec.source.c_str(), model.dofs());
    } else {
      std::printf("%s: %d Euler-Bernoulli elements, %d dofs\n", spec.source.c_str(), spec.beam.elements,
                  model.dofs());
    }
    if (spec.damping.type == DampingType::kRayleigh) {
      std::printf("Rayleigh damping: alpha = %.6g 1/s, beta = %.6g s\n", model.rayleigh_alpha_per_s(),
                  model.rayleigh_beta_s());
    }
    std::printf("%4s  %14s  %14s\n", "mode", "frequency_Hz", "damping_ratio");
    for (int k = 0; k < n; ++k) {
      std::printf("%4d  %14.4f  %14.6f\n", k + 1, modes.frequencies_Hz[k], modes.damping_ratios[k]);
    }
  });
}

}  // namespace podid::cli
