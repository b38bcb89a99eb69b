// Allocation checks: the no-allocation test compiles the core with
// EIGEN_RUNTIME_NO_MALLOC, and Run() forbids Eigen heap allocations inside the
// time loop, so any allocation there aborts (see tests/CMakeLists.txt).
#include "podid/core/newmark.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <sstream>

#include "newmark_kernels.hpp"
#include "newmark_modal.hpp"
#include "newmark_one_dof.hpp"
#include "podid/core/error.hpp"
#include "sparse_ordering.hpp"
#include "sparse_step.hpp"
#include "step_conditioning.hpp"

namespace podid {
namespace {

void SetMallocAllowed([[maybe_unused]] bool allowed) {
#ifdef EIGEN_RUNTIME_NO_MALLOC
  Eigen::internal::set_is_malloc_allowed(allowed);
#endif
}

// Reachable from a case (an imported C or K that is not positive
// semi-definite), so an error and not an internal check: it aborted podid.
[[noreturn]] void ThrowIndefiniteStepMatrix() {
  ThrowInvalid("model",
               "M / (beta dt^2) + gamma C / (beta dt) + K positive definite on the linear dofs "
               "(C and K positive semi-definite: no negative damping or stiffness)",
               "a matrix that is not");
}

}  // namespace

NewmarkIntegrator::NewmarkIntegrator(const BeamModel& model, const NewmarkOptions& options)
    : options_(options) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("integrator options: " + why);
  n_ = model.dofs();
  const std::vector<int>& a = model.nonlinear().dofs();
  na_ = static_cast<int>(a.size());
  nb_ = n_ - na_;
  const double dt = options.step_s, g = options.gamma, b = options.beta;
  a0_ = 1.0 / (b * dt * dt);
  a1_ = g / (b * dt);
  a2_ = 1.0 / (b * dt);
  a3_ = 1.0 / (2.0 * b) - 1.0;
  a4_ = g / b - 1.0;
  a5_ = dt * (g / (2.0 * b) - 1.0);

  // Permutation putting the `a` dofs first (eq. 21), so partitions are blocks.
  perm_ = a;
  for (int i = 0; i < n_; ++i) {
    if (!std::binary_search(a.begin(), a.end(), i)) perm_.push_back(i);
  }
  inv_perm_.assign(n_, 0);
  for (int k = 0; k < n_; ++k) inv_perm_[perm_[k]] = k;
  // P A P^T from the nonzeros: entry (i, j) moves to (inv_perm i, inv_perm j).
  auto permute = [&](const Eigen::SparseMatrix<double>& m) {
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(static_cast<std::size_t>(m.nonZeros()));
    for (int j = 0; j < m.outerSize(); ++j)
      for (Eigen::SparseMatrix<double>::InnerIterator it(m, j); it; ++it)
        t.emplace_back(inv_perm_[it.row()], inv_perm_[it.col()], it.value());
    Eigen::SparseMatrix<double> out(n_, n_);
    out.setFromTriplets(t.begin(), t.end());
    return out;
  };
  mass_sparse_ = permute(model.mass());
  damping_sparse_ = permute(model.damping());
  stiffness_sparse_ = permute(model.stiffness());
  // The `a` dofs are 0..na-1 in the permuted order, so the elements' local
  // indices are already permuted indices.
  nonlinear_ = model.nonlinear();
  sparse_ = options.type == IntegratorType::kModifiedNewmark && n_ > options.dense_dof_limit;
  coefficients_ = {a0_, a1_, a2_, a3_, a4_, a5_, dt, g, options.max_displacement};
  v0_velocity_ = 1.0 - g / b;
  v0_acceleration_ = dt * (1.0 - g / (2.0 * b));
  // The Newmark update of the condensed paths, dense and sparse.
  update_ = internal::SelectUpdateKernel(options.cpu_dispatch);

