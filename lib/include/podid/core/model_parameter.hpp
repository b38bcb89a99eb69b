#pragma once
// Typed model parameters: a case-file key (docs/case-file.md, e.g.
// "nonlinearity.0.k3") resolved once against a CaseSpec into the field it
// writes and what a change of it invalidates, so that an identification can
// change the value on every evaluation without copying the TOML document,
// re-validating the schema or rebuilding more than needed (see Simulator,
// simulator.hpp). Units are SI, as in the CaseSpec field.
//
// Typed keys (i, j are 0-based indices of the case's tables):
//   nonlinearity.i.{k1,k2,k3,gap,stiffness,mu,normal_force,velocity_scale}
//                                      kNonlinear (no refactorisation)
//   damping.alpha, damping.beta, damping.modal_ratios.j
//                                      kDamping (C and the integrator)
//   beam.youngs_modulus, beam.density  (a beam without [[beam.segment]]),
//   beam.segment.i.{youngs_modulus,density}, mass.i.{mass,inertia},
//   spring.i.{stiffness,damping}       kModel (M, K, C and the integrator)
//   force.{amplitude,frequency,start_frequency,end_frequency,gain,offset}
//                                      kLoad (the single [force]; gain and
//                                      offset of file and channel forces)
//   force.i.{same fields}              kLoad (the i-th [[force]])
//   base.{amplitude,frequency,start_frequency,end_frequency,gain,offset}
//                                      kLoad ([base]'s acceleration)
//   initial.static_tip_force, initial.static_force             kInitialState
// Any other real-valued key of the schema (CaseDocument::IsNumericKey, e.g.
// beam.length, beam.width) is a kDocument parameter: it is set in a copy of
// the document and the case re-validated, as before typed parameters.

#include <string>
#include <string_view>

#include "podid/core/case_spec.hpp"

namespace podid {

/// What a change of the parameter invalidates, cheapest first.
enum class ParameterEffect {
  kNonlinear,     ///< a nonlinear element's coefficient: nothing refactored
                  ///< (the static initial state, if any, is re-solved)
  kLoad,          ///< the external load
  kInitialState,  ///< the initial (static) state
  kDamping,       ///< C, hence the integrator's matrices
  kModel,         ///< M or K (and C through Rayleigh damping): the model
  kDocument,      ///< a key without a typed binding: the whole case is rebuilt
};

const char* ToString(ParameterEffect effect);

class ModelParameter {
 public:
  /// Resolves `key` against `spec` (the case the values will be written
  /// into). Throws std::invalid_argument naming the key when it is not a
  /// real-valued key of the schema (expected: the forms listed above) or
  /// addresses a table the case does not have or a field its type does not
  /// use (e.g. nonlinearity.0.k1 of a cubic element, damping.alpha with modal
  /// ratios). A kDocument parameter is accepted here; the document checks it.
  static ModelParameter Resolve(const CaseSpec& spec, std::string_view key);

  const std::string& key() const { return key_; }
  ParameterEffect effect() const { return effect_; }
  bool typed() const { return effect_ != ParameterEffect::kDocument; }

  /// The value in `spec` (typed parameters only).
  double Get(const CaseSpec& spec) const;
  /// Writes `value` into `spec` (typed parameters only) after the range check
  /// the case reader applies to the key (e.g. a modulus > 0, a damping ratio
  /// in [0, 1)). Returns false, with "<key>: expected X, got Y" in *why, for a
  /// value out of range; then `spec` is unchanged. Never throws.
  bool Set(double value, CaseSpec* spec, std::string* why) const;

 private:
  enum class Field {
    kK1, kK2, kK3, kGap, kContactStiffness, kMu, kNormalForce, kVelocityScale,
    kAlpha, kBeta, kModalRatio,
    kBeamModulus, kBeamDensity, kSegmentModulus, kSegmentDensity,
    kMass, kInertia, kSpringStiffness, kSpringDamping,
    // A force's or the base's ExcitationHistory (HistoryOf).
    kHistoryAmplitude, kHistoryFrequency, kHistoryStartFrequency, kHistoryEndFrequency,
    kHistoryGain, kHistoryOffset,
    kStaticForce, kNone,
  };
  enum class Range { kAny, kNonNegative, kPositive, kRatio };

  double* FieldOf(CaseSpec* spec) const;
  static constexpr int kForceIndex = -1, kBaseIndex = -2;
  /// index_ kForceIndex: [force]'s; kBaseIndex: [base]'s; else [[force]] index_'s.
  ExcitationHistory& HistoryOf(CaseSpec* spec) const;

  std::string key_;
  ParameterEffect effect_ = ParameterEffect::kDocument;
  Field field_ = Field::kNone;
  Range range_ = Range::kAny;
  int index_ = 0;  ///< the table's (or modal ratio's) index; history fields: as HistoryOf
};

}  // namespace podid
