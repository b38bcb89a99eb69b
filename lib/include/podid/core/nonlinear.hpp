#pragma once
// Local nonlinear elements acting on transverse dofs (eqs. 20-21: f_nl is
// nonzero on the `a` dofs only). Each element gives the force it applies to
// the beam and its tangents, for Newton iterations:
//   cubic       f = -k3 w^3
//   polynomial  f = -(k1 w + k2 w^2 + k3 w^3)   (quadratic + cubic: hardening-softening)
//   gap         f = -k_c (w - g) if w > g;  -k_c (w + g) if w < -g;  0 otherwise
//   friction    f = -mu N tanh(v / v_reg)       (regularised Coulomb friction)
// Units: w in m, v in m/s, f in N.

#include <Eigen/Core>
#include <vector>

#include "podid/core/case_spec.hpp"

namespace podid {

struct NonlinearElement {
  NonlinearitySpec spec;
  int dof = 0;     ///< index among all free dofs
  int local = 0;   ///< index among the nonlinear (`a`) dofs
};

/// The set of nonlinear elements and the `a` partition they induce.
class NonlinearForces {
 public:
  NonlinearForces() = default;
  /// Throws std::invalid_argument for a node outside 1..n_nodes.
  NonlinearForces(const std::vector<NonlinearitySpec>& specs, int n_nodes);

  bool empty() const { return elements_.empty(); }
  /// Sorted, unique free-dof indices of the nonlinear dofs (the `a` set).
  const std::vector<int>& dofs() const { return dofs_; }
  const std::vector<NonlinearElement>& elements() const { return elements_; }

  /// Forces and tangents on the `a` dofs (all dim n_a, or n_a x n_a):
  /// f = f_nl(w, v), k_t = -df/dw, c_t = -df/dv (tangent stiffness and
  /// damping; diagonal since every element acts on one dof). Allocation-free.
  void Evaluate(const Eigen::Ref<const Eigen::VectorXd>& w_a,
                const Eigen::Ref<const Eigen::VectorXd>& v_a,
                Eigen::Ref<Eigen::VectorXd> f_a,
                Eigen::Ref<Eigen::VectorXd> stiffness_a,
                Eigen::Ref<Eigen::VectorXd> damping_a) const;

  /// The same for a single `a` dof (n_a = 1): the hot path of the condensed
  /// integrator, without vector overhead.
  void EvaluateScalar(double w, double v, double* f, double* stiffness, double* damping) const;

 private:
  std::vector<NonlinearElement> elements_;
  std::vector<int> dofs_;
};

}  // namespace podid
