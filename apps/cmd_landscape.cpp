// podid landscape: objectives over a grid of one or two parameters, with metrics.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.hpp"
#include "ident_common.hpp"
#include "mpi_session.hpp"
#include "plot.hpp"
#include "podid/core/error.hpp"
#include "podid/core/io.hpp"
#include "podid/ident/landscape.hpp"

namespace podid::cli {
namespace {

std::atomic<bool> g_interrupted{false};
extern "C" void OnInterrupt(int) { g_interrupted.store(true); }

struct LandscapeArguments {
  ObjectiveArguments objective;
  std::string param, range;
  std::string param2, range2;
  std::string objectives = "full,time-free,wavelet";
  std::string output, json, plot;
  int threads = 0;
};

// "lower:upper:points"; the parameter index is resolved later (SetParameter).
ident::LandscapeAxis ParseRange(const std::string& option, const std::string& range) {
  ident::LandscapeAxis axis;
  double lower = 0, upper = 0;
  int points = 0;
  char c1 = 0, c2 = 0;
  std::istringstream is(range);
  if (!(is >> lower >> c1 >> upper >> c2 >> points) || c1 != ':' || c2 != ':' || !is.eof()) {
    ThrowInvalid(option, "LOWER:UPPER:POINTS, e.g. 0:100:201", "\"" + range + "\"");
  }
  if (!(lower < upper) || points < 2) {
    ThrowInvalid(option, "LOWER < UPPER and POINTS >= 2", "\"" + range + "\"");
  }
  if (points > ident::kMaxLandscapePoints) {
    ThrowInvalid(option, "at most " + ToText(ident::kMaxLandscapePoints) + " POINTS",
                 "\"" + range + "\"");
  }
  // Every grid value lower + (upper - lower) i / (n - 1) finite.
  if (!std::isfinite(upper - lower)) {
    ThrowInvalid(option, "bounds whose difference UPPER - LOWER is finite", "\"" + range + "\"");
  }
  axis.lower = lower;
  axis.upper = upper;
  axis.points = points;
  return axis;
}

void SetParameter(const ident::ObjectiveFunction& f, const std::string& option, const std::string& name,
                  ident::LandscapeAxis* axis) {
  axis->parameter = f.ParameterIndex(name, option);
  // Evaluated as asked (the valley's shape beyond them is worth seeing), but
  // said: identify searches only within the bounds.
  const ParameterSpec& p = f.parameters()[static_cast<std::size_t>(axis->parameter)];
  if ((axis->lower < p.lower || axis->upper > p.upper) && mpi::Rank() == 0) {
    std::fprintf(stderr,
                 "podid: note: %s %s..%s goes beyond %s's bounds %s..%s ([[identify.parameter]]): "
                 "identify does not search there\n",
                 option == "--param" ? "--range" : "--range2", ToText(axis->lower).c_str(),
                 ToText(axis->upper).c_str(), name.c_str(), ToText(p.lower).c_str(),
                 ToText(p.upper).c_str());
  }
}

// Errors name --objective (Preset's say "objective"); a repeated preset would
// be computed twice and give a CSV column and a JSON key of the same name.
std::vector<ident::NamedObjective> ParseObjectives(const std::string& list) {
  const std::string expected = "a list of full, time-free, wavelet";
  if (list.empty()) ThrowInvalid("--objective", expected, "\"\"");
  std::vector<ident::NamedObjective> out;
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t comma = std::min(list.find(',', start), list.size());
    const std::string name = list.substr(start, comma - start);
    start = comma + 1;
    if (name != "full" && name != "time-free" && name != "wavelet") {
      ThrowInvalid("--objective", expected, Excerpt(name));
    }
    for (const ident::NamedObjective& o : out) {
      if (o.name == name) ThrowInvalid("--objective", "each objective once", name + " twice");
    }
    out.push_back({name, ident::ObjectiveWeights::Preset(name)});
  }
  return out;
}

// Under MPI each rank computed its share of the points (p % ranks == rank):
// sum the shares (a rank leaves the points it did not compute at exactly 0,
// so every value arrives bit for bit) and summarise the whole grid on every
// rank. Failure texts stay with their rank: rank 0, which writes the outputs,
// owns point 0, the one the "none succeeded" message quotes.
void MergeShares(const std::vector<ident::NamedObjective>& weightings, ident::LandscapeResult* result) {
  const std::int64_t n = static_cast<std::int64_t>(result->terms.size());
  std::vector<double> terms(static_cast<std::size_t>(4 * n), 0.0);
  std::vector<std::int64_t> flags(static_cast<std::size_t>(2 * n), 0);
  for (std::int64_t p = 0; p < n; ++p) {
    if (!result->computed[p]) continue;
    const ident::TermValues& t = result->terms[p];
    terms[4 * p] = t.u;
    terms[4 * p + 1] = t.s;
    terms[4 * p + 2] = t.v;
    terms[4 * p + 3] = t.f;
    flags[2 * p] = 1;
    flags[2 * p + 1] = t.failed ? 1 : 0;
  }
  mpi::SumOnAll(terms.data(), 4 * n);
  mpi::SumOnAll(flags.data(), 2 * n);
  for (std::int64_t p = 0; p < n; ++p) {
    ident::TermValues& t = result->terms[p];
    if (!result->computed[p]) {
      t.u = terms[4 * p];
      t.s = terms[4 * p + 1];
      t.v = terms[4 * p + 2];
      t.f = terms[4 * p + 3];
      t.failed = flags[2 * p + 1] != 0;
      if (t.failed) t.failure = "failed on another rank";
    }
    result->computed[p] = flags[2 * p] != 0;
  }
  ident::SummariseLandscape(weightings, result);
}

}  // namespace