  if (sparse_) {
    // No n x n dense matrix: M, C, K stay sparse and S_b is factorised once
    // (sparse LDL^T). eqs. 28-29: H = S_b^-1 S_ba (n_b x n_a) and
    // Shat = S_a - S_ab H, both computed once.
    auto s_of = [&] {
      Eigen::SparseMatrix<double> s =
          a0_ * mass_sparse_ + a1_ * damping_sparse_ + stiffness_sparse_;
      s.makeCompressed();
      return s;
    };
    // The `b` dofs in the order of S_b's factor (nested dissection, then the
    // elimination tree level by level: sparse_ordering.hpp), applied to the
    // integrator's permutation so that the step permutes nothing.
    const internal::SparseOrdering ordering = internal::ChainBreakingOrdering(
        Eigen::SparseMatrix<double>(s_of().bottomRightCorner(nb_, nb_)));
    const std::vector<int> b(perm_.begin() + na_, perm_.end());
    for (int k = 0; k < nb_; ++k) perm_[na_ + k] = b[ordering.order[k]];
    for (int k = 0; k < n_; ++k) inv_perm_[perm_[k]] = k;
    mass_sparse_ = permute(model.mass());
    damping_sparse_ = permute(model.damping());
    stiffness_sparse_ = permute(model.stiffness());
    const Eigen::SparseMatrix<double> s = s_of();
    mass_ldlt_.compute(mass_sparse_);
    if (mass_ldlt_.info() != Eigen::Success) {
      ThrowInvalid("model", "a positive definite mass matrix M", "a singular one");
    }
    const Eigen::SparseMatrix<double> sbb = s.bottomRightCorner(nb_, nb_);
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower,
                                Eigen::NaturalOrdering<int>>
        sbb_ldlt(sbb);
    if (sbb_ldlt.info() != Eigen::Success) ThrowIndefiniteStepMatrix();
    // The solves the steps make are with this factor: probe it (step_conditioning.hpp).
    step_error_estimate_ = internal::ProbeSolveError(
        sbb, [&](const Eigen::VectorXd& rhs) -> Eigen::VectorXd { return sbb_ldlt.solve(rhs); });
    const Eigen::SparseMatrix<double> lower =
        sbb_ldlt.matrixL().nestedExpression().triangularView<Eigen::StrictlyLower>();
    sparse_step_ = std::make_shared<const internal::SparseStep>(mass_sparse_, damping_sparse_, na_,
                                                                lower, sbb_ldlt.vectorD());
    std::ostringstream status;
    status << ordering.method << ": elimination tree of height " << ordering.tree_height << " for "
           << nb_ << " rows, " << lower.nonZeros() << " nonzeros below L's diagonal";
    sparse_status_ = status.str();
    modal_status_ = "not used: sparse path";
    sab_sparse_ = s.topRightCorner(na_, nb_);
    const Eigen::MatrixXd sba = Eigen::MatrixXd(s.bottomLeftCorner(nb_, na_));
    h_ = sbb_ldlt.solve(sba);
    shat_ = Eigen::MatrixXd(s.topLeftCorner(na_, na_)) - sab_sparse_ * h_;
    return;
  }

  // Dense path: small models, and the full-Newton reference integrator.
  step_error_estimate_ =
      internal::StepSolveErrorEstimate(mass_sparse_, damping_sparse_, stiffness_sparse_, a0_, a1_);
  mass_ = Eigen::MatrixXd(mass_sparse_);
  damping_ = Eigen::MatrixXd(damping_sparse_);
  stiffness_ = Eigen::MatrixXd(stiffness_sparse_);
  s_ = a0_ * mass_ + a1_ * damping_ + stiffness_;
  s_norm_ = s_.cwiseAbs().rowwise().sum().maxCoeff();
  // rhs = M (a0 x + a2 x' + a3 x'') + C (a1 x + (g/b - 1) x' + dt (g/(2b) - 1) x'').
  rhs_matrix_.resize(n_, 3 * n_);
  rhs_matrix_.leftCols(n_) = a0_ * mass_ + a1_ * damping_;
  rhs_matrix_.middleCols(n_, n_) = a2_ * mass_ + (g / b - 1.0) * damping_;
  rhs_matrix_.rightCols(n_) = a3_ * mass_ + dt * (g / (2.0 * b) - 1.0) * damping_;
  mass_inverse_ = mass_.llt().solve(Eigen::MatrixXd::Identity(n_, n_));

