// podid identify: minimise an objective over the case's parameters.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "ident_common.hpp"
#include "plot.hpp"
#include "podid/core/error.hpp"
#include "podid/core/io.hpp"
#include "podid/core/quantity_check.hpp"
#include "podid/ident/identify.hpp"

namespace podid::cli {
namespace {

struct IdentifyArguments {
  ObjectiveArguments objective;
  std::string preset = "full";
  std::string terms, weights;
  std::string algorithm = "LN_BOBYQA";
  std::string local_algorithm = "LN_BOBYQA";
  int multistart = 1;
  int max_evaluations = 500;
  double xtol_rel = 1e-6;
  std::uint64_t seed = 1;
  std::string json;
  std::string plot_dir;
  bool report = false;
};

nlohmann::json ParametersJson(const std::vector<std::string>& names, const Eigen::VectorXd& values) {
  nlohmann::json j = nlohmann::json::object();
  for (std::size_t i = 0; i < names.size(); ++i) j[names[i]] = values[static_cast<Eigen::Index>(i)];
  return j;
}

nlohmann::json NumberOrNull(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

void WriteJson(const std::string& path, const ident::IdentifySummary& s) {
  nlohmann::json j;
  j["parameters"] = ParametersJson(s.parameter_names, s.parameters);
  j["initial_parameters"] = ParametersJson(s.parameter_names, s.initial_parameters);
  j["objective"] = NumberOrNull(s.final_objective);
  j["initial_objective"] = NumberOrNull(s.initial_objective);
  j["terms"] = {{"U", NumberOrNull(s.final_terms.u)},
                {"S", NumberOrNull(s.final_terms.s)},
                {"V", NumberOrNull(s.final_terms.v)},
                {"IF", NumberOrNull(s.final_terms.f)}};
  j["objective_terms"] = s.objective;
  j["algorithm"] = s.algorithm;
  j["evaluations"] = s.evaluations;
  j["failed_evaluations"] = s.failed_evaluations;
  j["starts"] = s.starts;
  j["termination"] = ident::ToString(s.termination);
  j["usable"] = s.IsSolutionUsable();
  j["message"] = s.message;
  j["wall_time_s"] = s.wall_time_s;
  nlohmann::json history = nlohmann::json::array();
  for (const ident::IterationRecord& r : s.history) {
    history.push_back({{"start", r.start + 1},
                       {"evaluation", r.evaluation},
                       {"parameters", ParametersJson(s.parameter_names, r.parameters)},
                       {"objective", NumberOrNull(r.objective)},
                       {"best", NumberOrNull(r.best_objective)},
                       {"failed", r.failed}});
  }
  j["history"] = history;
  WriteFileAtomically(path, [&](std::ostream& os) { os << j.dump(2) << '\n'; });
}

// The paper's fig. 2: measured vs simulated signals at the start and at the
// optimum, the convergence history, and with a wavelet term the ridges.
void WritePlots(const std::string& dir, const ident::ObjectiveFunction& objective,
                const ident::IdentifySummary& s, bool ridges) {
  std::filesystem::create_directories(dir);
  const TimeSeries& measured = objective.measured();
  const int channel = static_cast<int>(measured.channels()) - 1;
  const std::string name = measured.channel_names[channel];
  TimeSeries signals;
  signals.time_s = measured.time_s;
  signals.channel_names = {name + "_measured", name + "_start", name + "_optimum"};
  signals.values.resize(measured.samples(), 3);
  signals.values.col(0) = measured.values.col(channel);
  const SimulationResult at_start = objective.SimulateAt(s.initial_parameters);
  const SimulationResult at_optimum = objective.SimulateAt(s.parameters);
  for (const auto& [col, sim] : {std::pair{1, &at_start}, std::pair{2, &at_optimum}}) {
    signals.values.col(col).setConstant(std::numeric_limits<double>::quiet_NaN());
    const Eigen::Index rows = std::min(sim->sensors.samples(), measured.samples());
    signals.values.col(col).head(rows) = sim->sensors.values.col(channel).head(rows);
  }
  WriteCsv(dir + "/signals.csv", signals);
  const std::string pname = s.parameter_names.front();
  auto label = [&](const Eigen::VectorXd& p) { return pname + " = " + ToText(p[0]); };
  PlotLines(dir + "/fig2a_start.png", {"Measured vs simulated at the start (" + label(s.initial_parameters) + ")", "t (s)", name + " (m)"},
            {{"measured", measured.time_s, signals.values.col(0)},
             {"simulated", measured.time_s, signals.values.col(1)}});
  PlotLines(dir + "/fig2b_optimum.png", {"Measured vs simulated at the optimum (" + label(s.parameters) + ")", "t (s)", name + " (m)"},
            {{"measured", measured.time_s, signals.values.col(0)},
             {"simulated", measured.time_s, signals.values.col(2)}});
  Eigen::VectorXd evaluation(static_cast<Eigen::Index>(s.history.size())), best(evaluation.size()), value(evaluation.size());
  for (Eigen::Index i = 0; i < evaluation.size(); ++i) {
    evaluation[i] = static_cast<double>(i + 1);
    value[i] = s.history[i].objective;
    best[i] = s.history[i].best_objective;
  }
  PlotLines(dir + "/convergence.png", {"Objective per evaluation", "evaluation", "F", true},
            {{"F", evaluation, value}, {"best so far", evaluation, best}});
  if (ridges && !objective.measured_ridges().empty()) {
    wavelet::RidgeFrequencyEstimator estimator(objective.mode_ridge_options(0));
    const PodResult& pod = objective.measured_pod();
    const wavelet::RidgeTrack& measured_ridge = estimator.Estimate(pod.time_modes.col(0), measured.step_s());
    const wavelet::Scalogram& sc = estimator.scalogram();
    Eigen::MatrixXd magnitude = sc.coefficients.cwiseAbs();
    PlotHeatMap(dir + "/ridge.png", {"|W| of the measured V_1 with its ridge", "t (s)", "f (Hz)"}, "|W|",
                sc.time_s, sc.frequencies_Hz, magnitude,
                {{"measured ridge", measured_ridge.time_s, measured_ridge.frequency_Hz}});
  }
}

}  // namespace

void AddIdentifyCommand(CLI::App& app) {
  auto args = std::make_shared<IdentifyArguments>();
  CLI::App* command = app.add_subcommand(
      "identify",
      "Identify the case's [[identify.parameter]]s from measured data by minimising the\n"
      "difference between measured and simulated POD (Lenaerts et al., eq. 19 and sec. 4.3).\n"
      "Exit status 2 if no usable point was found.");
  args->objective.AddTo(*command);
  command->add_option("--objective", args->preset, "Preset: full (U+S+V), time-free (U+S), wavelet (U+S+IF)")
      ->capture_default_str();
  command->add_option("--terms", args->terms, "Custom terms instead of a preset, e.g. U,S,IF");
  command->add_option("--weights", args->weights, "Weights of --terms, e.g. 1,1,0.5 (default all 1)");
  command->add_option("--algorithm", args->algorithm,
                      "NLopt algorithm: LN_BOBYQA, LN_NELDERMEAD, LN_SBPLX, LN_COBYLA, GN_DIRECT_L, "
                      "GN_CRS2_LM, GN_ISRES, GN_MLSL_LDS")
      ->capture_default_str();
  command->add_option("--local-algorithm", args->local_algorithm, "Local optimiser of GN_MLSL_LDS")
      ->capture_default_str();
  command->add_option("--multistart", args->multistart,
                      "Local algorithms: number of starts (the start + Latin hypercube points), at most 10000")
      ->capture_default_str()->check(IntegerIn(1, ident::kMaxMultistart));
  command->add_option("--max-evaluations", args->max_evaluations, "Evaluation budget per start, at most 1000000 (and 1000000 times --multistart in all)")
      ->capture_default_str()->check(IntegerIn(1, ident::kMaxEvaluations));
  command->add_option("--xtol", args->xtol_rel, "Relative parameter tolerance")->capture_default_str();
  command->add_option("--seed", args->seed, "Seed of the Latin hypercube and random algorithms")
      ->capture_default_str();
  command->add_option("--json", args->json, "Write the result and history as JSON");
  command->add_option("--plot-dir", args->plot_dir,
                      "Write signals.csv and plots (fig2a_start.png, fig2b_optimum.png, convergence.png, "
                      "ridge.png) to this folder");
  command->add_flag("--report", args->report, "Print the full report");
  command->callback([args] {
    args->objective.PrepareData();  // -m and the data options become [data] keys
    std::vector<NamedFile> inputs = CaseInputFiles(args->objective.input);
    std::vector<NamedFile> outputs = {{"--json", args->json}};
    if (!args->plot_dir.empty()) {
      CheckOutputFolder({"--plot-dir", args->plot_dir});
      // An existing folder's files must not be inputs (a new one has none).
      if (std::filesystem::is_directory(args->plot_dir)) {
        for (const char* name : {"signals.csv", "fig2a_start.png", "fig2b_optimum.png",
                                 "convergence.png", "ridge.png"}) {
          outputs.push_back({"--plot-dir", args->plot_dir + "/" + name});
        }
      }
    }
    CheckOutputs(inputs, outputs);
    const ident::ObjectiveWeights weights = WeightsFrom(args->preset, args->terms, args->weights);
    const auto objective = args->objective.Build({{weights.ToString(), weights}});
    ident::IdentifyOptions options;
    options.algorithm = ident::ParseAlgorithm(args->algorithm);
    options.local_algorithm = ident::ParseAlgorithm(args->local_algorithm);
    options.start = args->objective.Start(*objective);
    options.multistart = args->multistart;
    options.max_evaluations = args->max_evaluations;
    options.xtol_rel = args->xtol_rel;
    options.seed = args->seed;
    const ident::IdentifySummary summary = ident::Identify(*objective, options);
    std::printf("%s\n", summary.BriefReport().c_str());
    // Measured accelerations declared as displacements (or the reverse):
    // the spectra of the record and of the simulation at the result tell.
    if (summary.parameters.size() == objective->parameter_count()) {
      const SimulationResult at = objective->SimulateAt(summary.parameters);
      if (at.summary.IsSolutionUsable() &&
          at.sensors.channels() == objective->measured().channels()) {
        const QuantityCheck q = CheckMeasuredQuantity(
            objective->measured(), at.sensors,
            objective->SpecAt(summary.parameters).sensors.quantity);
        if (q.mismatch) std::fprintf(stderr, "podid: warning: %s\n", q.message.c_str());
      }
    }
    if (args->report) std::printf("%s", summary.FullReport().c_str());
    if (!args->json.empty()) WriteJson(args->json, summary);
    if (!args->plot_dir.empty()) {
      WritePlots(args->plot_dir, *objective, summary, weights.NeedsRidges());
      std::printf("plots and signals.csv written to %s/\n", args->plot_dir.c_str());
    }
    if (!summary.IsSolutionUsable()) throw CommandFailed("identify: " + summary.message);
  });
}

}  // namespace podid::cli
