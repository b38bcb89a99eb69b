#include "data_arguments.hpp"

#include <cstdio>

#include "podid/core/error.hpp"

namespace podid::cli {

void DataArguments::AddTo(CLI::App& command, const std::string& prefix) {
  command.add_option("--" + prefix + "variable", variable,
                     "The .mat variable or struct to read (default: the first matrix, vectors or "
                     "struct of channels)");
  command
      .add_option("--" + prefix + "channels", channels,
                  "Channels to keep, in this order, by name, e.g. --channels 1+X,3+Z")
      ->type_name("A,B,...");
  rate_option_ = command.add_option("--" + prefix + "rate", rate_Hz,
                                    "Sampling rate (Hz) of a file without time, e.g. 610.3515625");
  step_option_ = command.add_option("--" + prefix + "step", step_s,
                                    "Sampling step (s) of a file without time");
  rate_option_->excludes(step_option_);
}

DataReadOptions DataArguments::Options() const {
  DataReadOptions options;
  options.variable = variable;
  options.rate_Hz = rate_Hz;
  options.step_s = step_s;
  if (!channels.empty()) {
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = channels.find(',', start);
      options.channels.push_back(
          channels.substr(start, comma == std::string::npos ? comma : comma - start));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  if (rate_option_ != nullptr && rate_option_->count() > 0 && !(rate_Hz > 0.0)) {
    ThrowInvalid(rate_option_->get_name(), "a sampling rate > 0 Hz", ToText(rate_Hz));
  }
  if (step_option_ != nullptr && step_option_->count() > 0 && !(step_s > 0.0)) {
    ThrowInvalid(step_option_->get_name(), "a sampling step > 0 s", ToText(step_s));
  }
  options.Check();
  return options;
}

TimeSeries DataArguments::Read(const std::string& path) const {
  std::vector<std::string> notes;
  TimeSeries series = ReadTimeSeries(path, Options(), &notes);
  for (const std::string& note : notes) std::fprintf(stderr, "podid: note: %s\n", note.c_str());
  return series;
}

}  // namespace podid::cli
