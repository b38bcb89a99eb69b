#include "podid/core/beam_model.hpp"

#include <Eigen/LU>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <string_view>

#include "podid/core/error.hpp"

namespace podid {

namespace {

constexpr std::string_view kBeamKeys =
    "beam.length, beam.elements, beam.youngs_modulus, beam.density, beam.area (or width, height)";

// Each value and each coefficient of the element matrices must be a normal
// double (no overflow to inf, no underflow to 0 or a subnormal), so that M and
// K are finite and of full rank in floating point.
void CheckNormal(double value, std::string_view key, std::string_view what) {
  if (!(value > 0 && std::isnormal(value))) {
    ThrowInvalid(key, std::string(what) + " between 2.3e-308 and 1.7e308 (a normal double)",
                 ToText(value));
  }
}

}  // namespace

BeamModel BeamModel::BuildLinear(const BeamSpec& beam) {
  if (!(beam.elements >= 1)) ThrowInvalid("beam.elements", "an integer >= 1", ToText(beam.elements));
  const bool single = beam.segments.empty();
  std::vector<BeamSegmentSpec> segments = beam.segments;
  if (single) {
    segments.push_back({beam.length_m, beam.elements, beam.youngs_modulus_Pa,
                        beam.density_kg_per_m3, beam.area_m2, beam.second_moment_m4});
  }
  long long total = 0;
  for (const BeamSegmentSpec& seg : segments) total += seg.elements;
  if (total != beam.elements) {
    ThrowInvalid("beam.elements", "the sum of the segments' elements, " + ToText(total),
                 ToText(beam.elements));
  }
  if (2LL * (beam.elements + 1) > kMaxModelDofs) {
    ThrowInvalid("beam.elements", "at most " + ToText(kMaxModelDofs / 2 - 1) + " elements in all",
                 ToText(beam.elements));
  }

  const int n_nodes = beam.elements + 1;
  // The end conditions remove dofs (BeamDof() gives the remaining order):
  // kept[2 node + (0: w, 1: theta)] is the model dof, or -1 when held.
  BeamModel model;
  std::vector<int> kept(2 * static_cast<std::size_t>(n_nodes), -1);
  int n = 0;
  for (int node = 0; node < n_nodes; ++node) {
    for (const SensorDof which : {SensorDof::kW, SensorDof::kTheta}) {
      const int d = BeamDof(beam, node, which);
      if (d < 0) continue;
      PODID_CHECK(d == n);
      if (which == SensorDof::kW) model.transverse_.push_back(d);
      kept[2 * node + (which == SensorDof::kW ? 0 : 1)] = d;
      ++n;
    }
  }
  std::vector<Eigen::Triplet<double>> k_triplets, m_triplets;
  k_triplets.reserve(16 * static_cast<std::size_t>(beam.elements));
  m_triplets.reserve(16 * static_cast<std::size_t>(beam.elements));
  int first_element = 0;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const BeamSegmentSpec& seg = segments[i];
    const std::string prefix = single ? "beam." : "beam.segment." + std::to_string(i) + ".";
    if (!(seg.elements >= 1))
      ThrowInvalid(prefix + "elements", "an integer >= 1", ToText(seg.elements));
    CheckNormal(seg.length_m, prefix + "length", "a length > 0 m");
    CheckNormal(seg.youngs_modulus_Pa, prefix + "youngs_modulus", "a modulus > 0 Pa");
    CheckNormal(seg.density_kg_per_m3, prefix + "density", "a density > 0 kg/m^3");
    CheckNormal(seg.area_m2, prefix + "area", "an area > 0 m^2");
    CheckNormal(seg.second_moment_m4,
                single ? std::string("beam section (from beam.area or width, height)")
                       : prefix + "second_moment (or area, width, height)",
                "a second moment of area > 0 m^4");

    const double l = seg.length_m / seg.elements;
    const double ei = seg.youngs_modulus_Pa * seg.second_moment_m4;
    const double rho_a = seg.density_kg_per_m3 * seg.area_m2;
    // The extreme coefficients of ke (EI/l^3, EI/l) and me (rho A l, rho A l^3)
    // and the frequency scale EI / (rho A l^4): the others lie between them.
    const std::string keys = single ? std::string(kBeamKeys)
                                    : "beam.segment." + std::to_string(i) +
                                          " (length, elements, youngs_modulus, density, section)";
    CheckNormal(l, keys, "an element length l = length / elements > 0 m");
    CheckNormal(ei, keys, "a bending stiffness E I > 0 N m^2");
    CheckNormal(rho_a, keys, "a mass per length rho A > 0 kg/m");
    CheckNormal(ei / (l * l * l), keys, "an element stiffness E I / l^3 > 0 N/m");
    CheckNormal(ei / l, keys, "an element stiffness E I / l > 0 N m");
    CheckNormal(rho_a * l, keys, "an element mass rho A l > 0 kg");
    CheckNormal(rho_a * l * l * l, keys, "an element rotary mass rho A l^3 > 0 kg m^2");
    CheckNormal(ei / (rho_a * l * l * l * l), keys, "a frequency scale E I / (rho A l^4) > 0 s^-2");

    Eigen::Matrix4d ke;
    ke << 12, 6 * l, -12, 6 * l,  //
        6 * l, 4 * l * l, -6 * l, 2 * l * l,  //
        -12, -6 * l, 12, -6 * l,  //
        6 * l, 2 * l * l, -6 * l, 4 * l * l;
    ke *= ei / (l * l * l);
    Eigen::Matrix4d me;
    me << 156, 22 * l, 54, -13 * l,  //
        22 * l, 4 * l * l, 13 * l, -3 * l * l,  //
        54, 13 * l, 156, -22 * l,  //
        -13 * l, -3 * l * l, -22 * l, 4 * l * l;
    me *= rho_a * l / 420.0;
    for (int e = first_element; e < first_element + seg.elements; ++e) {
      for (int r = 0; r < 4; ++r) {
        const int dr = kept[2 * e + r];
        if (dr < 0) continue;
        for (int c = 0; c < 4; ++c) {
          const int dc = kept[2 * e + c];
          if (dc < 0) continue;
          k_triplets.emplace_back(dr, dc, ke(r, c));
          m_triplets.emplace_back(dr, dc, me(r, c));
        }
      }
    }
    first_element += seg.elements;
  }
  // setFromTriplets sums the duplicates: the elements' shared nodes.
  model.stiffness_.resize(n, n);
  model.stiffness_.setFromTriplets(k_triplets.begin(), k_triplets.end());
  model.mass_.resize(n, n);
  model.mass_.setFromTriplets(m_triplets.begin(), m_triplets.end());
  model.damping_.resize(n, n);
  return model;
}

