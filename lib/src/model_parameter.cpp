#include "podid/core/model_parameter.hpp"

#include <charconv>
#include <cmath>
#include <optional>
#include <vector>

#include "podid/core/case_file.hpp"
#include "podid/core/error.hpp"

namespace podid {
namespace {

constexpr const char* kTypedForms =
    "a real-valued case-file key, e.g. nonlinearity.N.k3, damping.modal_ratios.N, "
    "damping.alpha, beam.youngs_modulus, beam.segment.N.youngs_modulus, mass.N.mass, "
    "spring.N.stiffness, force.amplitude, force.N.gain, base.amplitude, initial.static_tip_force";

std::vector<std::string_view> Split(std::string_view key) {
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = key.find('.', start);
    parts.push_back(key.substr(start, dot == std::string_view::npos ? dot : dot - start));
    if (dot == std::string_view::npos) return parts;
    start = dot + 1;
  }
}

/// The index in `part`, or -1 when it is not a plain non-negative integer.
int Index(std::string_view part) {
  int value = -1;
  const auto [end, error] = std::from_chars(part.data(), part.data() + part.size(), value);
  if (error != std::errc() || end != part.data() + part.size() || value < 0) return -1;
  return value;
}

}  // namespace

const char* ToString(ParameterEffect effect) {
  switch (effect) {
    case ParameterEffect::kNonlinear: return "nonlinear coefficient";
    case ParameterEffect::kLoad: return "load";
    case ParameterEffect::kInitialState: return "initial state";
    case ParameterEffect::kDamping: return "damping";
    case ParameterEffect::kModel: return "model";
    case ParameterEffect::kDocument: return "document";
  }
  return "?";
}

