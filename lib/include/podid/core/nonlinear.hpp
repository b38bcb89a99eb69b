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
#include <vector>

#include "podid/core/case_spec.hpp"

namespace podid {

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
  void EvaluateScalar(double w, double v, double* f, double* stiffness, double* damping) const;

 private:
  std::vector<NonlinearElement> elements_;
  std::vector<int> dofs_;
  bool has_joints_ = false;
};

}  // namespace podid