BeamModel BeamModel::FromMatrices(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& stiffness,
                                  const Eigen::MatrixXd& damping,
                                  const std::vector<NonlinearitySpec>& nonlinearities) {
  return FromMatrices(Eigen::SparseMatrix<double>(mass.sparseView(0.0, 0.0)),
                      Eigen::SparseMatrix<double>(stiffness.sparseView(0.0, 0.0)),
                      Eigen::SparseMatrix<double>(damping.sparseView(0.0, 0.0)), nonlinearities);
}

BeamModel BeamModel::FromMatrices(const Eigen::SparseMatrix<double>& mass,
                                  const Eigen::SparseMatrix<double>& stiffness,
                                  const Eigen::SparseMatrix<double>& damping,
                                  const std::vector<NonlinearitySpec>& nonlinearities) {
  const Eigen::Index n = mass.rows();
  for (const Eigen::SparseMatrix<double>* m : {&mass, &stiffness, &damping}) {
    if (m->rows() != n || m->cols() != n) {
      ThrowInvalid("BeamModel::FromMatrices", "square matrices of one size " + ToText(n),
                   ToText(m->rows()) + " x " + ToText(m->cols()));
    }
  }
  BeamModel model;
  model.mass_ = mass;
  model.stiffness_ = stiffness;
  model.damping_ = damping;
  for (Eigen::SparseMatrix<double>* m : {&model.mass_, &model.stiffness_, &model.damping_})
    m->makeCompressed();
  // Node k's transverse dof is 2 (k - 1): nodes 1..(n + 1) / 2 exist.
  model.nonlinear_ = NonlinearForces(nonlinearities, static_cast<int>((n + 1) / 2));
  for (int d : model.nonlinear_.dofs()) {
    if (d >= n) ThrowInvalid("BeamModel::FromMatrices: nonlinearity", "a dof in 1.." + ToText(n), ToText(d + 1));
  }
  for (Eigen::Index i = 0; i < n; i += 2) model.transverse_.push_back(static_cast<int>(i));
  return model;
}

