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

/// A file or channel history's parts on the data's grid (time.start_s + i dt):
/// the column linearly interpolated within the file (u 1_in), and 1_in, 1
/// where the record's time is inside the file's range, 0 outside.
void SampleFile(const ExcitationHistory& f,
                const CaseSpec& spec,
                Eigen::VectorXd* u_inside,
                Eigen::VectorXd* inside) {
  const int samples = spec.time.samples();
  const double dt = spec.time.step_s;
  const Eigen::VectorXd& ft = f.file_time_s;
  const Eigen::VectorXd& fv = f.file_values;
  PODID_CHECK(ft.size() == fv.size());
  u_inside->setZero(samples);
  inside->setZero(samples);
  for (int i = 0; i < samples; ++i) {
    const double t_abs = spec.time.start_s + i * dt;  // on the record's time axis
    if (ft.size() >= 2 && t_abs >= ft[0] && t_abs <= ft[ft.size() - 1]) {
      // Linear interpolation on the (uniform, increasing) file time grid.
      const double h = (ft[ft.size() - 1] - ft[0]) / static_cast<double>(ft.size() - 1);
      const Eigen::Index j =
          std::min<Eigen::Index>(static_cast<Eigen::Index>((t_abs - ft[0]) / h), ft.size() - 2);
      const double s = (t_abs - ft[j]) / (ft[j + 1] - ft[j]);
      (*u_inside)[i] = (1 - s) * fv[j] + s * fv[j + 1];
      (*inside)[i] = 1.0;
    }
  }
}

bool Equal(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == b.size() && (a.array() == b.array()).all();
}

}  // namespace

struct LoadCache::Entry {
  Eigen::VectorXd file_time_s, file_values;  // the key, with the grid
  double start_s = 0.0, step_s = 0.0;
  int samples = 0, substeps = 0;
  Eigen::VectorXd u_inside, inside;  // on the integration grid; inside empty: all 1
  bool used = false;
};

LoadCache::LoadCache() = default;
LoadCache::~LoadCache() = default;
LoadCache::LoadCache(LoadCache&&) noexcept = default;
LoadCache& LoadCache::operator=(LoadCache&&) noexcept = default;

struct LoadCacheAccess {
  /// The entry of f's column on spec's grid, computed if absent. cache may be
  /// null (then *scratch holds it).
  static const LoadCache::Entry& Find(const ExcitationHistory& f,
                                      const CaseSpec& spec,
                                      LoadCache* cache,
                                      LoadCache::Entry* scratch) {
    if (cache != nullptr) {
      for (LoadCache::Entry& e : cache->entries_) {
        if (e.start_s == spec.time.start_s && e.step_s == spec.time.step_s &&
            e.samples == spec.time.samples() && e.substeps == spec.integrator.substeps &&
            Equal(e.file_time_s, f.file_time_s) && Equal(e.file_values, f.file_values)) {
          e.used = true;
          return e;
        }
      }
    }
    LoadCache::Entry e;
    e.start_s = spec.time.start_s;
    e.step_s = spec.time.step_s;
    e.samples = spec.time.samples();
    e.substeps = spec.integrator.substeps;
    SampleFile(f, spec, &e.u_inside, &e.inside);
    if (e.substeps > 1) e.u_inside = InterpolateBandLimited(e.u_inside, e.substeps);
    if ((e.inside.array() == 1.0).all()) {
      e.inside.resize(0);  // the file covers the record: 1_in = 1, and so is its interpolation
    } else if (e.substeps > 1) {
      e.inside = InterpolateBandLimited(e.inside, e.substeps);
    }
    e.used = true;
    if (cache == nullptr) {
      *scratch = std::move(e);
      return *scratch;
    }
    e.file_time_s = f.file_time_s;
    e.file_values = f.file_values;
    ++cache->misses_;
    cache->entries_.push_back(std::move(e));
    return cache->entries_.back();
  }
  static void StartBuild(LoadCache* cache) {
    if (cache != nullptr)
      for (LoadCache::Entry& e : cache->entries_) e.used = false;
  }
  static void EndBuild(LoadCache* cache) {
    if (cache == nullptr) return;
    std::erase_if(cache->entries_, [](const LoadCache::Entry& e) { return !e.used; });
  }
};

