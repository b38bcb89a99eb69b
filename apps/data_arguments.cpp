#include "data_arguments.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "cli_common.hpp"
#include "mpi_session.hpp"
#include "podid/core/error.hpp"

namespace podid::cli {
namespace {

// "A:B" -> two numbers with A < B, or throws naming the option.
std::pair<double, double> ParsePair(const std::string& option,
                                    const std::string& text,
                                    const std::string& unit) {
  const std::size_t colon = text.find(':');
  const std::string expected = "START:END with START < END (" + unit + "), e.g. 0.5:2";
  if (colon == std::string::npos) ThrowInvalid(option, expected, Excerpt(text));
  const double a = ParseNumber(text.substr(0, colon), option, expected);
  const double b = ParseNumber(text.substr(colon + 1), option, expected);
  if (!(a < b)) ThrowInvalid(option, expected, Excerpt(text));
  return {a, b};
}

std::string Number(double x) {
  std::ostringstream os;
  os.precision(17);
  os << x;
  std::string s = os.str();
  if (s.find_first_of(".eE") == std::string::npos && s.find("inf") == std::string::npos) s += ".0";
  return s;
}

}  // namespace

std::string DataArguments::FirstGiven() const {
  for (const CLI::Option* option : added_) {
    if (option->count() > 0) return option->get_name();
  }
  return "";
}

void DataArguments::AddTo(CLI::App& command, const std::string& prefix) {
  const std::size_t before = command.get_options().size();
  prefix_ = prefix;
  const std::string p = "--" + prefix;
  command.add_option(p + "variable", variable,
                     "The .mat variable or struct to read (default: the first matrix, vectors or "
                     "struct of channels)");
  channels_option_ =
      command
          .add_option(
              p + "channels", channels,
              "Channels to keep, in this order, by name, e.g. --channels 1+X,3+Z (identify, "
              "landscape: the file's channels for the case's sensors, in order)")
          ->type_name("A,B,...");
  rate_option_ = command.add_option(p + "rate", rate_Hz,
                                    "Sampling rate (Hz) of a file without time, e.g. 610.3515625");
  step_option_ = command.add_option(p + "step", step_s, "Sampling step (s) of a file without time");
  rate_option_->excludes(step_option_);
  command.add_option(p + "window", window, "Keep the record's samples with START <= t <= END (s)")
      ->type_name("START:END");
  command
      .add_option(p + "detrend", detrend,
                  "Remove each channel's mean or line: none, constant, linear")
      ->check(CLI::IsMember({"none", "constant", "linear"}));
  lowpass_option_ = command.add_option(p + "lowpass", lowpass_Hz,
                                       "Zero-phase Butterworth low-pass at this cutoff (Hz)");
  highpass_option_ = command.add_option(p + "highpass", highpass_Hz,
                                        "Zero-phase Butterworth high-pass at this cutoff (Hz)");
  bandpass_option_ = command
                         .add_option(p + "bandpass", bandpass,
                                     "Zero-phase Butterworth band-pass between LOW and HIGH (Hz)")
                         ->type_name("LOW:HIGH");
  lowpass_option_->excludes(highpass_option_)->excludes(bandpass_option_);
  highpass_option_->excludes(bandpass_option_);
  order_option_ =
      command
          .add_option(p + "filter-order", filter_order,
                      "Butterworth order of the filter (a band-pass has twice the poles)")
          ->capture_default_str()
          ->check(IntegerIn(1, kMaxFilterOrder));
  command
      .add_option(
          p + "decimate", decimate,
          "Keep every Q-th sample after a zero-phase anti-alias low-pass (order 8, 0.8 x the "
          "new Nyquist frequency)")
      ->capture_default_str()
      ->check(IntegerIn(1, kMaxDecimation));
  const auto all = command.get_options();
  added_.assign(all.begin() + static_cast<std::ptrdiff_t>(before), all.end());
}

std::vector<std::string> DataArguments::ChannelList() const {
  std::vector<std::string> out;
  if (channels.empty()) return out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = channels.find(',', start);
    out.push_back(channels.substr(start, comma == std::string::npos ? comma : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

DataReadOptions DataArguments::Options() const {
  DataReadOptions options;
  options.variable = variable;
  options.rate_Hz = rate_Hz;
  options.step_s = step_s;
  options.channels = ChannelList();
  // Checked here to name the option: an empty list was taken for none given.
  if (channels_option_ != nullptr && channels_option_->count() > 0) {
    const std::string& option = channels_option_->get_name();
    if (channels.empty()) ThrowInvalid(option, "a list of channel names", "\"\"");
    for (std::size_t i = 0; i < options.channels.size(); ++i) {
      const std::string& name = options.channels[i];
      if (name.empty()) ThrowInvalid(option, "non-empty channel names", "an empty name");
      const auto earlier = options.channels.begin() + static_cast<std::ptrdiff_t>(i);
      if (std::find(options.channels.begin(), earlier, name) != earlier)
        ThrowInvalid(option, "distinct channel names", Excerpt(name) + " twice");
    }
  }
  // A subnormal value (1e-320) has an infinite reciprocal (IsSamplingStep).
  if (rate_option_ != nullptr && rate_option_->count() > 0 && !IsSamplingRate(rate_Hz)) {
    ThrowInvalid(rate_option_->get_name(),
                 "a finite sampling rate > 0 Hz with a finite step 1 / rate", ToText(rate_Hz));
  }
  if (step_option_ != nullptr && step_option_->count() > 0 && !IsSamplingStep(step_s)) {
    ThrowInvalid(step_option_->get_name(),
                 "a finite sampling step > 0 s with a finite rate 1 / step", ToText(step_s));
  }
  options.Check();
  return options;
}

ConditioningOptions DataArguments::Conditioning() const {
  ConditioningOptions c;
  const std::string p = "--" + prefix_;
  if (!window.empty()) {
    std::tie(c.window_start_s, c.window_end_s) = ParsePair(p + "window", window, "s");
  }
  c.detrend = detrend == "linear"     ? Detrend::kLinear
              : detrend == "constant" ? Detrend::kConstant
                                      : Detrend::kNone;
  auto positive = [](const std::string& option, double f) {
    if (!(f > 0.0 && std::isfinite(f))) ThrowInvalid(option, "a cutoff > 0 Hz", ToText(f));
    return f;
  };
  if (lowpass_option_ != nullptr && lowpass_option_->count() > 0) {
    c.filter.type = FilterType::kLowpass;
    c.filter.high_Hz = positive(p + "lowpass", lowpass_Hz);
  } else if (highpass_option_ != nullptr && highpass_option_->count() > 0) {
    c.filter.type = FilterType::kHighpass;
    c.filter.low_Hz = positive(p + "highpass", highpass_Hz);
  } else if (!bandpass.empty()) {
    c.filter.type = FilterType::kBandpass;
    std::tie(c.filter.low_Hz, c.filter.high_Hz) = ParsePair(p + "bandpass", bandpass, "Hz");
    positive(p + "bandpass", c.filter.low_Hz);
  } else if (order_option_ != nullptr && order_option_->count() > 0) {
    ThrowInvalid(p + "filter-order", "--lowpass, --highpass or --bandpass with it",
                 "--filter-order alone");
  }
  c.filter.order = filter_order;
  c.decimate = decimate;
  std::string why;
  if (!c.IsValid(&why)) throw std::invalid_argument(why);
  return c;
}

TimeSeries DataArguments::Read(const std::string& path) const {
  std::vector<std::string> notes;
  TimeSeries series = ReadTimeSeries(path, Options(), &notes);
  if (mpi::Rank() == 0) {  // under MPI, rank 0 speaks for every rank
    for (const std::string& note : notes) std::fprintf(stderr, "podid: note: %s\n", note.c_str());
  }
  return series;
}

TimeSeries DataArguments::ReadConditioned(const std::string& path) const {
  ConditioningOptions c = Conditioning();  // checked before reading
  c.channels.clear();                      // chosen by the reader already
  return ConditionRecord(Read(path), c, path);
}

std::vector<std::string> DataArguments::CaseSets(const std::string& path) const {
  (void)Options();  // the reading options' checks
  const ConditioningOptions c = Conditioning();
  // Named here: the case's own check would blame the case file for it.
  if (decimate != 1) {
    ThrowInvalid("--" + prefix_ + "decimate",
                 "1 for identify and landscape (the simulation runs on the measured grid; "
                 "decimate the file beforehand, or use podid pod)",
                 ToText(decimate));
  }
  std::vector<std::string> sets;
  if (!path.empty()) {
    sets.push_back("data.file=" + TomlString(std::filesystem::absolute(path).string()));
  }
  if (!variable.empty()) sets.push_back("data.variable=" + TomlString(variable));
  if (rate_Hz > 0.0) sets.push_back("data.rate=" + Number(rate_Hz));
  if (step_s > 0.0) sets.push_back("data.step=" + Number(step_s));
  const std::vector<std::string> list = ChannelList();
  if (!list.empty()) {
    std::string array = "[";
    for (const std::string& name : list) array += (array.size() > 1 ? ", " : "") + TomlString(name);
    sets.push_back("data.channels=" + array + "]");
  }
  if (!window.empty()) {
    sets.push_back("data.window=[" + Number(c.window_start_s) + ", " + Number(c.window_end_s) +
                   "]");
  }
  if (!detrend.empty()) sets.push_back("data.detrend=" + TomlString(detrend));
  if (c.filter.type != FilterType::kNone) {
    sets.push_back(std::string("data.filter=") + TomlString(ToString(c.filter.type)));
    sets.push_back("data.filter_order=" + std::to_string(c.filter.order));
    if (c.filter.type == FilterType::kBandpass) {
      sets.push_back("data.band=[" + Number(c.filter.low_Hz) + ", " + Number(c.filter.high_Hz) +
                     "]");
    } else {
      sets.push_back("data.cutoff=" + Number(c.filter.type == FilterType::kLowpass
                                                 ? c.filter.high_Hz
                                                 : c.filter.low_Hz));
    }
  }
  return sets;
}

}  // namespace podid::cli