  if (options.type == IntegratorType::kModifiedNewmark) {
    // Computed once for the constant step: S_b^-1, S_ab, H = S_b^-1 S_ba and
    // the condensed matrix S_a - S_ab S_b^-1 S_ba (eqs. 28-29).
    const Eigen::MatrixXd sbb = s_.bottomRightCorner(nb_, nb_);
    Eigen::LLT<Eigen::MatrixXd> llt(sbb);
    if (llt.info() != Eigen::Success) ThrowIndefiniteStepMatrix();
    sbb_inv_ = llt.solve(Eigen::MatrixXd::Identity(nb_, nb_));
    sab_ = s_.topRightCorner(na_, nb_);
    h_ = sbb_inv_ * s_.bottomLeftCorner(nb_, na_);
    shat_ = s_.topLeftCorner(na_, na_) - sab_ * h_;
    multiply_small_ = internal::SelectMultiplyKernel(options.cpu_dispatch);
    // One product per step gives both: [bhat; y] = T [M, C] [u1; u2].
    Eigen::MatrixXd mc(n_, 2 * n_);
    mc << mass_, damping_;
    condensed_mc_.resize(n_, 2 * n_);
    auto y_rows = condensed_mc_.bottomRows(nb_);
    y_rows.noalias() = sbb_inv_ * mc.bottomRows(nb_);
    condensed_mc_.topRows(na_) = mc.topRows(na_) - sab_ * y_rows;
    if (na_ == 1) {
      h_padded_.setZero(n_);
      h_padded_.tail(nb_) = h_.col(0);
      shat_scalar_ = shat_(0, 0);
    }
  }
  if (options.type != IntegratorType::kModifiedNewmark) {
    modal_status_ = "not used: full Newton";
  } else if (n_ == 1 && na_ == 1 && !sparse_ && !options.modal_portable) {
    // Nothing to condense: the scalar loop, faster than either (the Silverbox's
    // steps, docs/benchmark-log.md, "The one-dof loop").
    one_dof_ = true;
    modal_status_ = "not used: a one-dof model steps in its own scalar loop";
  } else if (!options.modal) {
    modal_status_ = "not used: NewmarkOptions::modal is false";
  } else if (!options.modal_portable &&
             !internal::ModalLoopVectorised(na_, options.cpu_dispatch, &modal_status_)) {
    // The dense condensation above is the faster step here (the status says why).
  } else {
    modal_ = internal::BuildModalStep(mass_, damping_, stiffness_, na_, coefficients_, &modal_status_);
  }
}

NewmarkWorkspace::NewmarkWorkspace(const NewmarkIntegrator& integrator) {
  const int n = integrator.n_, na = integrator.na_;
  z.setZero(3 * n);
  for (Eigen::VectorXd* v : {&x_new, &rhs, &r, &dx}) v->setZero(n);
  if (integrator.options_.type == IntegratorType::kModifiedNewmark) u.setZero(2 * n);
  if (integrator.modal_) {
    const int n_pad = integrator.modal_->n_pad;
    modal_state.setZero(3 * n_pad);
    for (Eigen::VectorXd* v : {&modal_d, &modal_p, &modal_load_next}) v->setZero(n_pad);
    modal_pa_lanes.setZero(4 * na);
    for (Eigen::VectorXd* v : {&da, &pa, &delta, &load_a}) v->setZero(na);
  }
  for (Eigen::VectorXd* v : {&xa, &xa_n, &va, &fa, &ra, &dxa, &xa_trial}) v->setZero(na);
  ka.setZero(na, na);
  ca.setZero(na, na);
  jac_a.setZero(na, na);
  lu_a = Eigen::PartialPivLU<Eigen::MatrixXd>(na);
  if (na > 0) lu_a.compute(Eigen::MatrixXd::Identity(na, na));
  // The n x n jacobian only for full Newton (dense by design).
  if (integrator.options_.type == IntegratorType::kNewmark) {
    jac.setZero(n, n);
    lu = Eigen::PartialPivLU<Eigen::MatrixXd>(n);
    lu.compute(Eigen::MatrixXd::Identity(n, n));
  }
}