// Relative round-off of the 2 x 2 Rayleigh solve: a coefficient that is 0
// exactly (equal zeta / omega) may come out as -1e-17 of its scale.
constexpr double kRayleighRoundOff = 1e-12;
// Two modal frequencies closer than this (relative) are one frequency: the
// eigensolver's accuracy is far finer, a real structure's split far coarser.
constexpr double kRayleighMinSeparation = 1e-6;

void RayleighFromModalRatios(double omega1_rad_per_s, double zeta1, double omega2_rad_per_s,
                             double zeta2, double* alpha_per_s, double* beta_s) {
  PODID_CHECK(omega1_rad_per_s > 0 && omega2_rad_per_s > 0 && omega1_rad_per_s != omega2_rad_per_s);
  // Solve [1/(2 w1)  w1/2; 1/(2 w2)  w2/2] [alpha; beta] = [z1; z2].
  const double w1 = omega1_rad_per_s, w2 = omega2_rad_per_s;
  *beta_s = 2.0 * (zeta2 * w2 - zeta1 * w1) / (w2 * w2 - w1 * w1);
  *alpha_per_s = 2.0 * zeta1 * w1 - *beta_s * w1 * w1;
}

BeamModel BeamModel::Build(const CaseSpec& spec) {
  BeamModel model = BuildStructure(spec);
  // The springs' dashpots and an imported C, added to Rayleigh damping below.
  const Eigen::SparseMatrix<double> extra_damping = model.damping_;
  const DampingSpec& d = spec.damping;
  if (d.type == DampingType::kRayleigh) {
    if (d.from_modal_ratios) {
      const int n = model.dofs();
      for (int k = 0; k < 2; ++k) {
        if (d.modes[k] < 1 || d.modes[k] > n) {
          ThrowInvalid("damping.modes." + std::to_string(k), "a mode in 1.." + std::to_string(n),
                       ToText(d.modes[k]));
        }
      }
      if (d.modes[0] == d.modes[1]) {
        ThrowInvalid("damping.modes", "two different modes", ToText(d.modes[0]) + " twice");
      }
      // Only the modes the ratios name (the lowest max(modes) of them).
      const ModalAnalysis modes = model.Modes(std::max(d.modes[0], d.modes[1]));
      const double w1 = 2 * std::numbers::pi * modes.frequencies_Hz[d.modes[0] - 1];
      const double w2 = 2 * std::numbers::pi * modes.frequencies_Hz[d.modes[1] - 1];
      // Two modes of one frequency (a symmetric structure's pair) leave the
      // 2 x 2 solve singular: its alpha and beta are round-off.
      if (!(w1 > 0 && w2 > 0 && std::abs(w2 - w1) > kRayleighMinSeparation * std::max(w1, w2) &&
            std::isfinite(w1) && std::isfinite(w2))) {
        ThrowInvalid("damping.modal_ratios (with " + std::string(kBeamKeys) + ")",
                     "modes of two different finite frequencies > 0 Hz (apart by more than 1e-6 of "
                     "the higher)",
                     ToText(w1 / (2 * std::numbers::pi)) + " Hz and " +
                         ToText(w2 / (2 * std::numbers::pi)) + " Hz");
      }
      RayleighFromModalRatios(w1, d.modal_ratios[0], w2, d.modal_ratios[1], &model.alpha_per_s_,
                              &model.beta_s_);
      // A negative coefficient is negative damping outside the two modes (an
      // indefinite C: the integrator's factorisation aborted on it), as
      // damping.alpha/beta < 0 are refused. Round-off of an exact 0 is 0.
      const double alpha_scale = 2.0 * d.modal_ratios[0] * w1,
                   beta_scale = 2.0 * d.modal_ratios[1] / w2;
      if (model.alpha_per_s_ < -kRayleighRoundOff * alpha_scale ||
          model.beta_s_ < -kRayleighRoundOff * beta_scale) {
        ThrowInvalid("damping.modal_ratios",
                     "ratios whose Rayleigh fit has alpha >= 0 and beta >= 0 (else some modes have "
                     "negative damping)",
                     "[" + ToText(d.modal_ratios[0]) + ", " + ToText(d.modal_ratios[1]) + "] at " +
                         ToText(w1 / (2 * std::numbers::pi)) + " and " +
                         ToText(w2 / (2 * std::numbers::pi)) +
                         " Hz: alpha = " + ToText(model.alpha_per_s_) +
                         " 1/s, beta = " + ToText(model.beta_s_) + " s");
      }
      model.alpha_per_s_ = std::max(model.alpha_per_s_, 0.0);
      model.beta_s_ = std::max(model.beta_s_, 0.0);
    } else {
      model.alpha_per_s_ = d.alpha_per_s;
      model.beta_s_ = d.beta_s;
    }
    model.damping_ = model.alpha_per_s_ * model.mass_ + model.beta_s_ * model.stiffness_;
    if (extra_damping.nonZeros() > 0) model.damping_ += extra_damping;
    model.damping_.makeCompressed();
  }
  return model;
}

