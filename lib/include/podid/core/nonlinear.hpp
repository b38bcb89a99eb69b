#pragma once
// Local nonlinear elements (eqs. 20-21: f_nl is nonzero on the `a` dofs only),
// each on one dof (grounded: w = x_i) or between two dofs (a joint: w = x_i -
// x_j, v = v_i - v_j, the force f on i and -f on j). Each element gives the
// force it applies and its tangents, for Newton iterations:
//   cubic       f = -k3 w^3
//   polynomial  f = -(k1 w + k2 w^2 + k3 w^3)   (quadratic + cubic: hardening-softening)
//   gap         f = -k_c (w - g) if w > g;  -k_c (w + g) if w < -g;  0 otherwise
//   friction    f = -mu N tanh(v / v_reg)       (regularised Coulomb friction)
// Units: w in m, v in m/s, f in N.

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <vector>

#include "podid/core/case_spec.hpp"

namespace podid {

namespace internal {

// Adds one element's force and tangents at (w, v). Inline: the condensed
// integrator calls it twice a step through EvaluateScalar.
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

}  // namespace internal

struct NonlinearElement {
  NonlinearitySpec spec;
  int dof = 0;      ///< index among all model dofs
  int dof2 = -1;    ///< joint: the second dof; -1 grounded
  int local = 0;    ///< index among the nonlinear (`a`) dofs
  int local2 = -1;  ///< joint: the second dof's `a` index; -1 grounded
};

/// The set of nonlinear elements and the `a` partition they induce.
class NonlinearForces {
 public:
  NonlinearForces() = default;
  /// Legacy numbering (a beam clamped at node 0): element k acts on dof
  /// spec.dof - 1 when spec.dof > 0, else on TransverseDof(spec.node); a
  /// joint's second dof likewise from dof2 / node2. Throws
  /// std::invalid_argument for a node outside 1..n_nodes.
  NonlinearForces(const std::vector<NonlinearitySpec>& specs, int n_nodes);
  /// Resolved dofs: element k acts on dofs[k][0] (and dofs[k][1] >= 0 for a
  /// joint), 0-based model dofs in 0..n_dofs-1. Throws std::invalid_argument
  /// for a dof out of range or a joint from a dof to itself.
  NonlinearForces(const std::vector<NonlinearitySpec>& specs,
                  const std::vector<std::array<int, 2>>& dofs, int n_dofs);

  bool empty() const { return elements_.empty(); }
  /// Replaces the elements' coefficients with those of `specs` (the specs
  /// the elements were built from, in order, with only coefficients changed:
  /// same count and types; dofs are kept). For a Simulator's parameter change.
  void SetCoefficients(const std::vector<NonlinearitySpec>& specs);
  /// True when some element is a joint (the tangents are then not diagonal).
  bool has_joints() const { return has_joints_; }
  /// Sorted, unique free-dof indices of the nonlinear dofs (the `a` set).
  const std::vector<int>& dofs() const { return dofs_; }
  const std::vector<NonlinearElement>& elements() const { return elements_; }

  /// Forces and tangents on the `a` dofs (x_a, v_a, f_a: dim n_a; tangents
  /// n_a x n_a): f = f_nl(x, v), K_t = -df/dx, C_t = -df/dv (tangent stiffness
  /// and damping; diagonal unless has_joints()). Allocation-free.
  void Evaluate(const Eigen::Ref<const Eigen::VectorXd>& x_a,
                const Eigen::Ref<const Eigen::VectorXd>& v_a,
                Eigen::Ref<Eigen::VectorXd> f_a,
                Eigen::Ref<Eigen::MatrixXd> stiffness_a,
                Eigen::Ref<Eigen::MatrixXd> damping_a) const;

  /// The same for a single `a` dof (n_a = 1, no joint): the hot path of the
  /// condensed integrator, without vector overhead.
  void EvaluateScalar(double w, double v, double* f, double* stiffness, double* damping) const {
    double fs = 0.0, ks = 0.0, cs = 0.0;  // locals: no reload through the pointers per element
    for (const NonlinearElement& e : elements_) internal::AddElement(e.spec, w, v, &fs, &ks, &cs);
    *f = fs;
    *stiffness = ks;
    *damping = cs;
  }

 private:
  std::vector<NonlinearElement> elements_;
  std::vector<int> dofs_;
  bool has_joints_ = false;
};

}  // namespace podid
