// podid pod: proper orthogonal decomposition of a time series (docs/pod.md).
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "commands.hpp"
#include "data_arguments.hpp"
#include "podid/core/error.hpp"
#include "podid/core/io.hpp"
#include "podid/pod/pod.hpp"

namespace podid::cli {
namespace {

struct PodArguments {
  std::string data;
  DataArguments reading;
  std::string method = "auto";
  int modes = 0;
  double energy = 1.0;
  double sigma_threshold = 0.0;
  bool no_mean = false;
  std::string json;
  std::string output;
};

std::vector<double> ToVector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

void RunPod(const PodArguments& a) {
  PodOptions options;
  options.method = ParsePodMethod(a.method);
  options.remove_mean = !a.no_mean;
  options.max_modes = a.modes;
  options.energy_fraction = a.energy;
  options.sigma_threshold = a.sigma_threshold;
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument(why);
  CheckOutputs({{"data file", a.data}}, {{"--json", a.json}, {"-o", a.output}});

  const TimeSeries series = a.reading.ReadConditioned(a.data);
  if (options.max_modes > std::min(series.channels(), series.samples())) {
    ThrowInvalid("--modes",
                 "<= min(channels, samples) = " +
                     std::to_string(std::min(series.channels(), series.samples())) + " for " +
                     a.data,
                 std::to_string(options.max_modes));
  }
  const PodResult r = ComputePod(series, options);
  if (r.IsDegenerate()) throw CommandFailed("pod: " + a.data + ": " + r.message + "; no file written");
  // A threshold above every sigma kept nothing, and wrote a CSV of times only
  // that podid cannot read back.
  if (r.modes() == 0) {
    ThrowInvalid(
        "--sigma-threshold",
        "a threshold below the largest singular value of " + a.data + " (it keeps no mode)",
        ToText(a.sigma_threshold));
  }

  std::printf("%s: %lld channels x %lld samples, method %s, numerical rank %d\n", a.data.c_str(),
              static_cast<long long>(r.sensors), static_cast<long long>(r.samples),
              ToString(r.method), r.numerical_rank);
  std::printf("%4s  %13s  %13s  %8s  %8s ", "mode", "sigma", "lambda", "energy%", "cumul%");
  for (const std::string& name : series.channel_names) std::printf(" %9s", name.c_str());
  std::printf("\n");
  for (Eigen::Index k = 0; k < r.modes(); ++k) {
    std::printf("%4lld  %13.6e  %13.6e  %8.4f  %8.4f ", static_cast<long long>(k + 1),
                r.singular_values(k), r.proper_orthogonal_values(k), 100.0 * r.energy_fraction(k),
                100.0 * r.cumulative_energy(k));
    for (Eigen::Index i = 0; i < r.sensors; ++i) std::printf(" %9.5f", r.poms(i, k));
    std::printf("\n");
  }

  OutputBatch batch;  // --json and -o published together
  if (!a.json.empty()) {
    nlohmann::json j;
    j["data"] = a.data;
    j["method"] = ToString(r.method);
    j["sensors"] = r.sensors;
    j["samples"] = r.samples;
    j["remove_mean"] = options.remove_mean;
    j["channels"] = series.channel_names;
    j["units"] = series.units;  // "" where the file names none
    j["start_s"] = series.time_s(0);
    j["conditioning"] = a.reading.Conditioning().Describe();
    j["step_s"] = series.step_s();
    j["sampling_rate_Hz"] = 1.0 / series.step_s();
    j["numerical_rank"] = r.numerical_rank;
    j["total_energy"] = r.total_energy;
    j["mean"] = ToVector(r.mean);
    j["singular_values"] = ToVector(r.singular_values);
    j["proper_orthogonal_values"] = ToVector(r.proper_orthogonal_values);
    j["energy_fraction"] = ToVector(r.energy_fraction);
    j["cumulative_energy"] = ToVector(r.cumulative_energy);
    nlohmann::json poms = nlohmann::json::array();  // one array per POM (dim M)
    for (Eigen::Index k = 0; k < r.modes(); ++k) poms.push_back(ToVector(r.poms.col(k)));
    j["poms"] = poms;
    WriteFileAtomically(
        a.json, [&](std::ostream& os) { os << j.dump(2) << '\n'; }, &batch);
  }
  if (!a.output.empty()) {
    TimeSeries v;  // time modes V (N x k): columns v1..vk
    v.time_s = series.time_s;
    v.values = r.time_modes;
    for (Eigen::Index k = 0; k < r.modes(); ++k)
      v.channel_names.push_back("v" + std::to_string(k + 1));
    WriteCsv(a.output, v, &batch);
  }
  batch.Commit();
}

}  // namespace

void AddPodCommand(CLI::App& app) {
  auto a = std::make_shared<PodArguments>();
  CLI::App* command = app.add_subcommand(
      "pod",
      "Proper orthogonal decomposition of a time series: POMs, singular values, proper\n"
      "orthogonal values and energy per mode (docs/pod.md)");
  command
      ->add_option("data", a->data,
                   "Time series: .csv (t,<channels>), .mat or .uff/.unv (docs/data-files.md)")
      ->required();
  a->reading.AddTo(*command);
  command->add_option("--method", a->method, "auto | svd | direct | snapshot")
      ->capture_default_str();
  auto* modes = command->add_option("--modes", a->modes, "Keep at most K modes (0: all)")
                    ->check(IntegerIn(0, kMaxPodModesOption));
  auto* energy =
      command
          ->add_option("--energy", a->energy, "Keep the fewest modes holding this energy fraction")
          ->check(NumberIn({0.0, true}, {1.0}));
  modes->excludes(energy);
  command
      ->add_option("--sigma-threshold", a->sigma_threshold,
                   "Drop modes with sigma <= this (0: off; noise filtering, section 2.3)")
      ->check(NumberIn({0.0}));
  command->add_flag("--no-mean", a->no_mean, "Do not subtract each channel's time mean (eq. 1)");
  command
      ->add_option("--json", a->json, "Write the decomposition (U, sigma, lambda, energy) as JSON")
      ->check(NonEmptyPath());
  command->add_option("-o,--output", a->output, "Write the time modes V as CSV (t,v1..vk)")
      ->check(NonEmptyPath());
  command->callback([a] { RunPod(*a); });
}

}  // namespace podid::cli
