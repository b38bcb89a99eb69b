// The one-dof dense condensed loop (newmark_one_dof.hpp).
#include "newmark_one_dof.hpp"

#include <cmath>
#include <cstddef>

#include "newmark_kernels.hpp"

namespace podid::internal {

void OneDofRunner::Run(const NewmarkIntegrator& in, const ExternalLoad& load,
                       const std::vector<int>& recorded, int rows, Recording* recording,
                       NewmarkWorkspace& w, SimulationSummary* summary) {
  const NewmarkCoefficients& c = in.coefficients_;
  const double a0 = c.a0, a1 = c.a1, a2 = c.a2, a3 = c.a3, a4 = c.a4, a5 = c.a5;
  const double dt = c.step_s, g = c.gamma, one_minus_g = 1.0 - g, half_dt2 = 0.5 * dt * dt;
  const double max_displacement = c.max_displacement, tolerance = in.options_.tolerance;
  const double v0_velocity = in.v0_velocity_, v0_acceleration = in.v0_acceleration_;
  const int max_iterations = in.options_.max_iterations, steps = in.options_.steps;
  const int stride = in.options_.record_stride, columns = load.columns();
  const int n_recorded = static_cast<int>(recorded.size());
  const double shat = in.shat_scalar_;
  // bhat = m u1 + c u2 + sum_k g_k(t) load_bhat_k: the 1 x 2 condensed_mc_ is [m, c].
  const double m = in.condensed_mc_(0, 0), damping = in.condensed_mc_(0, 1);
  const double* const load_bhat = w.load_bhat.data();  // 1 x K
  const auto load_at = [&](int step) {
    double share = 0.0;
    const double* const values = &load.history(0, step);
    for (int k = 0; k < columns; ++k) {
      if (values[k] != 0.0) share += values[k] * load_bhat[k];  // the dense step's order
    }
    return share;
  };
  // With x = x_n + u and, by the Newmark relations, x'' = a0 u + c1 and
  // x' = v_c + dt g a0 u (c1 = -a2 x'_n - a3 x''_n, v_c = x'_n + dt ((1 - g)
  // x''_n + g c1)), the predictor x + dt x' + dt^2 x'' / 2 is
  // G u + (x_n + dt v_c + dt^2 c1 / 2). bhat is kept as the modal path keeps
  // it, Shat (x + da) with Shat da = m (a2 x' + a3 x'') + c (a4 x' + a5 x'')
  // - k x + g (the dense path's m u1 + c u2 + g less Shat x): k then enters
  // the residual as k x_n, not through Shat's rounding of a0 m + k, which
  // would be a fixed frequency error (1e-11 relative at a0 m / k = 5e4). In u,
  // bhat' = B u + Shat (x_n + (Q v_c + R c1 - k x_n + g') / Shat) with
  // B = P + Q dt g a0 + R a0 (P, Q, R: the u1, u2 coefficients of x, x', x'').
  const double stiffness = in.stiffness_(0, 0), inv_shat = 1.0 / shat;  // K's k (0 if in an element)
  const double p = m * a0 + damping * a1, q = m * a2 + damping * a4, r = m * a3 + damping * a5;
  const double b_gain = p + q * (dt * g * a0) + r * a0;
  const double pred_gain = 1.0 + a0 * dt * dt * (g + 0.5);

  double* const z = w.z.data();
  double x_n = z[0], v_n = z[1], a_n = z[2];
  double first = (m * (a2 * v_n + a3 * a_n) + damping * (a4 * v_n + a5 * a_n)) - stiffness * x_n;
  if (columns > 0 && steps > 0) first += load_at(1);
  double bhat = shat * (x_n + first * inv_shat);
  double x_pred = x_n + dt * (v_n + 0.5 * dt * a_n);

  double* const rec_x = recording->displacement.data();
  double* const rec_v = recording->record_velocity ? recording->velocity.data() : nullptr;
  double* const rec_a = recording->record_acceleration ? recording->acceleration.data() : nullptr;
  int since_record = 0;
  for (int step = 1; step <= steps; ++step) {
    // The next step's constants first: they need only this step's start.
    const double v0 = v0_velocity * v_n + v0_acceleration * a_n;
    const double c1 = -(a2 * v_n) - a3 * a_n;
    const double v_c = v_n + dt * (one_minus_g * a_n + g * c1);
    const double pred_const = x_n + dt * v_c + half_dt2 * c1;
    double next = (q * v_c + r * c1) - stiffness * x_n;
    if (columns > 0 && step < steps) next += load_at(step + 1);
    const double b_const = shat * (x_n + next * inv_shat);

    double x = x_pred, residual = 0.0;
    int iterations = 0;
    const bool ok = SolveScalarNewton(in.nonlinear_, shat, bhat, a1, x_n, v0, tolerance,
                                      max_iterations, &x, &iterations, &residual);
    if (!CountStep(ok, iterations, residual, step, dt, summary)) break;
    if (!(std::abs(x) <= max_displacement)) {  // NaN fails too
      summary->termination = std::isfinite(x) ? SimulationTermination::kDiverged
                                              : SimulationTermination::kNonFinite;
      summary->failure_time_s = step * dt;
      break;
    }
    const double u = x - x_n;
    bhat = b_gain * u + b_const;
    x_pred = pred_gain * u + pred_const;
    const double an = a0 * u + c1;
    v_n += dt * (one_minus_g * a_n + g * an);
    a_n = an;
    x_n = x;
    summary->steps_completed = step;
    if (++since_record == stride) {  // step % stride == 0 without a division
      since_record = 0;
      const int row = step / stride;
      for (int i = 0; i < n_recorded; ++i) {
        const std::ptrdiff_t at = static_cast<std::ptrdiff_t>(i) * rows + row;
        rec_x[at] = x_n;
        if (rec_v) rec_v[at] = v_n;
        if (rec_a) rec_a[at] = a_n;
      }
      summary->rows_recorded = row + 1;
    }
  }
  // The last good step's state, as the dense step leaves it.
  z[0] = x_n;
  z[1] = v_n;
  z[2] = a_n;
  w.u[0] = a0 * x_n + a2 * v_n + a3 * a_n;
  w.u[1] = a1 * x_n + a4 * v_n + a5 * a_n;
}

}  // namespace podid::internal
