#include "podid/core/recording.hpp"

#include "podid/core/conditioning.hpp"
#include "podid/core/error.hpp"

namespace podid {

TimeSeries ConditionMeasured(const CaseSpec& spec,
                             const TimeSeries& raw,
                             const std::string& where,
                             std::vector<std::string>* notes) {
  TimeSeries out = ConditionRecord(raw, spec.data.conditioning, where);
  const std::vector<std::string>& chosen = spec.data.conditioning.channels;
  if (chosen.empty()) return out;
  const std::vector<std::string> sensors = spec.sensors.ChannelNames();
  if (chosen.size() != sensors.size()) {
    ThrowInvalid(spec.source + ": data.channels",
                 ToText(sensors.size()) + " channels, one per sensor of the case",
                 ToText(chosen.size()) + " channels");
  }
  for (std::size_t i = 0; i < chosen.size(); ++i) {
    if (chosen[i] != sensors[i] && notes != nullptr) {
      notes->push_back(where + ": channel " + chosen[i] + " is sensor " + sensors[i]);
    }
  }
  out.channel_names = sensors;
  return out;
}

TimeSeries ConditionSimulated(const CaseSpec& spec, const TimeSeries& sensors) {
  ConditioningOptions options = spec.data.conditioning;
  options.channels.clear();
  if (options.IsIdentity()) return sensors;
  return ConditionRecord(sensors, options, "simulated sensors");
}

}  // namespace podid
