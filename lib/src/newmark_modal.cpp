// The modal path of the dense condensed integrator (newmark_modal.hpp).
//
// The step's critical path is the Newton iteration of eq. 29 alone: the next
// step's da' = Phi_a d' needs no pass over the modes once x_a is known. The
// step from (q, q', q'') with increment dq = d + E delta has, by the Newmark
// relations, q''_{n+1} = a0 dq - a2 q' - a3 q'' and
// q'_{n+1} = q' + dt ((1 - g) q'' + g q''_{n+1}), so the next increment
// d' = beta q'_{n+1} + gamma q''_{n+1} - kappa q_{n+1} (+ load) is
//   d' = P + Q delta,  P = next_d d + next_x q + next_v q' + next_a q'',
// h = beta dt g + gamma, next_d = h a0 - kappa, next_x = -kappa,
// next_v = beta - h a2, next_a = beta dt (1 - g) - h a3, Q = next_d E:
// P depends on the step's start only, so the pass that forms a step forms
// the next step's P too, and da' = Phi_a P + (Phi_a Q) delta is one n_a x n_a
// product after the iterations; the pass runs beside the next iterations.
#include "newmark_modal.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstddef>

#include "newmark_kernels.hpp"
#include "podid/core/error.hpp"

#if defined(__GNUC__) && defined(__x86_64__)
#define PODID_MODAL_AVX2 1
#endif

