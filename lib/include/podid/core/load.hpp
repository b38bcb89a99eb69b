#pragma once
// The external load of a case on the integration grid (ExternalLoad,
// newmark.hpp): its point forces ([force] or [[force]]) and its base
// excitation ([base]). Units are SI.
//
// Base excitation (docs/case-file.md, [base]): with u = u_r + r u_g, u_r the
// motion relative to the supports, the equations of motion become
//   M u_r'' + C u_r' + K u_r + f_nl(u_r) = -M r a_g(t) + (the forces),
// the springs, dashpots and grounded elements acting on u_r (the support is
// their ground). For a beam, r is 1 on every free w and 0 on theta, and "M r"
// is the free rows of the unconstrained mass matrix times the rigid
// translation (M_full r_full): the consistent mass couples the supports'
// w to their neighbours, and this is the consistent load of the distributed
// inertia rho A a_g plus the point masses' m a_g. For imported models r is the
// case's influence vector and the load is -M r a_g.

#include <Eigen/Core>
#include <vector>

#include "podid/core/beam_model.hpp"
#include "podid/core/case_spec.hpp"
#include "podid/core/newmark.hpp"

namespace podid {

/// The case's external load on the integration grid: t_n = n dt / substeps,
/// n = 0..(samples - 1) substeps (integrator.substeps; 1: the data's grid).
/// One column per force (the single [force] or each [[force]], in order, then
/// [base] if any; type "none" adds nothing). Analytic histories are evaluated
/// there; a file or channel is read at the record's times time.start_s + n dt
/// (linear interpolation within the file, gain and offset applied), then
/// interpolated band-limited (InterpolateBandLimited) onto the fine grid.
/// `model` gives M for the base's column. Throws std::invalid_argument for a
/// node or dof the model does not have.
ExternalLoad BuildLoad(const CaseSpec& spec, const BeamModel& model);

/// Interpolated file and channel histories kept between BuildLoad calls. A
/// sampled history is gain (u 1_in) + offset 1_in (1_in: where the record's
/// time is inside the file), and the band-limited interpolation is linear, so
/// it is kept as the interpolations of u 1_in and of 1_in: a change of gain or
/// offset (identification's force.gain, force.offset) rescales them instead
/// of interpolating again (an FFT of the whole record per force). An entry is
/// reused only when the column, its time and the grid are equal to the
/// bit; entries a build does not use are dropped.
class LoadCache {
 public:
  struct Entry;
  LoadCache();
  ~LoadCache();
  LoadCache(LoadCache&&) noexcept;
  LoadCache& operator=(LoadCache&&) noexcept;
  /// Interpolations computed (not found) since construction: for tests.
  int misses() const { return misses_; }

 private:
  friend struct LoadCacheAccess;
  std::vector<Entry> entries_;
  int misses_ = 0;
};
/// Same as BuildLoad(spec, model), reusing (and filling) `cache`. With
/// integrator.substeps = 1 the result is the same to the bit; with sub-steps
/// it differs from interpolating gain u + offset by rounding only (the
/// interpolation is linear).
ExternalLoad BuildLoad(const CaseSpec& spec, const BeamModel& model, LoadCache* cache);
/// Same; builds the model when the case has [base] (its M is needed).
ExternalLoad BuildLoad(const CaseSpec& spec);

/// r (dim n_dofs): the motion of the model's dofs when the base moves by 1
/// (beam: 1 on free w dofs, 0 on theta; imported: base.influence). Empty
/// without [base].
Eigen::VectorXd BaseInfluence(const CaseSpec& spec, int n_dofs);

/// M r of the relative equations (dim n_dofs, kg): the base excitation's
/// load is -(M r) a_g. See the header comment for beams.
Eigen::VectorXd BaseMassInfluence(const CaseSpec& spec, const BeamModel& model);

}  // namespace podid