ModelParameter ModelParameter::Resolve(const CaseSpec& spec, std::string_view key) {
  if (!CaseDocument::IsNumericKey(key)) ThrowInvalid("parameter key", kTypedForms, Excerpt(key));
  ModelParameter p;
  p.key_ = std::string(key);
  const std::vector<std::string_view> parts = Split(key);
  // A typed key addresses a table the case has; "what" names what is missing.
  auto table = [&](std::size_t count, const char* what) {
    const int i = Index(parts[1]);
    if (i < 0 || static_cast<std::size_t>(i) >= count) {
      ThrowInvalid("parameter key " + p.key_,
                   std::string("an index of the case's ") + what + " (0.." +
                       (count == 0 ? std::string("none") : ToText(count - 1)) + ")",
                   std::string(parts[1]));
    }
    return i;
  };
  auto unused = [&](const std::string& why) {
    ThrowInvalid("parameter key " + p.key_, "a value the case uses", why);
  };
  auto set = [&p](ParameterEffect effect, Field field, Range range, int index = 0) {
    p.effect_ = effect;
    p.field_ = field;
    p.range_ = range;
    p.index_ = index;
    return p;
  };
  const std::string_view head = parts[0];
  const bool beam = spec.model.type == ModelType::kBeam;
  if (head == "nonlinearity" && parts.size() == 3) {
    const int i = table(spec.nonlinearities.size(), "[[nonlinearity]] tables");
    const NonlinearType type = spec.nonlinearities[i].type;
    const std::string_view f = parts[2];
    const bool polynomial = type == NonlinearType::kPolynomial;
    using E = ParameterEffect;
    if (f == "k3" && (polynomial || type == NonlinearType::kCubic))
      return set(E::kNonlinear, Field::kK3, Range::kAny, i);
    if (f == "k1" && polynomial) return set(E::kNonlinear, Field::kK1, Range::kAny, i);
    if (f == "k2" && polynomial) return set(E::kNonlinear, Field::kK2, Range::kAny, i);
    if (f == "gap" && type == NonlinearType::kGap)
      return set(E::kNonlinear, Field::kGap, Range::kNonNegative, i);
    if (f == "stiffness" && type == NonlinearType::kGap)
      return set(E::kNonlinear, Field::kContactStiffness, Range::kPositive, i);
    if (f == "mu" && type == NonlinearType::kFriction)
      return set(E::kNonlinear, Field::kMu, Range::kNonNegative, i);
    if (f == "normal_force" && type == NonlinearType::kFriction)
      return set(E::kNonlinear, Field::kNormalForce, Range::kNonNegative, i);
    if (f == "velocity_scale" && type == NonlinearType::kFriction)
      return set(E::kNonlinear, Field::kVelocityScale, Range::kPositive, i);
    unused("a coefficient the element's type does not have");
  }
  if (head == "damping") {
    const DampingSpec& d = spec.damping;
    if (d.type != DampingType::kRayleigh) unused("no [damping] in the case");
    if (parts.size() == 3 && parts[1] == "modal_ratios") {
      if (!d.from_modal_ratios) unused("damping given by alpha/beta, not modal_ratios");
      const int j = Index(parts[2]);
      if (j < 0 || j > 1) ThrowInvalid("parameter key " + p.key_, "damping.modal_ratios.0 or .1", std::string(parts[2]));
      return set(ParameterEffect::kDamping, Field::kModalRatio, Range::kRatio, j);
    }
    if (parts.size() == 2 && (parts[1] == "alpha" || parts[1] == "beta")) {
      if (d.from_modal_ratios) unused("damping given by modal_ratios, not alpha/beta");
      return set(ParameterEffect::kDamping, parts[1] == "alpha" ? Field::kAlpha : Field::kBeta,
                 Range::kNonNegative);
    }
  }
  if (head == "beam" && beam) {
    if (parts.size() == 2 && spec.beam.segments.empty()) {
      if (parts[1] == "youngs_modulus") return set(ParameterEffect::kModel, Field::kBeamModulus, Range::kPositive);
      if (parts[1] == "density") return set(ParameterEffect::kModel, Field::kBeamDensity, Range::kPositive);
    }
    if (parts.size() == 4 && parts[1] == "segment") {
      const std::size_t count = spec.beam.segments.size();
      const int i = Index(parts[2]);
      if (i < 0 || static_cast<std::size_t>(i) >= count) {
        ThrowInvalid("parameter key " + p.key_,
                     "an index of the case's [[beam.segment]] tables (0.." +
                         (count == 0 ? std::string("none") : ToText(count - 1)) + ")",
                     std::string(parts[2]));
      }
      if (parts[3] == "youngs_modulus") return set(ParameterEffect::kModel, Field::kSegmentModulus, Range::kPositive, i);
      if (parts[3] == "density") return set(ParameterEffect::kModel, Field::kSegmentDensity, Range::kPositive, i);
    }
  }
  if (head == "mass" && parts.size() == 3) {
    const int i = table(spec.masses.size(), "[[mass]] tables");
    if (parts[2] == "mass") return set(ParameterEffect::kModel, Field::kMass, Range::kNonNegative, i);
    return set(ParameterEffect::kModel, Field::kInertia, Range::kNonNegative, i);
  }
  if (head == "spring" && parts.size() == 3) {
    const int i = table(spec.springs.size(), "[[spring]] tables");
    if (parts[2] == "stiffness") return set(ParameterEffect::kModel, Field::kSpringStiffness, Range::kNonNegative, i);
    return set(ParameterEffect::kModel, Field::kSpringDamping, Range::kNonNegative, i);
  }
  // A force's or the base's history (ExcitationHistory): the fields its type
  // has; index as HistoryOf reads it.
  auto history = [&](ForceType t, std::string_view f, int index) -> std::optional<ModelParameter> {
    const bool sampled = t == ForceType::kFile || t == ForceType::kChannel;
    if (f == "amplitude" && (t == ForceType::kHarmonic || t == ForceType::kSweep))
      return set(ParameterEffect::kLoad, Field::kHistoryAmplitude, Range::kAny, index);
    if (f == "frequency" && t == ForceType::kHarmonic)
      return set(ParameterEffect::kLoad, Field::kHistoryFrequency, Range::kPositive, index);
    if (f == "start_frequency" && t == ForceType::kSweep)
      return set(ParameterEffect::kLoad, Field::kHistoryStartFrequency, Range::kPositive, index);
    if (f == "end_frequency" && t == ForceType::kSweep)
      return set(ParameterEffect::kLoad, Field::kHistoryEndFrequency, Range::kPositive, index);
    if (f == "gain" && sampled)
      return set(ParameterEffect::kLoad, Field::kHistoryGain, Range::kAny, index);
    if (f == "offset" && sampled)
      return set(ParameterEffect::kLoad, Field::kHistoryOffset, Range::kAny, index);
    if (f == "amplitude" || f == "frequency" || f == "start_frequency" || f == "end_frequency" ||
        f == "gain" || f == "offset")
      unused(std::string("a value the case's ") + (index == kBaseIndex ? "base" : "force") +
             ".type does not have");
    return std::nullopt;
  };
  if (head == "force" && parts.size() == 2) {
    if (!spec.forces.empty()) unused("the case has [[force]] tables: force.<i>." + std::string(parts[1]));
    if (auto q = history(spec.force.history_N.type, parts[1], kForceIndex)) return *q;
  }
  if (head == "force" && parts.size() == 3) {
    const int i = table(spec.forces.size(), "[[force]] tables");
    if (auto q = history(spec.forces[static_cast<std::size_t>(i)].history_N.type, parts[2], i))
      return *q;
  }
  if (head == "base" && parts.size() == 2) {
    if (auto q = history(spec.base.history_m_per_s2.type, parts[1], kBaseIndex)) return *q;
  }
  if (head == "initial" && parts.size() == 2 &&
      (parts[1] == "static_tip_force" || parts[1] == "static_force")) {
    if (spec.initial.type != InitialType::kStaticForce) unused("no static initial force in the case");
    return set(ParameterEffect::kInitialState, Field::kStaticForce, Range::kAny);
  }
  p.effect_ = ParameterEffect::kDocument;  // checked by the document
  return p;
}

