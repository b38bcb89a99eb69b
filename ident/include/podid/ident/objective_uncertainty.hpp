#pragma once
// Standard errors, 95 % intervals and correlations of parameters identified
// with an ObjectiveFunction (issue 12 item 7), by the sandwich estimator of
// uncertainty.hpp applied to the objective's own features:
//   f(theta) = [ sqrt(w_U) vec(U_K), sqrt(w_S) sigma_K (/ sigma_meas,K when relative),
//                sqrt(w_V) vec(V_K), sqrt(w_IF D) f_sim,k(t_j) / f_meas,k(t_j) ]
// of the simulated response aligned to the measured POD, so that the chosen
// weighting is F = ||f(theta) - f_meas||^2 (the IF samples: those inside the
// measured ridge's cone), the simulated response conditioned once by [data]
// as Evaluate conditions it. The noise: white, per channel, with the variance
// of the residual measured - simulated at the optimum (model error included,
// so the intervals are conservative when the model is wrong; with a [data]
// filter, the in-band residual's variance spread over every frequency); each
// draw is that noise on the fitted response, through the same features.

#include <Eigen/Core>
#include <cstdint>

#include "podid/ident/objective.hpp"
#include "podid/ident/uncertainty.hpp"

namespace podid::ident {

/// The uncertainty of `values` (dim parameter_count(), usually the optimum)
/// for weighting `weighting` of `objective`. Throws std::invalid_argument for
/// a wrong size, weighting index or options; a failed simulation or a
/// singular J^T J is a non-usable result with its reason. Seeded: the same
/// seed gives the same draws.
ParameterUncertainty ObjectiveUncertainty(const ObjectiveFunction& objective, const Eigen::VectorXd& values,
                                          int weighting, const UncertaintyOptions& options,
                                          std::uint64_t seed = 1);

}  // namespace podid::ident
