// podid plan: measure FFTW plans ahead of time into the on-disk wisdom cache,
// so that later `podid cwt` / `identify` runs plan nothing (docs/wavelet.md,
// "Planning").
#include <sys/stat.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "commands.hpp"
#include "data_arguments.hpp"
#include "podid/core/error.hpp"
#include "podid/core/io.hpp"
#include "podid/wavelet/cwt.hpp"
#include "podid/wavelet/plans.hpp"
#include "wavelet_arguments.hpp"

namespace podid::cli {
namespace {

constexpr long kMaxSamples = 1L << 26;  // 67 M samples: P <= 2^27 with reflect padding
constexpr std::size_t kMaxRecords = 64;

struct PlanArguments {
  std::vector<std::string> data;
  // As cwt reads DATA (--rate / --step for a file without time, --window,
  // --decimate...): the same record length and step, so the same plans.
  DataArguments reading;
  std::vector<std::string> samples;  // each occurrence's N[,N...], read by ParseSamples
  double fs_Hz = 0.0;
  CLI::Option* fs_option = nullptr;
  GridArguments grid;        // cwt's --fmin, --fmax, --voices, --bins
  WaveletArguments wavelet;  // cwt's wavelet options: the lengths follow the wavelet
  std::string padding;  // empty: cwt's default (zero) and identification's (reflect)
  std::string effort = "measure";
};

// The wisdom cache is the command's only output: checked, as every command
// checks its outputs, before anything is read or measured. The library
// creates the folders it lacks and renames its file over whatever is at the
// path, so only a missing cache, a folder in the file's place, and a folder
// that cannot be made or written are refused here.
void CheckWisdomDestination(const std::string& path) {
  if (path.empty()) {
    ThrowInvalid("plan: wisdom cache",
                 "XDG_CACHE_HOME (an absolute path) or HOME set, to save the plans in",
                 "neither set");
  }
  struct stat status {};
  if (::lstat(path.c_str(), &status) == 0 && S_ISDIR(status.st_mode)) {
    ThrowInvalid("plan: wisdom cache", "a file (or none yet)", "\"" + path + "\", a folder");
  }
  CheckOutputFolder({"plan: wisdom cache", std::filesystem::path(path).parent_path().string()});
}

// The lengths of --samples N[,N...] (one or more occurrences), each in
// 4..kMaxSamples. Read here instead of by CLI11's delimiter, which drops
// empty items: "1000,,2000" was read as two lengths.
std::vector<long> ParseSamples(const std::vector<std::string>& given) {
  std::vector<long> samples;
  for (const std::string& list : given) {
    std::size_t begin = 0;
    while (true) {
      const std::size_t end = std::min(list.find(',', begin), list.size());
      const std::string item = list.substr(begin, end - begin);
      long n = 0;
      const auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), n);
      if (item.empty() || ec != std::errc() || ptr != item.data() + item.size()) {
        ThrowInvalid("plan --samples",
                     "record lengths N[,N...], each a whole number 4.." + ToText(kMaxSamples),
                     item.empty() ? "an empty item in " + Excerpt(list) : Excerpt(item));
      }
      if (n < 4 || n > kMaxSamples) {
        ThrowInvalid("plan --samples", "4.." + ToText(kMaxSamples), ToText(n));
      }
      if (samples.size() == kMaxRecords) {
        ThrowInvalid("plan --samples", "at most " + ToText(kMaxRecords) + " lengths", "more");
      }
      samples.push_back(n);
      if (end == list.size()) break;
      begin = end + 1;
    }
  }
  return samples;
}