ExcitationHistory& ModelParameter::HistoryOf(CaseSpec* spec) const {
  if (index_ == kBaseIndex) return spec->base.history_m_per_s2;
  return index_ == kForceIndex ? spec->force.history_N
                               : spec->forces.at(static_cast<std::size_t>(index_)).history_N;
}

double* ModelParameter::FieldOf(CaseSpec* spec) const {
  const auto i = static_cast<std::size_t>(index_);
  switch (field_) {
    case Field::kK1: return &spec->nonlinearities.at(i).k1_N_per_m;
    case Field::kK2: return &spec->nonlinearities.at(i).k2_N_per_m2;
    case Field::kK3: return &spec->nonlinearities.at(i).k3_N_per_m3;
    case Field::kGap: return &spec->nonlinearities.at(i).gap_m;
    case Field::kContactStiffness: return &spec->nonlinearities.at(i).contact_stiffness_N_per_m;
    case Field::kMu: return &spec->nonlinearities.at(i).friction_coefficient;
    case Field::kNormalForce: return &spec->nonlinearities.at(i).normal_force_N;
    case Field::kVelocityScale: return &spec->nonlinearities.at(i).regularisation_velocity_m_per_s;
    case Field::kAlpha: return &spec->damping.alpha_per_s;
    case Field::kBeta: return &spec->damping.beta_s;
    case Field::kModalRatio: return &spec->damping.modal_ratios.at(i);
    case Field::kBeamModulus: return &spec->beam.youngs_modulus_Pa;
    case Field::kBeamDensity: return &spec->beam.density_kg_per_m3;
    case Field::kSegmentModulus: return &spec->beam.segments.at(i).youngs_modulus_Pa;
    case Field::kSegmentDensity: return &spec->beam.segments.at(i).density_kg_per_m3;
    case Field::kMass: return &spec->masses.at(i).mass_kg;
    case Field::kInertia: return &spec->masses.at(i).inertia_kg_m2;
    case Field::kSpringStiffness: return &spec->springs.at(i).stiffness;
    case Field::kSpringDamping: return &spec->springs.at(i).damping;
    case Field::kHistoryAmplitude: return &HistoryOf(spec).amplitude;
    case Field::kHistoryFrequency: return &HistoryOf(spec).frequency_Hz;
    case Field::kHistoryStartFrequency: return &HistoryOf(spec).start_frequency_Hz;
    case Field::kHistoryEndFrequency: return &HistoryOf(spec).end_frequency_Hz;
    case Field::kHistoryGain: return &HistoryOf(spec).gain;
    case Field::kHistoryOffset: return &HistoryOf(spec).offset;
    case Field::kStaticForce: return &spec->initial.static_force_N;
    case Field::kNone: break;
  }
  return nullptr;
}

double ModelParameter::Get(const CaseSpec& spec) const {
  PODID_CHECK(typed());
  return *FieldOf(const_cast<CaseSpec*>(&spec));  // read only
}

bool ModelParameter::Set(double value, CaseSpec* spec, std::string* why) const {
  PODID_CHECK(typed() && spec != nullptr);
  const char* expected = nullptr;
  switch (range_) {
    case Range::kAny: expected = std::isfinite(value) ? nullptr : "a finite number"; break;
    case Range::kNonNegative: expected = value >= 0 && std::isfinite(value) ? nullptr : "a finite value >= 0"; break;
    case Range::kPositive: expected = value > 0 && std::isfinite(value) ? nullptr : "a finite value > 0"; break;
    case Range::kRatio: expected = value >= 0 && value < 1 ? nullptr : "a damping ratio in [0, 1)"; break;
  }
  if (expected != nullptr) {
    if (why) {
      try {
        *why = key_ + ": expected " + expected + ", got " + ToText(value);
      } catch (...) {  // no memory for the reason: the value is still rejected
      }
    }
    return false;
  }
  *FieldOf(spec) = value;
  return true;
}

}  // namespace podid