// Velocity of the `a` dofs implied by the trial displacement w.xa (Newmark relations).
void NewmarkIntegrator::NonlinearVelocity(NewmarkWorkspace& w) const {
  const double dt = options_.step_s, g = options_.gamma, b = options_.beta;
  w.va = a1_ * (w.xa - w.xa_n) + (1.0 - g / b) * w.z.segment(n_, na_) +
         dt * (1.0 - g / (2.0 * b)) * w.z.segment(2 * n_, na_);
}

bool NewmarkIntegrator::StepModified(NewmarkWorkspace& w, bool has_load, int* iterations,
                                     double* residual) const {
  if (sparse_) {
    // rhs = M u1 + C u2 + g (eq. 23's known part), y = S_b^-1 rhs_b and
    // bhat = rhs_a - S_ab y: w.rhs becomes [bhat; y] as in the dense path.
    // Run() keeps w.u = [u1; u2] of the current state (fused with the update).
    if (has_load) {
      w.rhs.setZero();
      AddLoad(w, w.rhs);
    }
    sparse_step_->Apply(w.u.data(), has_load, w.rhs.data());
    if (na_ > 0) w.rhs.head(na_).noalias() -= sab_sparse_ * w.rhs.tail(nb_);
  } else {
    // y = S_b^-1 rhs_b and bhat = rhs_a - S_ab y (the right side of eq. 29 at
    // x_b = y): w.rhs = [bhat; y] = T [M, C] [u1; u2] (see the header).
    // Run() keeps w.u = [u1; u2] of the current state (fused with the update).
    multiply_small_(condensed_mc_.data(), n_, 2 * n_, w.u.data(), w.rhs.data());
    if (has_load)
      for (Eigen::Index k = 0; k < w.load_now.size(); ++k)
        if (w.load_now[k] != 0.0) w.rhs.tail(nb_) += w.load_now[k] * w.load_y.col(k);
  }
  *iterations = 0;
  *residual = 0.0;
  if (na_ > 0) {
    w.ra = w.rhs.head(na_);  // ra holds bhat during the iterations
    if (has_load && !sparse_)
      for (Eigen::Index k = 0; k < w.load_now.size(); ++k)
        if (w.load_now[k] != 0.0) w.ra += w.load_now[k] * w.load_bhat.col(k);
    if (na_ == 1) return SolveScalar(w, iterations, residual);
    if (!SolveCondensed(w, shat_, iterations, residual)) return false;
    w.x_new.head(na_) = w.xa;
  }
  // eq. 28: x_b = S_b^-1 (rhs_b - S_ba x_a) = y - H x_a.
  w.x_new.tail(nb_) = w.rhs.tail(nb_);
  if (na_ > 0) w.x_new.tail(nb_).noalias() -= h_ * w.xa;
  return true;
}

