#include "podid/core/beam_model.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
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
  const int n_all = 2 * n_nodes;
  Eigen::MatrixXd k_all = Eigen::MatrixXd::Zero(n_all, n_all);
  Eigen::MatrixXd m_all = Eigen::MatrixXd::Zero(n_all, n_all);
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
      k_all.block<4, 4>(2 * e, 2 * e) += ke;
      m_all.block<4, 4>(2 * e, 2 * e) += me;
    }
    first_element += seg.elements;
  }
  // The end conditions remove dofs (BeamDof() gives the remaining order).
  std::vector<int> keep;
  BeamModel model;
  for (int node = 0; node < n_nodes; ++node) {
    for (const SensorDof which : {SensorDof::kW, SensorDof::kTheta}) {
      const int d = BeamDof(beam, node, which);
      if (d < 0) continue;
      PODID_CHECK(d == static_cast<int>(keep.size()));
      if (which == SensorDof::kW) model.transverse_.push_back(d);
      keep.push_back(2 * node + (which == SensorDof::kW ? 0 : 1));
    }
  }
  const int n = static_cast<int>(keep.size());
  model.stiffness_ = k_all(keep, keep);
  model.mass_ = m_all(keep, keep);
  model.damping_ = Eigen::MatrixXd::Zero(n, n);
  return model;
}

BeamModel BeamModel::FromMatrices(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& stiffness,
                                  const Eigen::MatrixXd& damping,
                                  const std::vector<NonlinearitySpec>& nonlinearities) {
  const Eigen::Index n = mass.rows();
  for (const Eigen::MatrixXd* m : {&mass, &stiffness, &damping}) {
    if (m->rows() != n || m->cols() != n) {
      ThrowInvalid("BeamModel::FromMatrices", "square matrices of one size " + ToText(n),
                   ToText(m->rows()) + " x " + ToText(m->cols()));
    }
  }
  BeamModel model;
  model.mass_ = mass;
  model.stiffness_ = stiffness;
  model.damping_ = damping;
  // Node k's transverse dof is 2 (k - 1): nodes 1..(n + 1) / 2 exist.
  model.nonlinear_ = NonlinearForces(nonlinearities, static_cast<int>((n + 1) / 2));
  for (int d : model.nonlinear_.dofs()) {
    if (d >= n) ThrowInvalid("BeamModel::FromMatrices: nonlinearity", "a dof in 1.." + ToText(n), ToText(d + 1));
  }
  for (Eigen::Index i = 0; i < n; i += 2) model.transverse_.push_back(static_cast<int>(i));
  return model;
}

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
  const Eigen::MatrixXd extra_damping = model.damping_;
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
      const ModalAnalysis modes = model.Modes();
      const double w1 = 2 * std::numbers::pi * modes.frequencies_Hz[d.modes[0] - 1];
      const double w2 = 2 * std::numbers::pi * modes.frequencies_Hz[d.modes[1] - 1];
      if (!(w1 > 0 && w2 > 0 && w1 != w2 && std::isfinite(w1) && std::isfinite(w2))) {
        ThrowInvalid("damping.modal_ratios (with " + std::string(kBeamKeys) + ")",
                     "modes of two different finite frequencies > 0 Hz",
                     ToText(w1 / (2 * std::numbers::pi)) + " Hz and " +
                         ToText(w2 / (2 * std::numbers::pi)) + " Hz");
      }
      RayleighFromModalRatios(w1, d.modal_ratios[0], w2, d.modal_ratios[1], &model.alpha_per_s_,
                              &model.beta_s_);
    } else {
      model.alpha_per_s_ = d.alpha_per_s;
      model.beta_s_ = d.beta_s;
    }
    model.damping_ = model.alpha_per_s_ * model.mass_ + model.beta_s_ * model.stiffness_;
    if (extra_damping.any()) model.damping_ += extra_damping;
  }
  return model;
}

ModalAnalysis BeamModel::Modes() const {
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(stiffness_, mass_);
  // Values that pass the input checks can still give M and K too far apart in
  // scale for double precision: an input error, not a bug.
  if (solver.info() != Eigen::Success || !solver.eigenvalues().allFinite() ||
      !solver.eigenvectors().allFinite()) {
    ThrowInvalid("model (" + std::string(kBeamKeys) + ")",
                 "finite M (positive definite) and K whose modes double precision can compute",
                 "a failed eigensolution (max |M| " + ToText(mass_.cwiseAbs().maxCoeff()) +
                     ", max |K| " + ToText(stiffness_.cwiseAbs().maxCoeff()) + ")");
  }
  ModalAnalysis result;
  const int n = dofs();
  result.shapes = solver.eigenvectors();  // ascending eigenvalues, M-normalised
  result.frequencies_Hz.resize(n);
  result.damping_ratios.resize(n);
  for (int k = 0; k < n; ++k) {
    const double omega = std::sqrt(std::max(solver.eigenvalues()[k], 0.0));
    result.frequencies_Hz[k] = omega / (2 * std::numbers::pi);
    auto phi = result.shapes.col(k);
    // Sign convention: the largest-magnitude transverse component is positive.
    Eigen::Index best = transverse_.empty() ? 0 : transverse_.front();
    for (const int i : transverse_) {
      if (std::abs(phi[i]) > std::abs(phi[best])) best = i;
    }
    if (phi[best] < 0) phi = -phi;
    result.damping_ratios[k] = omega > 0 ? phi.dot(damping_ * phi) / (2 * omega) : 0.0;
  }
  return result;
}

Eigen::VectorXd SolveStatic(const BeamModel& model, const Eigen::VectorXd& force,
                            const StaticSolveOptions& options, StaticSolveSummary* summary) {
  PODID_CHECK(force.size() == model.dofs());
  PODID_CHECK(summary != nullptr);
  const Eigen::MatrixXd& k = model.stiffness();
  const NonlinearForces& nl = model.nonlinear();
  const std::vector<int>& a = nl.dofs();
  const int na = static_cast<int>(a.size());
  const Eigen::LLT<Eigen::MatrixXd> k_llt(k);
  if (model.has_rigid_body_modes() || k_llt.info() != Eigen::Success) {
    ThrowInvalid("initial static force",
                 "a model whose stiffness holds it (positive definite K: no rigid-body motion)",
                 "a stiffness matrix without a Cholesky factor");
  }
  Eigen::VectorXd x = k_llt.solve(force);  // linear solution as the start
  Eigen::VectorXd wa(na), va = Eigen::VectorXd::Zero(na), fa(na);
  Eigen::MatrixXd ka(na, na), ca(na, na);

  const double force_norm = std::max(force.norm(), 1e-300);
  // Backward-error scale: the residual's round-off grows with ||K|| ||x||, so
  // a fine mesh (stiff rotation dofs) cannot reach ||r|| <= tol ||F||.
  const double k_norm = k.cwiseAbs().rowwise().sum().maxCoeff();
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
    Eigen::MatrixXd jac = k;
    for (int i = 0; i < na; ++i)
      for (int j = 0; j < na; ++j) jac(a[i], a[j]) += ka(i, j);
    const Eigen::VectorXd dx = jac.partialPivLu().solve(-r);
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
  summary->message = summary->converged
                         ? "static solve converged in " + std::to_string(summary->iterations) +
                               " Newton iterations, relative residual " +
                               ToText(summary->relative_residual)
                         : "static solve did not converge in " +
                               std::to_string(options.max_iterations) +
                               " iterations, relative residual " + ToText(summary->relative_residual);
  return x;
}

}  // namespace podid
