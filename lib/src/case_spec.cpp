#include "podid/core/case_spec.hpp"

#include <cmath>

namespace podid {

int TimeSpec::samples() const {
  if (!(step_s > 0.0) || !(duration_s >= 0.0)) return 0;
  return static_cast<int>(std::llround(duration_s / step_s)) + 1;
}

std::vector<std::string> SensorSpec::ChannelNames() const {
  if (!names.empty()) return names;
  std::vector<std::string> out;
  if (!dofs.empty()) {
    out.reserve(dofs.size());
    for (const int dof : dofs) out.push_back("x" + std::to_string(dof));
    return out;
  }
  const char* prefix = dof == SensorDof::kW ? "w" : "theta";
  out.reserve(nodes.size());
  for (const int node : nodes) out.push_back(prefix + std::to_string(node));
  return out;
}

namespace {
// Free dofs of an end node: clamped none, pinned theta, free both.
int EndDofs(BeamEnd end) { return end == BeamEnd::kClamped ? 0 : (end == BeamEnd::kPinned ? 1 : 2); }
}  // namespace

int BeamDof(const BeamSpec& beam, int node, SensorDof which) {
  const int n = beam.elements;
  if (node < 0 || node > n || n < 1) return -1;
  const bool w = which == SensorDof::kW;
  auto at_end = [w](BeamEnd end, int offset) {
    if (end == BeamEnd::kClamped) return -1;
    if (end == BeamEnd::kPinned) return w ? -1 : offset;
    return offset + (w ? 0 : 1);
  };
  const int first = EndDofs(beam.left);
  if (node == 0) return at_end(beam.left, 0);
  const int offset = first + 2 * (node - 1);
  if (node < n) return offset + (w ? 0 : 1);
  return at_end(beam.right, offset);
}

int BeamDofCount(const BeamSpec& beam) {
  if (beam.elements < 1) return 0;
  return EndDofs(beam.left) + 2 * (beam.elements - 1) + EndDofs(beam.right);
}

const char* ToString(BeamEnd end) {
  switch (end) {
    case BeamEnd::kClamped: return "clamped";
    case BeamEnd::kPinned: return "pinned";
    case BeamEnd::kFree: return "free";
  }
  return "unknown";
}

int CaseSpec::dofs() const {
  if (model.type == ModelType::kMatrices) {
    return model.matrices ? static_cast<int>(model.matrices->mass.rows()) : 0;
  }
  return BeamDofCount(beam);
}

}  // namespace podid