// eq. 29 on the `a` dofs (n_a >= 2) by Newton from x_a = x_n (w.z's `a`
// entries), bhat in w.ra; the solution in w.xa.
bool NewmarkIntegrator::SolveCondensed(NewmarkWorkspace& w, const Eigen::MatrixXd& shat, int* iterations,
                                       double* residual) const {
  w.xa_n = w.z.head(na_);
  w.xa = w.xa_n;
  bool converged = false;
  for (int it = 0; it <= options_.max_iterations; ++it) {
    NonlinearVelocity(w);
    nonlinear_.Evaluate(w.xa, w.va, w.fa, w.ka, w.ca);
    // Condensed residual R = Shat x_a - bhat - f_a (eq. 29 with r_b = 0 kept by eq. 28).
    w.dxa.noalias() = shat * w.xa;
    const double scale = std::max({w.dxa.lpNorm<Eigen::Infinity>(), w.ra.lpNorm<Eigen::Infinity>(),
                                   w.fa.lpNorm<Eigen::Infinity>(), 1e-300});
    w.dxa -= w.ra + w.fa;
    *residual = w.dxa.lpNorm<Eigen::Infinity>() / scale;
    if (!std::isfinite(*residual)) return false;
    if (*residual <= options_.tolerance) {
      converged = true;
      break;
    }
    if (it == options_.max_iterations) break;
    // Tangent of eq. 29: Shat + K_t + a1 C_t on the `a` dofs.
    w.jac_a = shat + w.ka + a1_ * w.ca;
    w.lu_a.compute(w.jac_a);
    w.xa_trial = w.lu_a.solve(w.dxa);
    w.xa -= w.xa_trial;
    ++*iterations;
  }
  return converged;
}

// eq. 29 for a single nonlinear dof, in scalars; then eq. 28 for x_b.
bool NewmarkIntegrator::SolveScalar(NewmarkWorkspace& w, int* iterations, double* residual) const {
  const double dt = options_.step_s, g = options_.gamma, b = options_.beta;
  const double x_n = w.z[0], v_n = w.z[n_], a_n = w.z[2 * n_];
  const double shat = shat_(0, 0), bhat = w.ra[0];
  // The velocity implied by a trial x (Newmark relations): v = a1 (x - x_n) + v0.
  const double v0 = (1.0 - g / b) * v_n + dt * (1.0 - g / (2.0 * b)) * a_n;
  // Start from the Taylor predictor x_n + dt v_n + dt^2 a_n / 2.
  double x = x_n + dt * (v_n + 0.5 * dt * a_n), f = 0.0, k = 0.0, c = 0.0;
  for (int it = 0; it <= options_.max_iterations; ++it) {
    nonlinear_.EvaluateScalar(x, a1_ * (x - x_n) + v0, &f, &k, &c);
    const double sx = shat * x;
    const double scale = std::max({std::abs(sx), std::abs(bhat), std::abs(f), 1e-300});
    const double r = sx - bhat - f;
    *residual = std::abs(r) / scale;
    if (!std::isfinite(*residual)) return false;
    if (*residual <= options_.tolerance) {
      w.xa[0] = x;
      w.x_new[0] = x;
      w.x_new.tail(nb_) = w.rhs.tail(nb_);
      w.x_new.tail(nb_).noalias() -= h_.col(0) * x;
      return true;
    }
    if (it == options_.max_iterations) break;
    x -= r / (shat + k + a1_ * c);
    ++*iterations;
  }
  return false;
}

bool NewmarkIntegrator::StepDenseScalar(NewmarkWorkspace& w, bool has_load, int* iterations,
                                        double* residual, bool* bounded) const {
  // As StepModified + SolveScalar + Run's update for this case, the same
  // operations in the same order, with scalars and raw pointers.
  double* const rhs = w.rhs.data();
  multiply_small_(condensed_mc_.data(), n_, 2 * n_, w.u.data(), rhs);
  double bhat = rhs[0];
  if (has_load) {
    for (Eigen::Index k = 0; k < w.load_now.size(); ++k) {
      const double load = w.load_now[k];
      if (load == 0.0) continue;
      w.rhs.tail(nb_) += load * w.load_y.col(k);
      bhat += load * w.load_bhat(0, k);
    }
  }
  const double* const z = w.z.data();
  const double x_n = z[0], v_n = z[n_], a_n = z[2 * n_];
  const double shat = shat_scalar_, a1 = a1_, dt = options_.step_s, tolerance = options_.tolerance;
  const int max_iterations = options_.max_iterations;
  // eq. 29 in x_a: R(x) = shat x - bhat - f(x, v(x)), v(x) = a1 (x - x_n) + v0
  // (Newmark relations), from the Taylor predictor x_n + dt x'_n + dt^2 x''_n / 2.
  const double v0 = v0_velocity_ * v_n + v0_acceleration_ * a_n;
  double x = x_n + dt * (v_n + 0.5 * dt * a_n);
  if (!internal::SolveScalarNewton(nonlinear_, shat, bhat, a1, x_n, v0, tolerance, max_iterations, &x,
                                   iterations, residual))
    return false;
  rhs[0] = x;  // y[0] = x_a: x_new = y - h x_a for every dof (h[0] = 0)
  *bounded = update_(coefficients_, n_, rhs, h_padded_.data(), x, w.x_new.data(), w.z.data(), w.u.data());
  return true;
}

