// podid identify: minimise an objective over the case's parameters.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "ident_common.hpp"
#include "mpi_session.hpp"
#include "plot.hpp"
#include "podid/core/error.hpp"
#include "podid/core/io.hpp"
#include "podid/core/quantity_check.hpp"
#include "podid/ident/identify.hpp"
#include "podid/ident/objective_uncertainty.hpp"

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
  int threads = 0;
  double xtol_rel = 1e-6;
  std::uint64_t seed = 1;
  std::string json;
  std::string plot_dir;
  bool report = false;
};

constexpr const char* kPlotFiles[] = {"signals.csv", "fig2a_start.png", "fig2b_optimum.png",
                                      "convergence.png", "ridge.png"};

// True when `json` names a file directly in `plot_dir`, a folder that does not
// exist yet; refuses a name that is one of the plot files.
bool JsonInNewPlotDir(const std::string& json, const std::string& plot_dir) {
  namespace fs = std::filesystem;
  if (json.empty() || plot_dir.empty() || fs::exists(plot_dir)) return false;
  const fs::path file = fs::absolute(json).lexically_normal();
  const fs::path folder = (fs::absolute(plot_dir) / "").lexically_normal();
  if (file.parent_path() / "" != folder) return false;
  for (const char* name : kPlotFiles) {
    if (file.filename() == name) {
      ThrowInvalid("--json", "a file other than --plot-dir's " + std::string(name),
                   "\"" + json + "\", the same file");
    }
  }
  return true;
}

nlohmann::json ParametersJson(const std::vector<std::string>& names, const Eigen::VectorXd& values) {
  nlohmann::json j = nlohmann::json::object();
  for (std::size_t i = 0; i < names.size(); ++i) j[names[i]] = values[static_cast<Eigen::Index>(i)];
  return j;
}

nlohmann::json NumberOrNull(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

void WriteJson(const std::string& path,
               const ident::IdentifySummary& s,
               const ident::ObjectiveFunction& objective,
               OutputBatch* batch) {
  nlohmann::json j;
  j["parameters"] = ParametersJson(s.parameter_names, s.parameters);
  j["initial_parameters"] = ParametersJson(s.parameter_names, s.initial_parameters);
  j["objective"] = NumberOrNull(s.final_objective);
  j["initial_objective"] = NumberOrNull(s.initial_objective);
  j["terms"] = {{"U", NumberOrNull(s.final_terms.u)},
                {"S", NumberOrNull(s.final_terms.s)},
                {"V", NumberOrNull(s.final_terms.v)},
                {"IF", NumberOrNull(s.final_terms.f)}};
  // Each weighted term's share of F, at the start and at the optimum: one term
  // swamping the others shows here (issue 12 item 5).
  auto contributions = [&s](const ident::TermValues& t) {
    nlohmann::json out;
    const double total = t.Combine(s.weights, std::numeric_limits<double>::quiet_NaN());
    const std::pair<const char*, std::pair<double, double>> terms[] = {
        {"U", {s.weights.u, t.u}}, {"S", {s.weights.s, t.s}}, {"V", {s.weights.v, t.v}}, {"IF", {s.weights.f, t.f}}};
    for (const auto& [name, wv] : terms) {
      if (wv.first == 0) continue;
      out[name] = {{"value", NumberOrNull(wv.second)},
                   {"weight", wv.first},
                   {"share", NumberOrNull(total > 0 ? wv.first * wv.second / total : NAN)}};
    }
    return out;
  };
  j["term_shares"] = {{"initial", contributions(s.initial_terms)}, {"final", contributions(s.final_terms)}};
  j["objective_terms"] = s.objective;
  if (!objective.measured_ridges().empty()) j["ridges"] = RidgesJson(objective);
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
    if (r.failed) history.back()["failure"] = r.failure;
  }
  if (s.uncertainty.usable) {
    nlohmann::json u;
    u["confidence"] = s.uncertainty.confidence;
    u["method"] = s.uncertainty.message;
    for (std::size_t k = 0; k < s.parameter_names.size(); ++k) {
      u["parameters"][s.parameter_names[k]] = {{"standard_error", s.uncertainty.standard_error[k]},
                                               {"lower", s.uncertainty.lower[k]},
                                               {"upper", s.uncertainty.upper[k]}};
      if (k < s.uncertainty.bound_notes.size() && !s.uncertainty.bound_notes[k].empty()) {
        u["parameters"][s.parameter_names[k]]["bound_note"] = s.uncertainty.bound_notes[k];
      }
    }
    nlohmann::json rows = nlohmann::json::array();
    for (Eigen::Index r = 0; r < s.uncertainty.correlation.rows(); ++r) {
      std::vector<double> row(s.uncertainty.correlation.cols());
      for (Eigen::Index c = 0; c < s.uncertainty.correlation.cols(); ++c) row[c] = s.uncertainty.correlation(r, c);
      rows.push_back(row);
    }
    u["correlation"] = rows;
    j["uncertainty"] = u;
  } else {
    j["uncertainty"] = {{"usable", false}, {"reason", s.uncertainty.message}};
  }
  j["history"] = history;
  WriteFileAtomically(
      path, [&](std::ostream& os) { os << j.dump(2) << '\n'; }, batch);
}

