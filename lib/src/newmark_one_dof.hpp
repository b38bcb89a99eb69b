#pragma once
// The dense condensed step of a one-dof model (n = n_a = 1: a Duffing
// oscillator, the Silverbox), not installed; newmark.hpp.
//
// With every dof nonlinear there is nothing to condense: eq. 29 is the whole
// step, Shat x - bhat - f(x, v(x)) = 0 with Shat = a0 m + a1 c + k and
// bhat = m u1 + c u2 + g (u1, u2 as on the dense path). The generic dense
// step reaches it through a 1 x 2 product, an update kernel and the
// workspace's vectors, and waits on the chain x -> x'' -> x' -> u1, u2 ->
// bhat before the next iterations; here the state stays in registers and
// bhat and the Taylor predictor are affine in the increment u = x - x_n
// with constants formed beside the iterations (the modal loop's device,
// newmark_modal.cpp), so the next step waits on two products after x; bhat
// is Shat (x_n + da) as on the modal path, so K carries no rounding of
// a0 m + k (the .cpp). The equations are the dense path's, with other
// roundings (tests/core/newmark_one_dof_test.cpp).

#include "podid/core/newmark.hpp"

namespace podid::internal {

struct OneDofRunner {
  /// Runs options().steps steps from the workspace's state z and u (set by
  /// Run() as for the dense path): the summary's counts, termination and
  /// failure fields, the recording's rows, and z and u at the last good step.
  static void Run(const NewmarkIntegrator& integrator, const ExternalLoad& load,
                  const std::vector<int>& recorded, int rows, Recording* recording,
                  NewmarkWorkspace& w, SimulationSummary* summary);
};

}  // namespace podid::internal