bool NewmarkIntegrator::StepFull(NewmarkWorkspace& w, bool has_load, int* iterations,
                                 double* residual) const {
  w.rhs.noalias() = rhs_matrix_ * w.z;
  if (has_load) AddLoad(w, w.rhs);
  w.x_new = w.z.head(n_);
  w.xa_n = w.z.head(na_);
  *iterations = 0;
  for (int it = 0; it <= options_.max_iterations; ++it) {
    w.xa = w.x_new.head(na_);
    NonlinearVelocity(w);
    nonlinear_.Evaluate(w.xa, w.va, w.fa, w.ka, w.ca);
    // Residual of eq. 23: r = S x - rhs - f_nl.
    w.r.noalias() = s_ * w.x_new;
    const double scale = std::max({w.r.lpNorm<Eigen::Infinity>(), w.rhs.lpNorm<Eigen::Infinity>(),
                                   w.fa.lpNorm<Eigen::Infinity>(), 1e-300});
    w.r -= w.rhs;
    w.r.head(na_) -= w.fa;
    *residual = w.r.lpNorm<Eigen::Infinity>() / scale;
    if (!std::isfinite(*residual)) return false;
    if (*residual <= options_.tolerance) return true;
    // The round-off floor of S x (a fine mesh: stiff rotation rows cancel in
    // S x, so ||S x|| << ||S|| ||x||): a backward error of 1e3 eps is converged.
    if (w.r.lpNorm<Eigen::Infinity>() <=
        1e3 * std::numeric_limits<double>::epsilon() * s_norm_ * w.x_new.lpNorm<Eigen::Infinity>())
      return true;
    if (it == options_.max_iterations) break;
    // Jacobian (eq. 25), refactored at every iteration: the cost the
    // modified method avoids.
    w.jac = s_;
    w.jac.topLeftCorner(na_, na_) += w.ka + a1_ * w.ca;
    w.lu.compute(w.jac);
    w.dx = w.lu.solve(w.r);
    w.x_new -= w.dx;
    ++*iterations;
  }
  return false;
}

SimulationSummary NewmarkIntegrator::Run(const State& initial, const ExternalLoad& load,
                                         Recording* recording) const {
  NewmarkWorkspace workspace(*this);
  return Run(initial, load, recording, &workspace);
}