void AddLandscapeCommand(CLI::App& app) {
  auto args = std::make_shared<LandscapeArguments>();
  CLI::App* command = app.add_subcommand(
      "landscape",
      "Evaluate objectives over a grid of one parameter (or two) and print, per objective,\n"
      "the number of local minima, the global minimiser, its basin of attraction and a\n"
      "roughness figure (the paper's figs. 3-6). Parameters not on an axis stay at their\n"
      "start (--start NAME=VALUE). Failed points are nan in the CSV; exit status 2 if no\n"
      "point succeeded. Ctrl-C stops it without writing files (exit 130).");
  args->objective.AddTo(*command);
  command->add_option("--param", args->param, "Parameter on the x axis (a name from [[identify.parameter]])")
      ->required();
  command->add_option("--range", args->range, "LOWER:UPPER:POINTS of the x axis (2 to 1000000 points)")->required();
  command->add_option("--param2", args->param2, "Second parameter, for a 2-D landscape");
  command->add_option("--range2", args->range2, "LOWER:UPPER:POINTS of the second axis (1000000 points in all)");
  command->add_option("--objective", args->objectives, "Comma-separated presets: full, time-free, wavelet")
      ->capture_default_str();
  command
      ->add_option(
          "--threads", args->threads,
          "Worker threads (0: OMP_NUM_THREADS or the cores, shared by the MPI ranks on a machine)")
      ->check(IntegerIn(0, ident::kMaxThreads))
      ->capture_default_str();
  command->add_option("-o,--output", args->output, "CSV with a column per objective")
      ->check(NonEmptyPath());
  command->add_option("--json", args->json, "Metrics as JSON")->check(NonEmptyPath());
  command
      ->add_option("--plot", args->plot, "PNG of the curves (1-D) or of the first objective (2-D)")
      ->check(NonEmptyPath());
  command->callback([args] {
    args->objective.PrepareData();  // -m and the data options become [data] keys
    std::vector<NamedFile> inputs = CaseInputFiles(args->objective.input);
    CheckOutputs(inputs, {{"-o", args->output}, {"--json", args->json}, {"--plot", args->plot}});
    const std::vector<ident::NamedObjective> objectives = ParseObjectives(args->objectives);
    if (args->param2.empty() != args->range2.empty()) {
      ThrowInvalid("--param2/--range2", "both or neither", args->param2.empty() ? "--range2 alone" : "--param2 alone");
    }
    if (!args->param2.empty() && args->param2 == args->param) {  // before reading the data
      ThrowInvalid("--param2", "a parameter other than --param's", Excerpt(args->param2));
    }
    ident::LandscapeOptions options;
    options.x = ParseRange("--range", args->range);
    if (!args->param2.empty()) options.y = ParseRange("--range2", args->range2);
    if (options.y && static_cast<long long>(options.x.points) * options.y->points >
                         ident::kMaxLandscapePoints) {
      ThrowInvalid("--range/--range2", "at most " + ToText(ident::kMaxLandscapePoints) +
                                           " grid points in all",
                   ToText(options.x.points) + " x " + ToText(options.y->points));
    }
    const auto objective = args->objective.Build(objectives);
    SetParameter(*objective, "--param", args->param, &options.x);
    if (options.y) SetParameter(*objective, "--param2", args->param2, &*options.y);
    options.base = args->objective.Start(*objective);  // --start sets the other parameters
    options.threads = args->threads > 0 ? args->threads : mpi::DefaultThreads();
    options.share_index = mpi::Rank();
    options.share_count = mpi::Size();
    // The progress line, on a terminal, from rank 0 (its share of the points).
    const bool show_progress = mpi::Rank() == 0 && isatty(STDERR_FILENO);
    if (show_progress) {
      options.progress = [](const ident::Progress& p) {
        std::fprintf(stderr, "\rlandscape: %lld/%lld points", p.done, p.total);
        std::fflush(stderr);
      };
    }
    options.cancel = &g_interrupted;
    const auto previous_handler = std::signal(SIGINT, OnInterrupt);
    ident::LandscapeResult result;
    const std::string error =
        mpi::RunCollectively([&] { result = ident::ComputeLandscape(*objective, options); });
    std::signal(SIGINT, previous_handler);  // podid's temporary-file cleanup
    if (show_progress) std::fprintf(stderr, "\n");
    if (!error.empty()) throw CommandFailed("landscape: " + error + "; no file written");
    if (mpi::Active()) MergeShares(objective->options().weightings, &result);
    if (result.termination == ident::LandscapeTermination::kInterrupted) {
      throw CommandFailed("landscape: " + result.message + "; no file written", 130);
    }
    if (result.termination != ident::LandscapeTermination::kCompleted) {
      // Every point failed: no value, no minimiser (exit 2, CommandFailed).
      throw CommandFailed(result.BriefReport() + ": " + result.message + "; no file written");
    }
    if (mpi::Rank() != 0) return;  // rank 0 reports and writes
    std::printf("%s\n", result.BriefReport().c_str());
    const bool one_d = !options.y;
    if (one_d) {
      std::printf("%-10s %7s %14s %14s %25s %9s %10s\n", "objective", "minima", "minimiser", "minimum",
                  "basin", "basin_%", "roughness");
      for (std::size_t k = 0; k < result.names.size(); ++k) {
        const ident::LandscapeMetrics& m = result.metrics[k];
        std::printf("%-10s %7d %14.6g %14.6g %12.6g..%-12.6g %9.2f %10.3f\n", result.names[k].c_str(),
                    m.local_minima, m.global_minimiser, m.global_minimum, m.basin_lower, m.basin_upper,
                    100 * m.basin_fraction, m.roughness);
      }
    }
    // -o, --json and --plot published together (a failing gnuplot leaves none).
    OutputBatch batch;
    if (!args->output.empty()) {
      WriteFileAtomically(
          args->output,
          [&](std::ostream& os) {
            os.precision(12);
            os << result.parameter_names[0];
            if (!one_d) os << ',' << result.parameter_names[1];
            for (const std::string& n : result.names) os << ',' << n;
            os << '\n';
            for (Eigen::Index i = 0; i < result.x.size(); ++i) {
              for (Eigen::Index j = 0; j < std::max<Eigen::Index>(result.y.size(), 1); ++j) {
                os << result.x[i];
                if (!one_d) os << ',' << result.y[j];
                for (const Eigen::MatrixXd& v : result.values) os << ',' << v(i, j);
                os << '\n';
              }
            }
          },
          &batch);
    }
    if (!args->json.empty()) {
      nlohmann::json j;
      j["parameters"] = result.parameter_names;
      j["points"] = result.evaluations;
      j["failed_points"] = result.failed_evaluations;
      j["wall_time_s"] = result.wall_time_s;
      if (!objective->measured_ridges().empty()) j["ridges"] = RidgesJson(*objective);
      for (std::size_t k = 0; k < result.names.size(); ++k) {
        nlohmann::json o;
        const Eigen::MatrixXd& v = result.values[k];
        // Over the points that succeeded (failed points are NaN).
        const Eigen::ArrayXXd finite = v.array().isFinite().select(
            v.array(), std::numeric_limits<double>::infinity());
        o["minimum"] = finite.minCoeff();
        if (one_d) {
          const ident::LandscapeMetrics& m = result.metrics[k];
          o = {{"local_minima", m.local_minima},     {"global_minimiser", m.global_minimiser},
               {"global_minimum", m.global_minimum}, {"basin", {m.basin_lower, m.basin_upper}},
               {"basin_fraction", m.basin_fraction}, {"roughness", m.roughness}};
        }
        j["objectives"][result.names[k]] = o;
      }
      WriteFileAtomically(
          args->json, [&](std::ostream& os) { os << j.dump(2) << '\n'; }, &batch);
    }
    if (!args->plot.empty()) {
      if (one_d) {
        std::vector<LineSeries> curves;
        for (std::size_t k = 0; k < result.names.size(); ++k)
          curves.push_back({result.names[k], result.x, result.values[k].col(0)});
        PlotLines(args->plot, {"Objective landscape", result.parameter_names[0], "F", true}, curves,
                  &batch);
      } else {
        PlotHeatMap(
            args->plot,
            {result.names[0] + " objective", result.parameter_names[0], result.parameter_names[1]},
            "F", result.x, result.y, result.values[0], {}, &batch);
      }
    }
    batch.Commit();
  });
}

}  // namespace podid::cli
