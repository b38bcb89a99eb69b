#include "podid/core/time_series.hpp"

#include "podid/core/error.hpp"

namespace podid {

double TimeSeries::step_s() const {
  PODID_CHECK(time_s.size() >= 2);
  return (time_s(time_s.size() - 1) - time_s(0)) / static_cast<double>(time_s.size() - 1);
}

int TimeSeries::ChannelIndex(const std::string& name) const {
  for (std::size_t i = 0; i < channel_names.size(); ++i) {
    if (channel_names[i] == name) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace podid