SimulationSummary NewmarkIntegrator::Run(const State& initial, const ExternalLoad& load,
                                         Recording* recording, NewmarkWorkspace* workspace) const {
  const auto start = std::chrono::steady_clock::now();
  if (initial.displacement.size() != n_ || initial.velocity.size() != n_) {
    ThrowInvalid("initial state", "displacement and velocity of dimension " + ToText(n_),
                 ToText(initial.displacement.size()) + " and " + ToText(initial.velocity.size()));
  }
  const int steps = options_.steps;
  const bool has_load = load.columns() > 0;
  if (has_load && (load.pattern.rows() != n_ || load.history.rows() != load.columns() ||
                   load.history.cols() != steps + 1)) {
    ThrowInvalid("external load", "a " + ToText(n_) + " x K pattern and a K x " + ToText(steps + 1) +
                                      " history",
                 ToText(load.pattern.rows()) + " x " + ToText(load.columns()) + " and " +
                     ToText(load.history.rows()) + " x " + ToText(load.history.cols()));
  }
  PODID_CHECK(recording != nullptr && workspace != nullptr);
  const int n_rec = static_cast<int>(recording->dofs.size());
  std::vector<int> rec(n_rec);
  for (int k = 0; k < n_rec; ++k) {
    const int d = recording->dofs[k];
    if (d < 0 || d >= n_) ThrowInvalid("recorded dof", "a dof in 0.." + ToText(n_ - 1), ToText(d));
    rec[k] = inv_perm_[d];
  }
  const int stride = options_.record_stride;
  const int rows = steps / stride + 1;
  recording->displacement.resize(rows, n_rec);
  if (recording->record_velocity) recording->velocity.resize(rows, n_rec);
  if (recording->record_acceleration) recording->acceleration.resize(rows, n_rec);

  NewmarkWorkspace& w = *workspace;
  PrepareLoad(load, w);
  auto x = w.z.head(n_);
  auto v = w.z.segment(n_, n_);
  auto acc = w.z.tail(n_);
  for (int k = 0; k < n_; ++k) {
    x[k] = initial.displacement[perm_[k]];
    v[k] = initial.velocity[perm_[k]];
  }
  // Initial acceleration from the equation of motion at t = 0.
  w.xa = x.head(na_);
  w.va = v.head(na_);
  nonlinear_.Evaluate(w.xa, w.va, w.fa, w.ka, w.ca);
  w.rhs.setZero();
  w.rhs.head(na_) = w.fa;
  if (has_load) AddLoad(w, w.rhs);
  if (sparse_) {
    w.rhs.noalias() -= stiffness_sparse_ * x;
    w.rhs.noalias() -= damping_sparse_ * v;
    acc = mass_ldlt_.solve(w.rhs);
  } else {
    w.rhs.noalias() -= stiffness_ * x;
    w.rhs.noalias() -= damping_ * v;
    acc.noalias() = mass_inverse_ * w.rhs;
  }

  SimulationSummary summary;
  summary.integrator = options_.type;
  summary.dofs = n_;
  summary.nonlinear_dofs = na_;
  summary.steps_requested = steps;
  summary.step_error_estimate = step_error_estimate_;
  // Raw column pointers: the recording's stores then cannot alias the
  // matrices' sizes, which would be reloaded at every sample.
  double* const rec_x = recording->displacement.data();
  double* const rec_v = recording->record_velocity ? recording->velocity.data() : nullptr;
  double* const rec_a = recording->record_acceleration ? recording->acceleration.data() : nullptr;
  const int* const rec_dofs = rec.data();
  const double* const zx = w.z.data();
  auto record = [&](int row) {
    for (int k = 0; k < n_rec; ++k) rec_x[static_cast<std::ptrdiff_t>(k) * rows + row] = zx[rec_dofs[k]];
    if (rec_v)
      for (int k = 0; k < n_rec; ++k) rec_v[static_cast<std::ptrdiff_t>(k) * rows + row] = zx[n_ + rec_dofs[k]];
    if (rec_a)
      for (int k = 0; k < n_rec; ++k)
        rec_a[static_cast<std::ptrdiff_t>(k) * rows + row] = zx[2 * n_ + rec_dofs[k]];
  };
  record(0);
  summary.rows_recorded = 1;

  const double dt = options_.step_s, g = options_.gamma;
  const bool dense_condensed = options_.type == IntegratorType::kModifiedNewmark && !sparse_;
  // One nonlinear dof on the dense path: the fused step (StepDenseScalar).
  const bool dense_scalar = dense_condensed && na_ == 1;
  if (dense_condensed || sparse_) {
    w.u.head(n_) = a0_ * x + a2_ * v + a3_ * acc;
    w.u.tail(n_) = a1_ * x + a4_ * v + a5_ * acc;
  }
  if (modal_) internal::ModalRunner::Prepare(*this, load, rec, w);
  summary.termination = SimulationTermination::kCompleted;
  int since_record = 0;
  SetMallocAllowed(false);
  if (modal_) internal::ModalRunner::Run(*this, load, rec, rows, recording, w, &summary);
  if (one_dof_) internal::OneDofRunner::Run(*this, load, rec, rows, recording, w, &summary);
  // The modal and one-dof paths run their own loops; the dense one below is then skipped.
  const int dense_steps = modal_ || one_dof_ ? 0 : steps;
  for (int step = 1; step <= dense_steps; ++step) {
    int iterations = 0;
    double residual = 0.0;
    bool bounded = true;
    if (has_load) w.load_now = load.history.col(step);
    const bool ok = dense_scalar ? StepDenseScalar(w, has_load, &iterations, &residual, &bounded)
                    : options_.type == IntegratorType::kModifiedNewmark
                        ? StepModified(w, has_load, &iterations, &residual)
                        : StepFull(w, has_load, &iterations, &residual);
    if (!internal::CountStep(ok, iterations, residual, step, dt, &summary)) break;
    if ((dense_condensed && !dense_scalar) || sparse_) {
      // The bounds check, the Newmark update and the next step's u in one kernel.
      bounded = update_(coefficients_, n_, nullptr, nullptr, 0.0, w.x_new.data(), w.z.data(), w.u.data());
    } else if (!dense_condensed) {
      // One pass catches both: NaN and inf fail |x| <= max_displacement.
      for (int i = 0; i < n_; ++i) bounded &= std::abs(w.x_new[i]) <= options_.max_displacement;
      if (bounded) {
        // Newmark updates of acceleration and velocity, fused in one pass:
        // acc_new = a0 (x_new - x) - a2 v - a3 acc; v += dt ((1 - g) acc + g acc_new).
        double* const zv = w.z.data() + n_;
        double* const za = w.z.data() + 2 * n_;
        double* const zxm = w.z.data();
        const double* const xn = w.x_new.data();
        for (int i = 0; i < n_; ++i) {
          const double an = a0_ * (xn[i] - zxm[i]) - a2_ * zv[i] - a3_ * za[i];
          zv[i] += dt * ((1.0 - g) * za[i] + g * an);
          za[i] = an;
          zxm[i] = xn[i];
        }
      }
    }
    if (!bounded) {
      summary.termination = w.x_new.allFinite() ? SimulationTermination::kDiverged
                                                : SimulationTermination::kNonFinite;
      summary.failure_time_s = step * dt;
      break;
    }
    summary.steps_completed = step;
    if (++since_record == stride) {  // step % stride == 0, without a division per step
      since_record = 0;
      record(step / stride);
      summary.rows_recorded = step / stride + 1;
    }
  }
  SetMallocAllowed(true);
  summary.wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::ostringstream os;
  os.precision(6);
  switch (summary.termination) {
    case SimulationTermination::kCompleted:
      os << "completed " << steps << " steps of " << dt << " s";
      break;
    case SimulationTermination::kNewtonFailed:
      os << "Newton failed at t = " << summary.failure_time_s << " s (step " << summary.steps_completed + 1
         << ") with relative residual " << summary.failure_residual << " after "
         << options_.max_iterations << " iterations; history kept up to t = "
         << summary.steps_completed * dt << " s";
      break;
    case SimulationTermination::kDiverged:
      os << "state diverged at t = " << summary.failure_time_s << " s (step " << summary.steps_completed + 1
         << "): |x| exceeded " << options_.max_displacement << "; history kept up to t = "
         << summary.steps_completed * dt << " s";
      break;
    case SimulationTermination::kNonFinite:
      os << "state became non-finite at t = " << summary.failure_time_s << " s (step "
         << summary.steps_completed + 1 << "); history kept up to t = " << summary.steps_completed * dt
         << " s";
      break;
    default:
      os << ToString(summary.termination);
  }
  summary.message = os.str();
  return summary;
}

}  // namespace podid