// The paper's fig. 2: measured vs simulated signals at the start and at the
// optimum, the convergence history, and with a wavelet term the ridges.
void WritePlots(const std::string& dir,
                const ident::ObjectiveFunction& objective,
                const ident::IdentifySummary& s,
                bool ridges,
                ident::EvaluationWorkspace* workspace,
                OutputBatch* batch) {
  batch->CreateFolders(dir);
  const TimeSeries& measured = objective.measured();
  const int channel = static_cast<int>(measured.channels()) - 1;
  const std::string name = measured.channel_names[channel];
  TimeSeries signals;
  signals.time_s = measured.time_s;
  signals.channel_names = {name + "_measured", name + "_start", name + "_optimum"};
  signals.values.resize(measured.samples(), 3);
  signals.values.col(0) = measured.values.col(channel);
  const SimulationResult at_start = objective.SimulateAt(s.initial_parameters, workspace);
  const SimulationResult at_optimum = objective.SimulateAt(s.parameters, workspace);
  for (const auto& [col, sim] : {std::pair{1, &at_start}, std::pair{2, &at_optimum}}) {
    signals.values.col(col).setConstant(std::numeric_limits<double>::quiet_NaN());
    const Eigen::Index rows = std::min(sim->sensors.samples(), measured.samples());
    signals.values.col(col).head(rows) = sim->sensors.values.col(channel).head(rows);
  }
  WriteCsv(dir + "/signals.csv", signals, batch);
  const std::string pname = s.parameter_names.front();
  auto label = [&](const Eigen::VectorXd& p) { return pname + " = " + ToText(p[0]); };
  PlotLines(dir + "/fig2a_start.png",
            {"Measured vs simulated at the start (" + label(s.initial_parameters) + ")", "t (s)",
             name + " (m)"},
            {{"measured", measured.time_s, signals.values.col(0)},
             {"simulated", measured.time_s, signals.values.col(1)}},
            batch);
  PlotLines(dir + "/fig2b_optimum.png",
            {"Measured vs simulated at the optimum (" + label(s.parameters) + ")", "t (s)",
             name + " (m)"},
            {{"measured", measured.time_s, signals.values.col(0)},
             {"simulated", measured.time_s, signals.values.col(2)}},
            batch);
  Eigen::VectorXd evaluation(static_cast<Eigen::Index>(s.history.size())), best(evaluation.size()), value(evaluation.size());
  for (Eigen::Index i = 0; i < evaluation.size(); ++i) {
    evaluation[i] = static_cast<double>(i + 1);
    value[i] = s.history[i].objective;
    best[i] = s.history[i].best_objective;
  }
  PlotLines(dir + "/convergence.png", {"Objective per evaluation", "evaluation", "F", true},
            {{"F", evaluation, value}, {"best so far", evaluation, best}}, batch);
  if (ridges && !objective.measured_ridges().empty()) {
    wavelet::RidgeFrequencyOptions plot_options = objective.mode_ridge_options(0);
    plot_options.keep_scalogram = true;  // the heat map needs |W|
    wavelet::RidgeFrequencyEstimator estimator(plot_options);
    const PodResult& pod = objective.measured_pod();
    const wavelet::RidgeTrack& measured_ridge = estimator.Estimate(pod.time_modes.col(0), measured.step_s());
    const wavelet::Scalogram& sc = estimator.scalogram();
    Eigen::MatrixXd magnitude = sc.coefficients.cwiseAbs();
    PlotHeatMap(dir + "/ridge.png", {"|W| of the measured V_1 with its ridge", "t (s)", "f (Hz)"},
                "|W|", sc.time_s, sc.frequencies_Hz, magnitude,
                {{"measured ridge", measured_ridge.time_s, measured_ridge.frequency_Hz}}, batch);
  }
}