void Run(const PlanArguments& a) {
  const std::string wisdom_path = wavelet::FftWisdomPath();
  CheckWisdomDestination(wisdom_path);
  // Every record to plan for, and what an error about it names.
  struct Record {
    long samples;
    double step_s;
    std::string label;
  };
  std::vector<Record> records;
  const bool fs_given = a.fs_option->count() > 0;
  // The transforms' step range as frequencies (0, NaN, inf and subnormal
  // rates give steps outside it).
  if (fs_given && !wavelet::IsTransformStep(1.0 / a.fs_Hz)) {
    ThrowInvalid("plan --fs", "a sampling frequency between 1e-15 Hz and 1e15 Hz", ToText(a.fs_Hz));
  }
  const std::vector<long> samples = ParseSamples(a.samples);
  if (!samples.empty() && !fs_given) {
    ThrowInvalid("plan --samples", "--fs HZ (the sampling frequency) as well", "no --fs");
  }
  if (fs_given && samples.empty()) {
    ThrowInvalid("plan --fs", "--samples N (the record lengths at that frequency) as well",
                 "no --samples");
  }
  if (a.data.empty() && !a.reading.FirstGiven().empty()) {  // it was silently ignored
    ThrowInvalid("plan " + a.reading.FirstGiven(), "DATA files to read and condition with it",
                 "--samples alone (give the conditioned records' lengths and --fs instead)");
  }
  for (const std::string& path : a.data) {
    const TimeSeries series = a.reading.ReadConditioned(path);
    records.push_back({static_cast<long>(series.samples()), series.step_s(), path});
  }
  for (long n : samples) {
    records.push_back({n, 1.0 / a.fs_Hz, "--samples " + ToText(n)});
  }
  if (records.empty()) ThrowInvalid("plan", "DATA files or --samples N --fs HZ", "neither");
  if (records.size() > kMaxRecords) {
    ThrowInvalid("plan", "at most " + ToText(kMaxRecords) + " records", ToText(records.size()));
  }
  // The lengths of the full-rate transform (podid cwt) and of the
  // band-limited one (identification, cwt --band-limited).
  wavelet::MorletWavelet psi;
  a.wavelet.ApplyTo(&psi);
  wavelet::FftLengths lengths;
  for (const Record& record : records) {
    try {
      const long n = record.samples;
      const double step = record.step_s;
      std::vector<std::string> paddings = {a.padding};
      if (a.padding.empty()) paddings = {"zero", "reflect"};
      for (const std::string& padding : paddings) {
        wavelet::CwtOptions options;
        options.wavelet = psi;
        options.padding = ParseOption("--padding", padding, wavelet::ParsePadding);
        options.frequencies = a.grid.Grid(
            0.5 / step, "the Nyquist frequency of a record of step " + ToText(step) + " s");
        std::string why;
        if (!options.IsValid(&why)) throw std::invalid_argument("plan: " + why);
        for (bool band_limited : {false, true}) {
          options.band_limited = band_limited;
          wavelet::MergeFftLengths(wavelet::CwtFftLengths(options, n, step), &lengths);
        }
      }
    } catch (const std::invalid_argument& e) {
      // Name the record: a file's step comes from its time column.
      throw std::invalid_argument(record.label + ": " + e.what());
    }
  }
  const wavelet::PlanEffort effort =
      a.effort == "patient" ? wavelet::PlanEffort::kPatient : wavelet::PlanEffort::kMeasure;
  std::string list;
  for (int n : lengths.real_forward) list += (list.empty() ? "" : ", ") + ToText(n) + " real";
  for (int n : lengths.complex_forward) list += ", " + ToText(n) + " complex forward";
  for (int n : lengths.complex_backward) list += ", " + ToText(n) + " complex";
  for (const auto& [m, d] : lengths.interleaved_backward) {
    list += ", " + ToText(d) + " x " + ToText(m) + " complex";
  }
  // Before measuring, flushed: at 2^26 samples the measurement takes minutes
  // (over 90 s), which looked like a hang with nothing printed.
  std::printf("podid plan: FFT lengths %s\n", list.c_str());
  std::fflush(stdout);
  const wavelet::PlanSummary summary = wavelet::MeasureFftPlans(lengths, effort);
  std::printf("measured %d plan(s) (FFTW_%s) in %.3g s, %d already measured\n", summary.measured,
              effort == wavelet::PlanEffort::kPatient ? "PATIENT" : "MEASURE", summary.seconds,
              summary.known);
  if (!summary.ignored.empty()) {
    std::printf("wisdom cache ignored: %s%s\n", summary.ignored.c_str(),
                summary.saved ? " (replaced)" : "");
  }
  if (summary.saved) {
    std::printf("wisdom -> %s\n", summary.wisdom_path.c_str());
  } else if (!summary.message.empty()) {
    // Saving the wisdom is the command's whole purpose: a failure is one
    // (cwt, which only uses the wisdom, carries on without it).
    throw std::runtime_error("plan: wisdom not saved to " + summary.wisdom_path + ": " +
                             summary.message + " (the " + ToText(summary.measured) +
                             " plan(s) measured are lost)");
  }
}

}  // namespace

void AddPlanCommand(CLI::App& app) {
  auto a = std::make_shared<PlanArguments>();
  CLI::App* command = app.add_subcommand(
      "plan",
      "Measure the FFT plans of `podid cwt` and identification for these records ahead of\n"
      "time, into the cache $XDG_CACHE_HOME/podid (else ~/.cache/podid). Without it each\n"
      "process uses quick estimated plans. Exit status 1, before measuring where it can\n"
      "be seen, if the cache cannot be written. docs/wavelet.md, \"Planning\"");
  command->add_option("data", a->data,
                      "Time series (.csv, .mat, .uff or .unv) whose length and step to plan for,\n"
                      "read and conditioned with the data options below as cwt reads them");
  a->reading.AddTo(*command);
  command->add_option("--samples", a->samples, "Record lengths N[,N...] (4..67108864), with --fs")
      ->type_name("N[,N...]");
  a->fs_option =
      command->add_option("--fs", a->fs_Hz, "Sampling frequency (Hz) of --samples, 1e-15..1e15");
  a->grid.AddTo(*command, "Highest analysis frequency (Hz), capped at Nyquist");
  a->wavelet.AddTo(*command, " to plan for, as for cwt");
  command->add_option("--padding", a->padding,
                      "reflect, zero or periodic (default: both cwt's zero and\n"
                      "identification's reflect)");
  command
      ->add_option("--effort", a->effort,
                   "measure (FFTW_MEASURE, seconds) or patient (FFTW_PATIENT: minutes at\n"
                   "10^5 samples, transforms up to about 1.07x faster)")
      ->check(CLI::IsMember({"measure", "patient"}))
      ->capture_default_str();
  command->callback([a] { Run(*a); });
}

}  // namespace podid::cli