namespace podid::internal {
namespace {

int PadToFour(int n) { return (n + 3) / 4 * 4; }

// 4 doubles (GCC vector extension): one AVX register in the AVX2 build of the
// loop's pass over the modes (the portable build keeps scalar lanes: SSE2
// halves of these spill, 138 against 109 ns a step). Loaded and stored with memcpy (no alignment needed); never a parameter or
// a return value (their ABI differs between the two builds).
using V4 = double __attribute__((vector_size(32)));
using V4Bits = unsigned long long __attribute__((vector_size(32)));

// Whether every |x_j| = |(phi q)_j| is within the bound (the exact test,
// when the cheap sum_i bound_i |q_i| is not); *finite = false for NaN or inf.
bool StateWithinBound(const ModalStep& m, const double* q, double max_displacement, bool* finite) {
  bool bounded = true;
  *finite = true;
  for (int j = 0; j < m.n; ++j) {
    double x = 0.0;
    for (int i = 0; i < m.n; ++i) x += m.phi(j, i) * q[i];
    bounded &= std::abs(x) <= max_displacement;  // NaN fails too
    *finite &= std::isfinite(x);
  }
  return bounded;
}

// phi^T A phi in long double (64-bit significand), rounded once to double: a
// low mode's k_i = phi_i^T K phi_i is a small difference of large terms (the
// rotation dofs), and its rounding is a fixed frequency error, i.e. a phase
// drift that grows with time (2e-13 in double, 6e-11 of the response after
// 5000 steps of the reference beam).
Eigen::MatrixXd Project(const Eigen::MatrixXd& phi, const Eigen::MatrixXd& a) {
  using Long = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
  const Long p = phi.cast<long double>();
  const Long product = p.transpose() * (a.cast<long double>() * p);
  return product.cast<double>();
}

}  // namespace

std::shared_ptr<const ModalStep> BuildModalStep(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& damping,
                                                const Eigen::MatrixXd& stiffness, int na,
                                                const NewmarkCoefficients& c, std::string* why) {
  const int n = static_cast<int>(mass.rows());
  if (n < 1) {
    *why = "not used: no dofs";
    return nullptr;
  }
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eigen(stiffness, mass);
  if (eigen.info() != Eigen::Success) {
    *why = "not used: the eigenproblem K phi = lambda M phi failed";
    return nullptr;
  }
  auto step = std::make_shared<ModalStep>();
  ModalStep& m = *step;
  m.n = n;
  m.n_pad = PadToFour(n);
  m.na = na;
  m.phi = eigen.eigenvectors();
  // The full products, not the eigenvalues: they also show an asymmetric K
  // or C (the solver reads one triangle) and the eigenvectors' own error.
  const Eigen::MatrixXd mm = Project(m.phi, mass), cm = Project(m.phi, damping), km = Project(m.phi, stiffness);
  const Eigen::VectorXd s = c.a0 * mm.diagonal() + c.a1 * cm.diagonal() + km.diagonal();
  if (!s.allFinite() || !(s.array() > 0.0).all()) {
    *why = "not used: a mode's a0 m + a1 c + k is not positive";
    return nullptr;
  }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      if (i != j) {
        const double coupling = std::max({c.a0 * std::abs(mm(i, j)), c.a1 * std::abs(cm(i, j)),
                                          std::abs(km(i, j))}) / std::sqrt(s[i] * s[j]);
        m.coupling = std::max(m.coupling, std::isfinite(coupling) ? coupling : HUGE_VAL);
      }
  if (!(m.coupling <= kModalCouplingTolerance)) {
    *why = "not used: the modes couple by " + ToText(m.coupling) + " (> " + ToText(kModalCouplingTolerance) +
           ": non-proportional damping)";
    return nullptr;
  }

  const int np = m.n_pad;
  m.to_modal = mm.diagonal().cwiseInverse().asDiagonal() * m.phi.transpose() * mass;
  m.force_map.setZero(np, n);
  m.force_map.topRows(n) = s.cwiseInverse().asDiagonal() * m.phi.transpose();
  for (Eigen::VectorXd* v : {&m.beta, &m.gamma, &m.kappa, &m.next_d, &m.next_x, &m.next_v, &m.next_a, &m.bound})
    v->setZero(np);
  const double dt = c.step_s, g = c.gamma;
  for (int i = 0; i < n; ++i) {
    // s_i dq = m_i (a2 q' + a3 q'') + c_i (a4 q' + a5 q'') - k_i q (mode i's eq. 23 in increments).
    m.beta[i] = (c.a2 * mm(i, i) + c.a4 * cm(i, i)) / s[i];
    m.gamma[i] = (c.a3 * mm(i, i) + c.a5 * cm(i, i)) / s[i];
    m.kappa[i] = km(i, i) / s[i];
    const double h = m.beta[i] * dt * g + m.gamma[i];
    m.next_d[i] = h * c.a0 - m.kappa[i];
    m.next_x[i] = -m.kappa[i];
    m.next_v[i] = m.beta[i] - h * c.a2;
    m.next_a[i] = m.beta[i] * dt * (1.0 - g) - h * c.a3;
    m.bound[i] = m.phi.col(i).cwiseAbs().maxCoeff();
  }
  m.phi_a.setZero(np, na);
  m.phi_a.topRows(n) = m.phi.topRows(na).transpose();
  // F = Phi_a diag(1/s) Phi_a^T, SPD: Shat = F^-1.
  const Eigen::MatrixXd f = m.phi_a.topRows(n).transpose() * s.cwiseInverse().asDiagonal() * m.phi_a.topRows(n);
  const Eigen::LLT<Eigen::MatrixXd> llt(f);
  if (na > 0 && llt.info() != Eigen::Success) {
    *why = "not used: the nonlinear dofs' modal flexibility is not positive definite";
    return nullptr;
  }
  m.shat = na > 0 ? Eigen::MatrixXd(llt.solve(Eigen::MatrixXd::Identity(na, na))) : Eigen::MatrixXd(0, 0);
  m.e.setZero(np, na);
  m.e.topRows(n) = s.cwiseInverse().asDiagonal() * m.phi_a.topRows(n) * m.shat;
  m.q_gain = m.next_d.asDiagonal() * m.e;
  m.qa = m.phi_a.transpose() * m.q_gain;
  *why = "used: modal coordinates (largest coupling " + ToText(m.coupling) + ")";
  return step;
}

void ModalRunner::Prepare(const NewmarkIntegrator& integrator, const ExternalLoad& load,
                          const std::vector<int>& recorded, NewmarkWorkspace& w) {
  const ModalStep& m = *integrator.modal_;
  const int n = m.n, np = m.n_pad;
  w.modal_state.setZero();
  for (int k = 0; k < 3; ++k) w.modal_state.segment(k * np, n).noalias() = m.to_modal * w.z.segment(k * n, n);
  const int n_recorded = static_cast<int>(recorded.size());
  w.modal_sensors.setZero(PadToFour(n_recorded), n);
  for (int k = 0; k < n_recorded; ++k) w.modal_sensors.row(k) = m.phi.row(recorded[k]);
  w.modal_out.setZero(w.modal_sensors.rows());
  // The load in modal form (w.load_pattern: permuted by PrepareLoad), and its
  // share of the first step's increment (t_1).
  const int columns = load.columns();
  w.modal_load.noalias() = m.force_map * Eigen::MatrixXd(w.load_pattern);
  w.modal_load_a.noalias() = m.phi_a.transpose() * w.modal_load;
  w.modal_load_next.setZero();
  w.load_a.setZero();
  for (int k = 0; k < columns; ++k) {
    w.modal_load_next += load.history(k, 1) * w.modal_load.col(k);
    w.load_a += load.history(k, 1) * w.modal_load_a.col(k);
  }
  const auto q = w.modal_state.segment(0, np), qd = w.modal_state.segment(np, np),
             qdd = w.modal_state.segment(2 * np, np);
  w.modal_d = m.beta.cwiseProduct(qd) + m.gamma.cwiseProduct(qdd) - m.kappa.cwiseProduct(q) + w.modal_load_next;
  w.modal_p = m.next_d.cwiseProduct(w.modal_d) + m.next_x.cwiseProduct(q) + m.next_v.cwiseProduct(qd) +
              m.next_a.cwiseProduct(qdd);
  w.da.noalias() = m.phi_a.transpose() * w.modal_d;
  w.pa.noalias() = m.phi_a.transpose() * w.modal_p;
}

template <int kNa, bool kVector>
[[gnu::always_inline]] inline void ModalRunner::Steps(const NewmarkIntegrator& in, const ExternalLoad& load,
                                                      int n_recorded, int rows,
                                                      Recording* recording, NewmarkWorkspace& w,
                                                      SimulationSummary* summary) {
  const ModalStep& m = *in.modal_;
  const int n = m.n, np = m.n_pad, na = kNa > 0 ? kNa : m.na;
  const NewmarkCoefficients& c = in.coefficients_;
  const double a0 = c.a0, a1 = c.a1, a2 = c.a2, a3 = c.a3, dt = c.step_s, g = c.gamma;
  const double one_minus_g = 1.0 - g, max_displacement = c.max_displacement;
  const double tolerance = in.options_.tolerance;
  const int max_iterations = in.options_.max_iterations, steps = in.options_.steps;
  const int stride = in.options_.record_stride, columns = load.columns();
  double* __restrict const q = w.modal_state.data();
  double* __restrict const qd = q + np;
  double* __restrict const qdd = q + 2 * np;
  double* __restrict const d = w.modal_d.data();
  double* __restrict const p = w.modal_p.data();
  double* __restrict const load_next = w.modal_load_next.data();
  const double* __restrict const modal_load = w.modal_load.data();      // n_pad x columns
  const double* __restrict const modal_load_a = w.modal_load_a.data();  // (na = 1) x columns
  // The one-dof vector loop's load share on its nonlinear dof (w.load_a elsewhere).
  double load_a = 0.0;
  const double* __restrict const e = m.e.data();
  const double* __restrict const q_gain = m.q_gain.data();
  const double* __restrict const phi_a = m.phi_a.data();
  const double* __restrict const next_d = m.next_d.data();
  const double* __restrict const next_x = m.next_x.data();
  const double* __restrict const next_v = m.next_v.data();
  const double* __restrict const next_a = m.next_a.data();
  const double* __restrict const bound = m.bound.data();
  double* const z = w.z.data();  // the `a` dofs' physical x, x', x'': z[j], z[n + j], z[2 n + j]
  double* const delta = w.delta.data();
  double* const lanes = w.modal_pa_lanes.data();
  // One nonlinear dof: its state, da and pa in registers.
  double x_n = z[0], v_n = z[n], a_n = z[2 * n], da = na == 1 ? w.da[0] : 0.0, pa = na == 1 ? w.pa[0] : 0.0;
  const double shat = na == 1 ? m.shat(0, 0) : 0.0, qa = na == 1 ? m.qa(0, 0) : 0.0;
  // What a step's Newton iteration starts from, the Taylor predictor
  // x_n + dt x'_n + dt^2 x''_n / 2 and bhat = Shat (x_n + da), is affine in
  // the last step's increment u = x - x_n (by the Newmark relations and
  // da = pa + qa (u - da_last) + load):
  //   predictor = pred_gain u + pred_const,  pred_gain = 1 + a0 dt^2 (g + 1/2),
  //   bhat = Shat ((1 + qa) u + (x_last + pa + load - qa da_last)),
  // the constants formed beside the iterations, so the next step waits on
  // two products after x instead of the chain x -> x'' -> x' -> predictor
  // (the Silverbox's 1-dof steps 1.08-1.10x; the 12-dof reference step 0.98x).
  const double half_dt2 = 0.5 * dt * dt, pred_gain = 1.0 + a0 * dt * dt * (g + 0.5);
  double x_pred = x_n + dt * (v_n + 0.5 * dt * a_n), bhat = shat * (x_n + da);
  const double one_plus_qa = 1.0 + qa;
  double u_last = 0.0, x_last = 0.0;

  // Sensors: out = the recorded rows of phi times v, 4 rows at a time.
  const int sensor_rows = static_cast<int>(w.modal_sensors.rows());
  const double* __restrict const sensors = w.modal_sensors.data();
  double* __restrict const out = w.modal_out.data();
  auto record = [&](const double* v, double* column0, int row) {
    // Up to 8 sensors in the AVX2 build: modes outer, both row blocks' sums in
    // registers (the same additions in the same order), 3 of the reference
    // step's 39 ns; the SSE2 build would spill them (0.7x).
    if (kVector && sensor_rows <= 8) {
      V4 acc0 = {0.0, 0.0, 0.0, 0.0}, acc1 = {0.0, 0.0, 0.0, 0.0}, column;
      const bool two = sensor_rows == 8;
      for (int i = 0; i < n; ++i) {
        const double value = v[i];
        const double* at = sensors + static_cast<std::ptrdiff_t>(i) * sensor_rows;
        __builtin_memcpy(&column, at, sizeof column);
        acc0 += column * value;
        if (two) {
          __builtin_memcpy(&column, at + 4, sizeof column);
          acc1 += column * value;
        }
      }
      for (int k = 0; k < n_recorded; ++k)
        column0[static_cast<std::ptrdiff_t>(k) * rows + row] = k < 4 ? acc0[k] : acc1[k - 4];
      return;
    }
    for (int r = 0; r < sensor_rows; r += 4) {
      V4 acc = {0.0, 0.0, 0.0, 0.0}, column;
      for (int i = 0; i < n; ++i) {
        __builtin_memcpy(&column, sensors + static_cast<std::ptrdiff_t>(i) * sensor_rows + r, sizeof column);
        acc += column * v[i];
      }
      __builtin_memcpy(out + r, &acc, sizeof acc);
    }
    for (int k = 0; k < n_recorded; ++k)
      column0[static_cast<std::ptrdiff_t>(k) * rows + row] = out[k];
  };
  double* const rec_x = recording->displacement.data();
  double* const rec_v = recording->record_velocity ? recording->velocity.data() : nullptr;
  double* const rec_a = recording->record_acceleration ? recording->acceleration.data() : nullptr;

  int since_record = 0;
  for (int step = 1; step <= steps; ++step) {
    int iterations = 0;
    double residual = 0.0;
    bool ok = true;
    if (na == 1) {
      // eq. 29 with Shat = F^-1 and bhat = Shat (x_n + da), from the Taylor predictor.
      const double v0 = in.v0_velocity_ * v_n + in.v0_acceleration_ * a_n;
      double x = x_pred;
      // x''_(n+1) = a0 u + c1: the next predictor's constant part.
      const double c1 = -(a2 * v_n) - a3 * a_n;
      const double pred_const =
          x_n + dt * (v_n + dt * one_minus_g * a_n + dt * g * c1) + half_dt2 * c1;
      ok = SolveScalarNewton(in.nonlinear_, shat, bhat, a1, x_n, v0, tolerance, max_iterations, &x,
                             &iterations, &residual);
      if (ok) {
        const double u = x - x_n;
        u_last = u;
        x_last = x_n;
        delta[0] = u - da;
        x_pred = pred_gain * u + pred_const;
        const double an = a0 * u - a2 * v_n - a3 * a_n;
        v_n += dt * (one_minus_g * a_n + g * an);
        a_n = an;
        x_n = x;
      }
    } else if (na > 0) {
      for (int j = 0; j < na; ++j) w.xa[j] = z[j] + w.da[j];
      w.ra.noalias() = m.shat * w.xa;
      ok = in.SolveCondensed(w, m.shat, &iterations, &residual);
      if (ok) {
        for (int j = 0; j < na; ++j) {
          delta[j] = (w.xa[j] - z[j]) - w.da[j];
          const double an = a0 * (w.xa[j] - z[j]) - a2 * z[n + j] - a3 * z[2 * n + j];
          z[n + j] += dt * (one_minus_g * z[2 * n + j] + g * an);
          z[2 * n + j] = an;
          z[j] = w.xa[j];
        }
      }
    }
    if (!CountStep(ok, iterations, residual, step, dt, summary)) break;
    // The next step's load share (t_{step+1}), then its da = Phi_a P + (Phi_a Q) delta.
    // The one-dof vector loop forms the modes' share in registers below: a
    // round trip through load_next (zeroed by a memset call, then read as
    // vectors) stalled its loads (the Silverbox's steps are 1.2x faster
    // without it).
    const double* const load_values =
        columns > 0 && step < steps ? &load.history(0, step + 1) : nullptr;
    if constexpr (kNa == 1 && kVector) {
      load_a = 0.0;
      for (int k = 0; load_values != nullptr && k < columns; ++k) {
        if (load_values[k] != 0.0) load_a += load_values[k] * modal_load_a[k];
      }
    } else if (load_values != nullptr) {
      for (int i = 0; i < np; ++i) load_next[i] = 0.0;
      for (int j = 0; j < na; ++j) w.load_a[j] = 0.0;
      for (int k = 0; k < columns; ++k) {
        const double value = load_values[k];
        if (value == 0.0) continue;
        const double* column = modal_load + static_cast<std::ptrdiff_t>(k) * np;
        for (int i = 0; i < np; ++i) load_next[i] += value * column[i];
        for (int j = 0; j < na; ++j) w.load_a[j] += value * w.modal_load_a(j, k);
      }
    }
    if (na == 1) {
      const double load_share = columns > 0 ? (kNa == 1 && kVector ? load_a : w.load_a[0]) : 0.0;
      bhat = shat * (one_plus_qa * u_last + (((x_last + pa) + load_share) - qa * da));
      da = pa + qa * delta[0] + load_share;
    } else {
      for (int j = 0; j < na; ++j) {
        double value = w.pa[j] + w.load_a[j];
        for (int l = 0; l < na; ++l) value += m.qa(j, l) * delta[l];
        w.da[j] = value;
      }
    }
    // The modes, 4 at a time: the new state (eq. 28 in modal form and the
    // Newmark relations), d' = P + Q delta + the load's share, the next P,
    // its image on the `a` dofs and the displacement bound.
    double x_bound = 0.0;
    if constexpr (kNa == 1 && kVector) {
      const V4 sign_off = (V4)(V4Bits{} + 0x7fffffffffffffffULL);
      V4 bound_sum = {0.0, 0.0, 0.0, 0.0}, pa_sum = {0.0, 0.0, 0.0, 0.0};
      const double d0 = delta[0];
      for (int b = 0; b < np; b += 4) {
        V4 vd, vp, ve, vq_gain, vload, vq, vqd, vqdd, vnext_d, vnext_x, vnext_v, vnext_a, vphi_a, vbound;
        __builtin_memcpy(&vd, d + b, sizeof vd);
        __builtin_memcpy(&vp, p + b, sizeof vp);
        __builtin_memcpy(&ve, e + b, sizeof ve);
        __builtin_memcpy(&vq_gain, q_gain + b, sizeof vq_gain);
        vload = V4{};  // load_next's bits: 0 + the columns' shares in order
        for (int k = 0; load_values != nullptr && k < columns; ++k) {
          if (load_values[k] == 0.0) continue;
          V4 column;
          __builtin_memcpy(&column, modal_load + static_cast<std::ptrdiff_t>(k) * np + b,
                           sizeof column);
          vload += load_values[k] * column;
        }
        __builtin_memcpy(&vq, q + b, sizeof vq);
        __builtin_memcpy(&vqd, qd + b, sizeof vqd);
        __builtin_memcpy(&vqdd, qdd + b, sizeof vqdd);
        __builtin_memcpy(&vnext_d, next_d + b, sizeof vnext_d);
        __builtin_memcpy(&vnext_x, next_x + b, sizeof vnext_x);
        __builtin_memcpy(&vnext_v, next_v + b, sizeof vnext_v);
        __builtin_memcpy(&vnext_a, next_a + b, sizeof vnext_a);
        __builtin_memcpy(&vphi_a, phi_a + b, sizeof vphi_a);
        __builtin_memcpy(&vbound, bound + b, sizeof vbound);
        const V4 dq = vd + ve * d0;
        const V4 dn = (vp + vq_gain * d0) + vload;
        const V4 qn = vq + dq;
        const V4 an = a0 * dq - a2 * vqd - a3 * vqdd;
        const V4 vn = vqd + dt * (one_minus_g * vqdd + g * an);
        const V4 pn = vnext_d * dn + vnext_x * qn + vnext_v * vn + vnext_a * an;
        pa_sum += vphi_a * pn;
        bound_sum += vbound * (V4)((V4Bits)qn & (V4Bits)sign_off);  // |q_n|
        __builtin_memcpy(q + b, &qn, sizeof qn);
        __builtin_memcpy(qd + b, &vn, sizeof vn);
        __builtin_memcpy(qdd + b, &an, sizeof an);
        __builtin_memcpy(d + b, &dn, sizeof dn);
        __builtin_memcpy(p + b, &pn, sizeof pn);
      }
      pa = (pa_sum[0] + pa_sum[1]) + (pa_sum[2] + pa_sum[3]);
      x_bound = (bound_sum[0] + bound_sum[1]) + (bound_sum[2] + bound_sum[3]);
    } else if constexpr (kNa == 1) {
      // The same in scalar lanes (lane l: modes l, l + 4, ...), in registers.
      double bound_lanes[4] = {0.0, 0.0, 0.0, 0.0}, pa_lanes[4] = {0.0, 0.0, 0.0, 0.0};
      const double d0 = delta[0];
      for (int b = 0; b < np; b += 4) {
        for (int l = 0; l < 4; ++l) {
          const int i = b + l;
          const double dq = d[i] + e[i] * d0;
          const double dn = (p[i] + q_gain[i] * d0) + load_next[i];
          const double qn = q[i] + dq;
          const double an = a0 * dq - a2 * qd[i] - a3 * qdd[i];
          const double vn = qd[i] + dt * (one_minus_g * qdd[i] + g * an);
          const double pn = next_d[i] * dn + next_x[i] * qn + next_v[i] * vn + next_a[i] * an;
          pa_lanes[l] += phi_a[i] * pn;
          bound_lanes[l] += bound[i] * std::abs(qn);
          q[i] = qn;
          qd[i] = vn;
          qdd[i] = an;
          d[i] = dn;
          p[i] = pn;
        }
      }
      pa = (pa_lanes[0] + pa_lanes[1]) + (pa_lanes[2] + pa_lanes[3]);
      x_bound = (bound_lanes[0] + bound_lanes[1]) + (bound_lanes[2] + bound_lanes[3]);
    } else {
      double bound_lanes[4] = {0.0, 0.0, 0.0, 0.0};
      for (int k = 0; k < 4 * na; ++k) lanes[k] = 0.0;
      for (int b = 0; b < np; b += 4) {
        for (int l = 0; l < 4; ++l) {
          const int i = b + l;
          double dq = d[i], dn = p[i];
          for (int j = 0; j < na; ++j) {
            dq += e[static_cast<std::ptrdiff_t>(j) * np + i] * delta[j];
            dn += q_gain[static_cast<std::ptrdiff_t>(j) * np + i] * delta[j];
          }
          dn += load_next[i];
          const double qn = q[i] + dq;
          const double an = a0 * dq - a2 * qd[i] - a3 * qdd[i];
          const double vn = qd[i] + dt * (one_minus_g * qdd[i] + g * an);
          const double pn = next_d[i] * dn + next_x[i] * qn + next_v[i] * vn + next_a[i] * an;
          for (int j = 0; j < na; ++j) lanes[4 * j + l] += phi_a[static_cast<std::ptrdiff_t>(j) * np + i] * pn;
          bound_lanes[l] += bound[i] * std::abs(qn);
          q[i] = qn;
          qd[i] = vn;
          qdd[i] = an;
          d[i] = dn;
          p[i] = pn;
        }
      }
      for (int j = 0; j < na; ++j)
        w.pa[j] = (lanes[4 * j] + lanes[4 * j + 1]) + (lanes[4 * j + 2] + lanes[4 * j + 3]);
      x_bound = (bound_lanes[0] + bound_lanes[1]) + (bound_lanes[2] + bound_lanes[3]);
    }
    // max_j |x_j| <= sum_i bound_i |q_i|: the exact test only when this fails.
    if (!(x_bound <= max_displacement)) {
      bool finite = true;
      if (!StateWithinBound(m, q, max_displacement, &finite)) {
        summary->termination = finite ? SimulationTermination::kDiverged : SimulationTermination::kNonFinite;
        summary->failure_time_s = step * dt;
        break;
      }
    }
    summary->steps_completed = step;
    if (++since_record == stride) {
      since_record = 0;
      const int row = step / stride;
      record(q, rec_x, row);
      if (rec_v) record(qd, rec_v, row);
      if (rec_a) record(qdd, rec_a, row);
      summary->rows_recorded = row + 1;
    }
  }
  if (na == 1) {
    z[0] = x_n;
    z[n] = v_n;
    z[2 * n] = a_n;
  }
}

namespace {

using StepsFunction = void (*)(const NewmarkIntegrator&, const ExternalLoad&, int, int, Recording*,
                               NewmarkWorkspace&, SimulationSummary*);

void StepsOnePortable(const NewmarkIntegrator& in, const ExternalLoad& load, int n_recorded,
                      int rows, Recording* recording, NewmarkWorkspace& w, SimulationSummary* summary) {
  ModalRunner::Steps<1, false>(in, load, n_recorded, rows, recording, w, summary);
}

void StepsAnyPortable(const NewmarkIntegrator& in, const ExternalLoad& load, int n_recorded,
                      int rows, Recording* recording, NewmarkWorkspace& w, SimulationSummary* summary) {
  ModalRunner::Steps<0, false>(in, load, n_recorded, rows, recording, w, summary);
}

#ifdef PODID_MODAL_AVX2
// The same loop compiled for AVX2 (4 modes a register; no FMA in the target:
// the portable version's roundings, so the same bits).
__attribute__((target("avx2"))) void StepsOneAvx2(const NewmarkIntegrator& in, const ExternalLoad& load,
                                                  int n_recorded, int rows,
                                                  Recording* recording, NewmarkWorkspace& w,
                                                  SimulationSummary* summary) {
  ModalRunner::Steps<1, true>(in, load, n_recorded, rows, recording, w, summary);
}
#endif

StepsFunction SelectSteps(int na, [[maybe_unused]] bool cpu_dispatch) {
  if (na != 1) return StepsAnyPortable;
#ifdef PODID_MODAL_AVX2
  if (ModalLoopVectorised(na, cpu_dispatch, nullptr)) return StepsOneAvx2;
#endif
  return StepsOnePortable;
}

}  // namespace

bool ModalLoopVectorised(int na, bool cpu_dispatch, std::string* why) {
  const char* missing = nullptr;
  if (na != 1) {
    missing = "its AVX2 loop takes one nonlinear dof";
  } else if (!cpu_dispatch) {
    missing = "NewmarkOptions::cpu_dispatch is false";
  } else {
#ifdef PODID_MODAL_AVX2
    if (!__builtin_cpu_supports("avx2")) missing = "the CPU has no AVX2";
#else
    missing = "no AVX2 build of its loop (not GCC or Clang on x86-64)";
#endif
  }
  if (missing != nullptr && why != nullptr)
    *why = std::string("not used: ") + missing +
           ", and its portable loop is slower than the dense step";
  return missing == nullptr;
}

void ModalRunner::Run(const NewmarkIntegrator& integrator, const ExternalLoad& load,
                      const std::vector<int>& recorded, int rows, Recording* recording, NewmarkWorkspace& w,
                      SimulationSummary* summary) {
  SelectSteps(integrator.modal_->na, integrator.options_.cpu_dispatch)(
      integrator, load, static_cast<int>(recorded.size()), rows, recording, w, summary);
}

}  // namespace podid::internal