// Under MPI each rank ran its share of the starts (s % ranks == rank): sum the
// shares' per-start results and histories (a rank leaves what it did not run
// at exactly 0, so every value arrives bit for bit) and summarise on every
// rank. Start 0, whose first failure the summary may quote, is rank 0's.
void MergeStarts(ident::IdentifySummary* summary, int parameters) {
  const std::int64_t starts = static_cast<std::int64_t>(summary->start_results.size());
  const std::int64_t p = parameters;
  const std::int64_t width = 11 + p;  // see the layout below
  std::vector<double> per_start(static_cast<std::size_t>(starts * width), 0.0);
  for (std::int64_t s = 0; s < starts; ++s) {
    const ident::StartResult& r = summary->start_results[s];
    if (!r.computed) continue;
    double* row = per_start.data() + s * width;
    row[0] = 1;
    row[1] = r.evaluations;
    row[2] = r.failed_evaluations;
    row[3] = r.best_objective;
    row[4] = r.best_parameters.size() ? 1 : 0;
    row[5] = r.best_terms.u;
    row[6] = r.best_terms.s;
    row[7] = r.best_terms.v;
    row[8] = r.best_terms.f;
    row[9] = r.best_terms.failed ? 1 : 0;
    row[10] = r.nlopt_result;
    for (std::int64_t i = 0; i < r.best_parameters.size(); ++i) row[11 + i] = r.best_parameters[i];
  }
  mpi::SumOnAll(per_start.data(), starts * width);
  // The history, start by start: offsets from the merged evaluation counts.
  std::vector<std::int64_t> offset(static_cast<std::size_t>(starts + 1), 0);
  for (std::int64_t s = 0; s < starts; ++s) {
    offset[s + 1] = offset[s] + static_cast<std::int64_t>(per_start[s * width + 1]);
  }
  const std::int64_t record_width = 5 + p;
  std::vector<double> history(static_cast<std::size_t>(offset[starts] * record_width), 0.0);
  std::vector<std::int64_t> written(static_cast<std::size_t>(starts), 0);
  for (const ident::IterationRecord& r : summary->history) {
    double* row = history.data() + (offset[r.start] + written[r.start]++) * record_width;
    row[0] = r.evaluation;
    row[1] = r.start;
    row[2] = r.objective;
    row[3] = r.best_objective;
    row[4] = r.failed ? 1 : 0;
    for (std::int64_t i = 0; i < p; ++i) row[5 + i] = r.parameters[i];
  }
  mpi::SumOnAll(history.data(), offset[starts] * record_width);

  for (std::int64_t s = 0; s < starts; ++s) {
    ident::StartResult& r = summary->start_results[s];
    const double* row = per_start.data() + s * width;
    if (r.computed) continue;  // this rank's own, already complete
    r.computed = row[0] != 0;
    r.evaluations = static_cast<int>(row[1]);
    r.failed_evaluations = static_cast<int>(row[2]);
    r.best_objective = row[3];
    r.best_parameters.resize(row[4] != 0 ? p : 0);
    for (std::int64_t i = 0; i < r.best_parameters.size(); ++i) r.best_parameters[i] = row[11 + i];
    r.best_terms.u = row[5];
    r.best_terms.s = row[6];
    r.best_terms.v = row[7];
    r.best_terms.f = row[8];
    r.best_terms.failed = row[9] != 0;
    r.nlopt_result = static_cast<int>(row[10]);
  }
  // The failure texts of the history, rank by rank ("index<TAB>text" lines;
  // the texts are one line each).
  std::string own;
  {
    std::vector<std::int64_t> seen(static_cast<std::size_t>(starts), 0);
    for (const ident::IterationRecord& r : summary->history) {
      const std::int64_t index = offset[r.start] + seen[r.start]++;
      if (!r.failed) continue;
      std::string text = r.failure;
      for (char& c : text) c = (c == '\n' || c == '\t') ? ' ' : c;
      own += std::to_string(index) + '\t' + text + '\n';
    }
  }
  std::vector<std::string> failures(static_cast<std::size_t>(offset[starts]));
  for (int rank = 0; rank < mpi::Size(); ++rank) {
    std::string blob = rank == mpi::Rank() ? own : std::string();
    mpi::Broadcast(&blob, rank);
    std::size_t pos = 0;
    while (pos < blob.size()) {
      const std::size_t tab = blob.find('\t', pos), end = blob.find('\n', pos);
      if (tab == std::string::npos || end == std::string::npos || tab > end) break;
      const std::int64_t index = std::stoll(blob.substr(pos, tab - pos));
      if (index >= 0 && index < offset[starts]) failures[index] = blob.substr(tab + 1, end - tab - 1);
      pos = end + 1;
    }
  }
  summary->history.clear();
  for (std::int64_t k = 0; k < offset[starts]; ++k) {
    const double* row = history.data() + k * record_width;
    ident::IterationRecord r;
    r.evaluation = static_cast<int>(row[0]);
    r.start = static_cast<int>(row[1]);
    r.objective = row[2];
    r.best_objective = row[3];
    r.failed = row[4] != 0;
    r.parameters = Eigen::Map<const Eigen::VectorXd>(row + 5, p);
    if (r.failed) r.failure = failures[k];
    summary->history.push_back(std::move(r));
  }
  ident::SummariseStarts(summary);
}

}  // namespace

