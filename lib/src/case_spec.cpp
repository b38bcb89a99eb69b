#include "podid/core/case_spec.hpp"

#include <cmath>

namespace podid {

int TimeSpec::samples() const {
  if (!(step_s > 0.0) || !(duration_s >= 0.0)) return 0;
  return static_cast<int>(std::llround(duration_s / step_s)) + 1;
}

std::vector<std::string> SensorSpec::ChannelNames() const {
  const char* prefix = dof == SensorDof::kW ? "w" : "theta";
  std::vector<std::string> names;
  names.reserve(nodes.size());
  for (const int node : nodes) names.push_back(prefix + std::to_string(node));
  return names;
}

}  // namespace podid
