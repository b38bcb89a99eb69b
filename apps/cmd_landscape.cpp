// podid landscape: objectives over a grid of one or two parameters, with metrics.
#include <atomic>
#include <cmath>
#include <csignal>
#include <limits>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.hpp"
#include "ident_common.hpp"
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
  axis->parameter = -1;
  std::string names;
  for (int i = 0; i < f.parameter_count(); ++i) {
    if (f.parameters()[i].name == name) axis->parameter = i;
    names += (i ? ", " : "") + f.parameters()[i].name;
  }
  if (axis->parameter < 0) ThrowInvalid(option, "a parameter of the case (" + names + ")", "\"" + name + "\"");
}

std::vector<ident::NamedObjective> ParseObjectives(const std::string& list) {
  std::vector<ident::NamedObjective> out;
  std::stringstream ss(list);
  std::string name;
  while (std::getline(ss, name, ',')) out.push_back({name, ident::ObjectiveWeights::Preset(name)});
  if (out.empty()) ThrowInvalid("--objective", "a list of full, time-free, wavelet", "\"" + list + "\"");
  return out;
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
  command->add_option("-o,--output", args->output, "CSV with a column per objective");
  command->add_option("--json", args->json, "Metrics as JSON");
  command->add_option("--plot", args->plot, "PNG of the curves (1-D) or of the first objective (2-D)");
  command->callback([args] {
    args->objective.PrepareData();  // -m and the data options become [data] keys
    std::vector<NamedFile> inputs = CaseInputFiles(args->objective.input);
    CheckOutputs(inputs, {{"-o", args->output}, {"--json", args->json}, {"--plot", args->plot}});
    const std::vector<ident::NamedObjective> objectives = ParseObjectives(args->objectives);
    if (args->param2.empty() != args->range2.empty()) {
      ThrowInvalid("--param2/--range2", "both or neither", args->param2.empty() ? "--range2 alone" : "--param2 alone");
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
    options.progress = true;
    options.cancel = &g_interrupted;
    const auto previous_handler = std::signal(SIGINT, OnInterrupt);
    const ident::LandscapeResult result = ident::ComputeLandscape(*objective, options);
    std::signal(SIGINT, previous_handler);  // podid's temporary-file cleanup
    if (result.termination == ident::LandscapeTermination::kInterrupted) {
      throw CommandFailed("landscape: " + result.message + "; no file written", 130);
    }
    if (result.termination != ident::LandscapeTermination::kCompleted) {
      // Every point failed: no value, no minimiser (exit 2, CommandFailed).
      throw CommandFailed(result.BriefReport() + ": " + result.message + "; no file written");
    }
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
    if (!args->output.empty()) {
      WriteFileAtomically(args->output, [&](std::ostream& os) {
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
      });
    }
    if (!args->json.empty()) {
      nlohmann::json j;
      j["parameters"] = result.parameter_names;
      j["points"] = result.evaluations;
      j["failed_points"] = result.failed_evaluations;
      j["wall_time_s"] = result.wall_time_s;
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
      WriteFileAtomically(args->json, [&](std::ostream& os) { os << j.dump(2) << '\n'; });
    }
    if (!args->plot.empty()) {
      if (one_d) {
        std::vector<LineSeries> curves;
        for (std::size_t k = 0; k < result.names.size(); ++k)
          curves.push_back({result.names[k], result.x, result.values[k].col(0)});
        PlotLines(args->plot, {"Objective landscape", result.parameter_names[0], "F", true}, curves);
      } else {
        PlotHeatMap(args->plot, {result.names[0] + " objective", result.parameter_names[0], result.parameter_names[1]},
                    "F", result.x, result.y, result.values[0]);
      }
    }
  });
}

}  // namespace podid::cli
