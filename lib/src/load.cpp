#include "podid/core/load.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "podid/core/error.hpp"
#include "podid/core/interpolate.hpp"

namespace podid {
namespace {

/// What a force or the base says about its time history (ForceSpec, BaseSpec).
struct History {
  ForceType type = ForceType::kNone;
  double amplitude = 0.0, frequency_Hz = 0.0, start_frequency_Hz = 0.0, end_frequency_Hz = 0.0;
  double gain = 1.0, offset = 0.0;
  const Eigen::VectorXd* file_time_s = nullptr;
  const Eigen::VectorXd* file_values = nullptr;
};

History Of(const ForceSpec& f) {
  return {f.type, f.amplitude_N, f.frequency_Hz, f.start_frequency_Hz, f.end_frequency_Hz,
          f.gain, f.offset_N, &f.file_time_s, &f.file_values};
}

History Of(const BaseSpec& b) {
  return {b.type, b.amplitude_m_per_s2, b.frequency_Hz, b.start_frequency_Hz, b.end_frequency_Hz,
          b.gain, b.offset_m_per_s2, &b.file_time_s, &b.file_values};
}

/// The history on the integration grid (dim (samples - 1) substeps + 1).
Eigen::VectorXd Sample(const History& f, const CaseSpec& spec) {
  const int samples = spec.time.samples();
  const double dt = spec.time.step_s;
  const double duration = (samples - 1) * dt;
  // Sub-stepping: analytic histories at the fine times; a sampled one on the
  // data's grid here, interpolated band-limited below.
  const bool sampled = f.type == ForceType::kFile || f.type == ForceType::kChannel;
  const int k = sampled ? 1 : spec.integrator.substeps;
  const int count = (samples - 1) * k + 1;
  Eigen::VectorXd values(count);
  constexpr double kTwoPi = 2 * std::numbers::pi;
  for (int i = 0; i < count; ++i) {
    const double t = i * dt / k;                 // from the simulation's start
    const double t_abs = spec.time.start_s + t;  // on the record's time axis
    double value = 0.0;
    switch (f.type) {
      case ForceType::kHarmonic:
        value = f.amplitude * std::sin(kTwoPi * f.frequency_Hz * t);
        break;
      case ForceType::kSweep:  // linear sweep: phase = 2 pi (f0 t + (f1 - f0) t^2 / (2 T))
        value = f.amplitude *
                std::sin(kTwoPi * (f.start_frequency_Hz * t +
                                   (f.end_frequency_Hz - f.start_frequency_Hz) * t * t / (2 * duration)));
        break;
      case ForceType::kFile:
      case ForceType::kChannel: {
        const Eigen::VectorXd& ft = *f.file_time_s;
        const Eigen::VectorXd& fv = *f.file_values;
        PODID_CHECK(ft.size() == fv.size());
        if (ft.size() >= 2 && t_abs >= ft[0] && t_abs <= ft[ft.size() - 1]) {
          // Linear interpolation on the (uniform, increasing) file time grid.
          const double h = (ft[ft.size() - 1] - ft[0]) / static_cast<double>(ft.size() - 1);
          const Eigen::Index j =
              std::min<Eigen::Index>(static_cast<Eigen::Index>((t_abs - ft[0]) / h), ft.size() - 2);
          const double s = (t_abs - ft[j]) / (ft[j + 1] - ft[j]);
          value = f.gain * ((1 - s) * fv[j] + s * fv[j + 1]) + f.offset;
        }
        break;
      }
      case ForceType::kNone:
        break;
    }
    values[i] = value;
  }
  if (sampled && spec.integrator.substeps > 1) values = InterpolateBandLimited(values, spec.integrator.substeps);
  return values;
}

}  // namespace

Eigen::VectorXd BaseInfluence(const CaseSpec& spec, int n_dofs) {
  if (spec.base.type == ForceType::kNone) return {};
  if (spec.model.type == ModelType::kMatrices) {
    if (spec.base.influence.size() != n_dofs) {
      ThrowInvalid("base.influence", ToText(n_dofs) + " values (one per model dof)",
                   ToText(spec.base.influence.size()));
    }
    return spec.base.influence;
  }
  Eigen::VectorXd r = Eigen::VectorXd::Zero(n_dofs);
  for (int node = 0; node <= spec.beam.elements; ++node) {
    const int d = BeamDof(spec.beam, node, SensorDof::kW);
    if (d >= 0) r[d] = 1.0;
  }
  return r;
}

Eigen::VectorXd BaseMassInfluence(const CaseSpec& spec, const BeamModel& model) {
  const int n = model.dofs();
  if (spec.model.type == ModelType::kMatrices) return model.mass() * BaseInfluence(spec, n);
  // The unconstrained beam (both ends free; its masses, no springs, damping or
  // elements, which M does not depend on): M_full r_full, r_full = 1 on every w.
  CaseSpec free = spec;
  free.beam.left = free.beam.right = BeamEnd::kFree;
  free.springs.clear();
  free.damping = DampingSpec{};
  free.nonlinearities.clear();
  free.initial = InitialSpec{};
  const BeamModel full = BeamModel::Build(free);
  Eigen::VectorXd r_full = Eigen::VectorXd::Zero(full.dofs());
  for (int node = 0; node <= spec.beam.elements; ++node) r_full[BeamDof(free.beam, node, SensorDof::kW)] = 1.0;
  const Eigen::VectorXd m_r_full = full.mass() * r_full;
  Eigen::VectorXd m_r = Eigen::VectorXd::Zero(n);
  for (int node = 0; node <= spec.beam.elements; ++node) {
    for (const SensorDof which : {SensorDof::kW, SensorDof::kTheta}) {
      const int d = BeamDof(spec.beam, node, which);
      if (d >= 0) m_r[d] = m_r_full[BeamDof(free.beam, node, which)];
    }
  }
  return m_r;
}

namespace {

/// model: needed for [base] only (M r).
ExternalLoad Build(const CaseSpec& spec, int n, const BeamModel* model) {
  std::vector<const ForceSpec*> forces;
  if (spec.force.type != ForceType::kNone) forces.push_back(&spec.force);
  for (const ForceSpec& f : spec.forces)
    if (f.type != ForceType::kNone) forces.push_back(&f);
  const bool base = spec.base.type != ForceType::kNone;
  const int columns = static_cast<int>(forces.size()) + (base ? 1 : 0);
  ExternalLoad load;
  if (columns == 0) return load;
  const int count = (spec.time.samples() - 1) * spec.integrator.substeps + 1;
  load.history.resize(columns, count);
  std::vector<Eigen::Triplet<double>> pattern;
  for (std::size_t k = 0; k < forces.size(); ++k) {
    const ForceSpec& f = *forces[k];
    // Keys as in the file: force.node for the single [force], force.<i>.node for [[force]].
    std::string key = "force";
    if (&f != &spec.force) key += "." + ToText(&f - spec.forces.data());
    const int dof = ResolveDof(spec, f.node, f.dof, SensorDof::kW, key + (f.dof > 0 ? ".dof" : ".node"));
    pattern.emplace_back(dof, static_cast<int>(k), 1.0);
    load.history.row(static_cast<Eigen::Index>(k)) = Sample(Of(f), spec).transpose();
  }
  if (base) {
    const int k = columns - 1;
    PODID_CHECK(model != nullptr);
    const Eigen::VectorXd m_r = BaseMassInfluence(spec, *model);
    for (int i = 0; i < n; ++i)
      if (m_r[i] != 0.0) pattern.emplace_back(i, k, -m_r[i]);  // -M r a_g
    load.history.row(k) = Sample(Of(spec.base), spec).transpose();
    load.base_row = k;
    load.base_influence = BaseInfluence(spec, n);
  }
  load.pattern.resize(n, columns);
  load.pattern.setFromTriplets(pattern.begin(), pattern.end());
  return load;
}

}  // namespace

ExternalLoad BuildLoad(const CaseSpec& spec, const BeamModel& model) {
  return Build(spec, model.dofs(), &model);
}

ExternalLoad BuildLoad(const CaseSpec& spec) {
  if (spec.base.type == ForceType::kNone) return Build(spec, spec.dofs(), nullptr);
  const BeamModel model = BeamModel::Build(spec);
  return Build(spec, model.dofs(), &model);
}

}  // namespace podid
