#include "podid/core/nonlinear.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "podid/core/error.hpp"

namespace podid {

NonlinearForces::NonlinearForces(const std::vector<NonlinearitySpec>& specs, int n_nodes) {
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const NonlinearitySpec& s = specs[i];
    if (s.node < 1 || s.node > n_nodes) {
      ThrowInvalid("nonlinearity." + std::to_string(i) + ".node",
                   "a node in 1.." + std::to_string(n_nodes), ToText(s.node));
    }
    dofs_.push_back(TransverseDof(s.node));
  }
  std::sort(dofs_.begin(), dofs_.end());
  dofs_.erase(std::unique(dofs_.begin(), dofs_.end()), dofs_.end());
  for (const NonlinearitySpec& s : specs) {
    NonlinearElement e;
    e.spec = s;
    e.dof = TransverseDof(s.node);
    e.local = static_cast<int>(std::lower_bound(dofs_.begin(), dofs_.end(), e.dof) - dofs_.begin());
    elements_.push_back(e);
  }
}

namespace {

// Adds one element's force and tangents at (w, v).
inline void AddElement(const NonlinearitySpec& s, double w, double v, double* f, double* k, double* c) {
  switch (s.type) {
    case NonlinearType::kCubic:
      *f -= s.k3_N_per_m3 * w * w * w;
      *k += 3.0 * s.k3_N_per_m3 * w * w;
      break;
    case NonlinearType::kPolynomial:
      *f -= (s.k1_N_per_m + (s.k2_N_per_m2 + s.k3_N_per_m3 * w) * w) * w;
      *k += s.k1_N_per_m + (2.0 * s.k2_N_per_m2 + 3.0 * s.k3_N_per_m3 * w) * w;
      break;
    case NonlinearType::kGap:
      if (w > s.gap_m) {
        *f -= s.contact_stiffness_N_per_m * (w - s.gap_m);
        *k += s.contact_stiffness_N_per_m;
      } else if (w < -s.gap_m) {
        *f -= s.contact_stiffness_N_per_m * (w + s.gap_m);
        *k += s.contact_stiffness_N_per_m;
      }
      break;
    case NonlinearType::kFriction: {
      const double slip = s.friction_coefficient * s.normal_force_N;
      const double th = std::tanh(v / s.regularisation_velocity_m_per_s);
      *f -= slip * th;
      *c += slip * (1.0 - th * th) / s.regularisation_velocity_m_per_s;
      break;
    }
  }
}

}  // namespace

void NonlinearForces::EvaluateScalar(double w, double v, double* f, double* stiffness,
                                     double* damping) const {
  *f = *stiffness = *damping = 0.0;
  for (const NonlinearElement& e : elements_) AddElement(e.spec, w, v, f, stiffness, damping);
}

void NonlinearForces::Evaluate(const Eigen::Ref<const Eigen::VectorXd>& w_a,
                               const Eigen::Ref<const Eigen::VectorXd>& v_a,
                               Eigen::Ref<Eigen::VectorXd> f_a,
                               Eigen::Ref<Eigen::VectorXd> stiffness_a,
                               Eigen::Ref<Eigen::VectorXd> damping_a) const {
  f_a.setZero();
  stiffness_a.setZero();
  damping_a.setZero();
  for (const NonlinearElement& e : elements_) {
    AddElement(e.spec, w_a[e.local], v_a[e.local], &f_a[e.local], &stiffness_a[e.local],
               &damping_a[e.local]);
  }
}

}  // namespace podid
