// podid simulate: integrate a case and write its sensor histories.
#include <cstdio>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "podid/core/io.hpp"
#include "podid/core/simulate.hpp"

namespace podid::cli {

namespace {
struct SimulateArguments {
  CaseArguments input;
  std::string output;
  bool no_noise = false;
  bool report = false;
};
}  // namespace

void AddSimulateCommand(CLI::App& app) {
  auto args = std::make_shared<SimulateArguments>();
  CLI::App* command = app.add_subcommand(
      "simulate",
      "Integrate the case with Newmark's scheme and write the sensor histories as CSV\n"
      "(columns t,w1..wN as in the reference data). Exit status 2 if the integration\n"
      "fails; the history up to the failure is still written.");
  args->input.AddTo(*command);
  command
      ->add_option("-o,--output", args->output,
                   "Output CSV (default: <case name>_simulated.csv in the current folder)")
      ->check(NonEmptyPath());
  command->add_flag("--no-noise", args->no_noise, "Ignore the case's [noise] table");
  command->add_flag("--report", args->report, "Print the full simulation report");
  command->callback([args] {
    const std::string output =
        args->output.empty() ? DefaultOutput(args->input.path, "_simulated.csv") : args->output;
    CheckOutputs(CaseInputFiles(args->input), {{"-o", output}});
    const CaseSpec spec = args->input.Load().ToSpec();
    SimulateOptions options;
    options.add_noise = !args->no_noise;
    const SimulationResult result = Simulate(spec, options);
    if (result.summary.termination == SimulationTermination::kStaticSolveFailed) {
      throw CommandFailed("simulate: initial state: " + result.summary.message);
    }
    if (result.summary.step_error_estimate > kMaxStepRelativeError) {
      // A warning, not a failure: the estimate covers every dof (newmark.hpp).
      std::fprintf(
          stderr,
          "warning: simulate: the step matrix M / (beta dt^2) + gamma C / (beta dt) + K is "
          "ill-conditioned: one solve's estimated relative error is %.2g, above %.0e; some "
          "dofs may be inaccurate (element lengths or stiffnesses many orders apart?)\n",
          result.summary.step_error_estimate, kMaxStepRelativeError);
    }
    WriteCsv(output, result.sensors);
    std::printf("%s -> %s (%ld samples x %ld channels)\n", result.summary.BriefReport().c_str(),
                output.c_str(), static_cast<long>(result.sensors.samples()),
                static_cast<long>(result.sensors.channels()));
    if (args->report) std::printf("%s", result.summary.FullReport().c_str());
    if (!result.summary.IsSolutionUsable()) {
      throw CommandFailed("simulate: " + result.summary.message);
    }
  });
}

}  // namespace podid::cli