namespace {

/// The history on the integration grid (dim (samples - 1) substeps + 1).
Eigen::VectorXd Sample(const ExcitationHistory& f, const CaseSpec& spec, LoadCache* cache) {
  if (f.type == ForceType::kFile || f.type == ForceType::kChannel) {
    // gain (u 1_in) + offset 1_in, interpolated band-limited with sub-steps
    // (linear: the cached interpolations of the two parts, rescaled).
    LoadCache::Entry scratch;
    const LoadCache::Entry& e = LoadCacheAccess::Find(f, spec, cache, &scratch);
    if (e.inside.size() == 0) return (f.gain * e.u_inside.array() + f.offset).matrix();
    return (f.gain * e.u_inside.array() + f.offset * e.inside.array()).matrix();
  }
  const int samples = spec.time.samples();
  const double dt = spec.time.step_s;
  const double duration = (samples - 1) * dt;
  // Sub-stepping: analytic histories at the fine times.
  const int k = spec.integrator.substeps;
  const int count = (samples - 1) * k + 1;
  Eigen::VectorXd values(count);
  constexpr double kTwoPi = 2 * std::numbers::pi;
  for (int i = 0; i < count; ++i) {
    const double t = i * dt / k;  // from the simulation's start
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
      default:
        break;
    }
    values[i] = value;
  }
  return values;
}

}  // namespace

Eigen::VectorXd BaseInfluence(const CaseSpec& spec, int n_dofs) {
  if (spec.base.history_m_per_s2.type == ForceType::kNone) return {};
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

/// model: needed for [base] only (M r); cache may be null.
ExternalLoad Build(const CaseSpec& spec, int n, const BeamModel* model, LoadCache* cache) {
  std::vector<const ForceSpec*> forces;
  if (spec.force.history_N.type != ForceType::kNone) forces.push_back(&spec.force);
  for (const ForceSpec& f : spec.forces)
    if (f.history_N.type != ForceType::kNone) forces.push_back(&f);
  const bool base = spec.base.history_m_per_s2.type != ForceType::kNone;
  const int columns = static_cast<int>(forces.size()) + (base ? 1 : 0);
  ExternalLoad load;
  LoadCacheAccess::StartBuild(cache);
  if (columns == 0) {
    LoadCacheAccess::EndBuild(cache);
    return load;
  }
  const int count = (spec.time.samples() - 1) * spec.integrator.substeps + 1;
  load.history.resize(columns, count);
  std::vector<Eigen::Triplet<double>> pattern;
  for (std::size_t k = 0; k < forces.size(); ++k) {
    const ForceSpec& f = *forces[k];
    // Keys as in the file: force.node for the single [force], force.<i>.node for [[force]].
    std::string key = "force";
    if (&f != &spec.force) {
      key += '.';  // appended in two steps: GCC 12 -O3 warns (-Wrestrict) on "." + string
      key += ToText(&f - spec.forces.data());
    }
    const int dof = ResolveDof(spec, f.node, f.dof, SensorDof::kW, key + (f.dof > 0 ? ".dof" : ".node"));
    pattern.emplace_back(dof, static_cast<int>(k), 1.0);
    load.history.row(static_cast<Eigen::Index>(k)) = Sample(f.history_N, spec, cache).transpose();
  }
  if (base) {
    const int k = columns - 1;
    PODID_CHECK(model != nullptr);
    const Eigen::VectorXd m_r = BaseMassInfluence(spec, *model);
    for (int i = 0; i < n; ++i)
      if (m_r[i] != 0.0) pattern.emplace_back(i, k, -m_r[i]);  // -M r a_g
    load.history.row(k) = Sample(spec.base.history_m_per_s2, spec, cache).transpose();
    load.base_row = k;
    load.base_influence = BaseInfluence(spec, n);
  }
  load.pattern.resize(n, columns);
  load.pattern.setFromTriplets(pattern.begin(), pattern.end());
  LoadCacheAccess::EndBuild(cache);
  return load;
}

}  // namespace

ExternalLoad BuildLoad(const CaseSpec& spec, const BeamModel& model) {
  return Build(spec, model.dofs(), &model, nullptr);
}

ExternalLoad BuildLoad(const CaseSpec& spec, const BeamModel& model, LoadCache* cache) {
  return Build(spec, model.dofs(), &model, cache);
}

ExternalLoad BuildLoad(const CaseSpec& spec) {
  if (spec.base.history_m_per_s2.type == ForceType::kNone)
    return Build(spec, spec.dofs(), nullptr, nullptr);
  const BeamModel model = BeamModel::Build(spec);
  return Build(spec, model.dofs(), &model, nullptr);
}

}  // namespace podid