void AddIdentifyCommand(CLI::App& app) {
  auto args = std::make_shared<IdentifyArguments>();
  CLI::App* command = app.add_subcommand(
      "identify",
      "Identify the case's [[identify.parameter]]s from measured data by minimising the\n"
      "difference between measured and simulated POD (Lenaerts et al., eq. 19 and sec. 4.3).\n"
      "Exit status 2 if no usable point was found; no file is then written.");
  args->objective.AddTo(*command);
  auto* preset = command
                     ->add_option("--objective", args->preset,
                                  "Preset: full (U+S+V), time-free (U+S), wavelet (U+S+IF)")
                     ->capture_default_str();
  // A preset beside --terms was silently dropped, and an empty --terms meant "full".
  command->add_option("--terms", args->terms, "Custom terms instead of a preset, e.g. U,S,IF")
      ->check(NonEmpty("a list of terms U, S, V, IF (e.g. U,S,IF)"))
      ->excludes(preset);
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
  command->add_option("--xtol", args->xtol_rel, "Relative parameter tolerance")
      ->capture_default_str()
      ->check(NumberIn({0.0, true}));
  // Bounded so that "-1" is refused rather than wrapped to 2^64 - 1.
  command->add_option("--seed", args->seed, "Seed of the Latin hypercube and random algorithms")
      ->capture_default_str()
      ->check(IntegerIn(0, std::numeric_limits<long long>::max()));
  command->add_option("--json", args->json, "Write the result and history as JSON")
      ->check(NonEmptyPath());
  command
      ->add_option(
          "--plot-dir", args->plot_dir,
          "Write signals.csv and plots (fig2a_start.png, fig2b_optimum.png, convergence.png, "
          "ridge.png) to this folder")
      ->check(NonEmptyPath("a folder path"));
  command
      ->add_option("--threads", args->threads,
                   "Threads running the starts (0: OMP_NUM_THREADS or the cores, shared by the MPI "
                   "ranks on a machine); "
                   "with one start, a long record's ridge takes two of them")
      ->capture_default_str()
      ->check(IntegerIn(0, ident::kMaxThreads));
  command->add_flag("--report", args->report, "Print the full report");
  command->callback([args] {
    args->objective.PrepareData();  // -m and the data options become [data] keys
    std::vector<NamedFile> inputs = CaseInputFiles(args->objective.input);
    std::vector<NamedFile> outputs;
    if (!args->plot_dir.empty()) {
      CheckOutputFolder({"--plot-dir", args->plot_dir});
      // An existing folder's files must not be inputs (a new one has none).
      if (std::filesystem::is_directory(args->plot_dir)) {
        for (const char* name : kPlotFiles)
          outputs.push_back({"--plot-dir", args->plot_dir + "/" + name});
      }
    }
    // --json may go into the --plot-dir this run creates: the folder's check
    // above stands for it, and the plots are written first (they create it).
    if (!JsonInNewPlotDir(args->json, args->plot_dir))
      outputs.insert(outputs.begin(), {"--json", args->json});
    CheckOutputs(inputs, outputs);
    const ident::ObjectiveWeights weights = WeightsFrom(args->preset, args->terms, args->weights);
    const int threads = args->threads > 0 ? args->threads : mpi::DefaultThreads();
    // One start leaves the other threads idle: a ridge over several blocks
    // (a long record) then runs its transform beside its dynamic programme
    // (RidgeFrequencyEstimator; the same result bit for bit).
    args->objective.ridge_threads = args->multistart <= 1 && threads >= 2 ? 2 : 1;
    const auto objective = args->objective.Build({{weights.ToString(), weights}});
    ident::IdentifyOptions options;
    options.algorithm = ident::ParseAlgorithm(args->algorithm);
    options.local_algorithm = ident::ParseAlgorithm(args->local_algorithm);
    options.start = args->objective.Start(*objective);
    options.multistart = args->multistart;
    options.max_evaluations = args->max_evaluations;
    options.xtol_rel = args->xtol_rel;
    options.seed = args->seed;
    options.threads = threads;
    options.share_index = mpi::Rank();
    options.share_count = mpi::Size();
    ident::IdentifySummary summary;
    const std::string error = mpi::RunCollectively([&] { summary = ident::Identify(*objective, options); });
    if (!error.empty()) throw CommandFailed("identify: " + error + "; no file written");
    if (mpi::Active()) {
      MergeStarts(&summary, objective->parameter_count());
      if (mpi::Rank() != 0) {  // rank 0 reports and writes; every rank exits alike
        if (!summary.IsSolutionUsable()) throw CommandFailed("identify: " + summary.message);
        return;
      }
      if (summary.IsSolutionUsable()) {  // at the merged best point (as one process does)
        summary.uncertainty = ident::ObjectiveUncertainty(*objective, summary.parameters, options.weighting,
                                                          options.uncertainty_options, options.seed);
      }
    }
    std::printf("%s\n", summary.BriefReport().c_str());
    // One cached simulator for the reports' simulations (the quantity check,
    // the plots): the model and its load are built once, not per report.
    ident::EvaluationWorkspace reports;
    // Measured accelerations declared as displacements (or the reverse):
    // the spectra of the record and of the simulation at the result tell.
    if (summary.parameters.size() == objective->parameter_count()) {
      const SimulationResult at = objective->SimulateAt(summary.parameters, &reports);
      if (at.summary.IsSolutionUsable() &&
          at.sensors.channels() == objective->measured().channels()) {
        const QuantityCheck q = CheckMeasuredQuantity(
            objective->measured(), at.sensors,
            objective->SpecAt(summary.parameters).sensors.quantity);
        if (q.mismatch) std::fprintf(stderr, "podid: warning: %s\n", q.message.c_str());
      }
    }
    // A weighted term with under 1 % of F at the start hardly steers the fit.
    if (!summary.initial_terms.failed) {
      const ident::TermValues& t = summary.initial_terms;
      const double total = t.Combine(weights, NAN);
      const std::pair<const char*, double> shares[] = {
          {"dU", weights.u * t.u}, {"dS", weights.s * t.s}, {"dV", weights.v * t.v}, {"dIF", weights.f * t.f}};
      const double w[] = {weights.u, weights.s, weights.v, weights.f};
      for (int k = 0; k < 4; ++k) {
        if (w[k] != 0 && total > 0 && shares[k].second < 0.01 * total) {
          std::fprintf(stderr,
                       "podid: note: at the start %s is %.3g %% of F (%s): it hardly steers the fit; "
                       "see --terms/--weights\n",
                       shares[k].first, 100 * shares[k].second / total,
                       ident::TermContributions(t, weights).c_str());
        }
      }
    }
    if (args->report) std::printf("%s", summary.FullReport().c_str());
    // No usable point: the plots would show NaN and the JSON no result. As
    // landscape and pod on failure, nothing is written (the message quotes
    // the first failure; --report prints the run's summary).
    if (!summary.IsSolutionUsable()) {
      const bool outputs_asked = !args->json.empty() || !args->plot_dir.empty();
      throw CommandFailed("identify: " + summary.message +
                          (outputs_asked ? "; no file written" : ""));
    }
    // --json and the plots published together: a failing plot leaves none.
    OutputBatch batch;
    if (!args->plot_dir.empty()) {
      WritePlots(args->plot_dir, *objective, summary, weights.NeedsRidges(), &reports, &batch);
    }
    if (!args->json.empty()) WriteJson(args->json, summary, *objective, &batch);
    batch.Commit();
    if (!args->plot_dir.empty()) {
      std::printf("plots and signals.csv written to %s/\n", args->plot_dir.c_str());
    }
  });
}

}  // namespace podid::cli