Eigen::VectorXd SolveStatic(const BeamModel& model, const Eigen::VectorXd& force,
                            const StaticSolveOptions& options, StaticSolveSummary* summary) {
  PODID_CHECK(force.size() == model.dofs());
  PODID_CHECK(summary != nullptr);
  const Eigen::SparseMatrix<double>& k = model.stiffness();
  const NonlinearForces& nl = model.nonlinear();
  const std::vector<int>& a = nl.dofs();
  const int na = static_cast<int>(a.size());
  const int n = model.dofs();
  // One sparse LDL^T of K (fill-reducing ordering), reused by every Newton step.
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> k_ldlt(k);
  if (model.has_rigid_body_modes() || k_ldlt.info() != Eigen::Success ||
      !(k_ldlt.vectorD().minCoeff() > 0.0)) {
    ThrowInvalid("initial static force",
                 "a model whose stiffness holds it (positive definite K: no rigid-body motion)",
                 "a stiffness matrix without a Cholesky factor");
  }
  Eigen::VectorXd x = k_ldlt.solve(force);  // linear solution as the start
  Eigen::VectorXd wa(na), va = Eigen::VectorXd::Zero(na), fa(na);
  Eigen::MatrixXd ka(na, na), ca(na, na);
  // Newton on K + U K_t U^T (U selects the `a` dofs), condensed: with
  // Z = K^-1 U (n x n_a, once) and z0 = K^-1 (-r), u = U^T dx solves
  // (I + U^T Z K_t) u = U^T z0 and dx = z0 - Z K_t u.
  Eigen::MatrixXd z(n, na);
  {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
    for (int i = 0; i < na; ++i) {
      e[a[i]] = 1.0;
      z.col(i) = k_ldlt.solve(e);
      e[a[i]] = 0.0;
    }
  }
  Eigen::MatrixXd g(na, na);  // U^T Z
  for (int i = 0; i < na; ++i) g.row(i) = z.row(a[i]);

  const double force_norm = std::max(force.norm(), 1e-300);
  // Backward-error scale: the residual's round-off grows with ||K|| ||x||, so
  // a fine mesh (stiff rotation dofs) cannot reach ||r|| <= tol ||F||.
  const double k_norm = (k.cwiseAbs() * Eigen::VectorXd::Ones(n)).maxCoeff();
  auto residual = [&](const Eigen::VectorXd& xx, Eigen::VectorXd* r) {
    for (int i = 0; i < na; ++i) wa[i] = xx[a[i]];
    nl.Evaluate(wa, va, fa, ka, ca);
    *r = k * xx - force;
    for (int i = 0; i < na; ++i) (*r)[a[i]] -= fa[i];
  };
  auto backward_ok = [&](const Eigen::VectorXd& xx, const Eigen::VectorXd& r) {
    const double scale = k_norm * xx.lpNorm<Eigen::Infinity>() + fa.lpNorm<Eigen::Infinity>() +
                         force.lpNorm<Eigen::Infinity>();
    return r.lpNorm<Eigen::Infinity>() <= options.tolerance * scale;
  };
  // The Newton correction -J^-1 r, J = K + U K_t U^T at the last evaluation.
  auto newton_step = [&](const Eigen::VectorXd& rr) {
    Eigen::VectorXd dx = k_ldlt.solve(-rr);
    if (na > 0) {
      Eigen::VectorXd ua(na);
      for (int i = 0; i < na; ++i) ua[i] = dx[a[i]];
      const Eigen::MatrixXd small = Eigen::MatrixXd::Identity(na, na) + g * ka;
      const Eigen::VectorXd u = small.partialPivLu().solve(ua);
      dx.noalias() -= z * (ka * u);
    }
    return dx;
  };
  Eigen::VectorXd r(x.size()), trial(x.size()), r_trial(x.size());
  residual(x, &r);
  summary->converged = false;
  summary->iterations = 0;
  for (int it = 0; it < options.max_iterations; ++it) {
    summary->relative_residual = r.norm() / force_norm;
    if (summary->relative_residual <= options.tolerance || force.norm() == 0.0) {
      summary->converged = true;
      break;
    }
    const Eigen::VectorXd dx = newton_step(r);
    // Backtracking: halve the step until the residual norm decreases.
    double step = 1.0;
    bool decreased = false;
    for (int halving = 0; halving < 40; ++halving) {
      trial = x + step * dx;
      residual(trial, &r_trial);
      if (r_trial.norm() < r.norm()) {
        decreased = true;
        break;
      }
      step *= 0.5;
    }
    const double previous = r.norm();
    x = trial;
    r = r_trial;
    summary->iterations = it + 1;
    // At the round-off floor: no further progress is possible.
    if (backward_ok(x, r) && (!decreased || r.norm() > 0.5 * previous)) break;
  }
  residual(x, &r);
  summary->relative_residual = r.norm() / force_norm;
  if (summary->relative_residual <= options.tolerance || force.norm() == 0.0 || backward_ok(x, r))
    summary->converged = true;
  // A forward-error estimate: the size of one more Newton step from the
  // computed residual (one step of iterative refinement; the residual's own
  // round-off, eps |K| |x|, mapped through J^-1, is the error an
  // ill-conditioned K leaves in x).
  const double x_norm = x.lpNorm<Eigen::Infinity>();
  summary->relative_error_estimate =
      x_norm > 0.0 ? newton_step(r).lpNorm<Eigen::Infinity>() / x_norm : 0.0;
  const std::string figures = "relative residual " + ToText(summary->relative_residual) +
                              ", estimated relative error " +
                              ToText(summary->relative_error_estimate);
  if (!summary->converged) {
    summary->message = "static solve did not converge in " +
                       std::to_string(options.max_iterations) + " iterations, " + figures;
  } else if (!(summary->relative_error_estimate <= kMaxStaticRelativeError)) {
    summary->converged = false;
    summary->message = "static solve: K is too ill-conditioned for an accurate deflection (" +
                       figures + ", above " + ToText(kMaxStaticRelativeError) +
                       "): elements of very different lengths or stiffnesses";
  } else {
    summary->message = "static solve converged in " + std::to_string(summary->iterations) +
                       " Newton iterations, " + figures;
  }
  return x;
}

}  // namespace podid
