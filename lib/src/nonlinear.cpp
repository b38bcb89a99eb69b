#include "podid/core/nonlinear.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "podid/core/error.hpp"

namespace podid {

void NonlinearForces::SetCoefficients(const std::vector<NonlinearitySpec>& specs) {
  PODID_CHECK(specs.size() == elements_.size());
  for (std::size_t i = 0; i < specs.size(); ++i) {
    PODID_CHECK(specs[i].type == elements_[i].spec.type);
    elements_[i].spec = specs[i];
  }
}

namespace {

std::vector<std::array<int, 2>> LegacyDofs(const std::vector<NonlinearitySpec>& specs, int n_nodes) {
  std::vector<std::array<int, 2>> dofs;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const NonlinearitySpec& s = specs[i];
    std::array<int, 2> d{-1, -1};
    const int nodes[2] = {s.node, s.node2};
    const int explicit_dofs[2] = {s.dof, s.dof2};
    for (int k = 0; k < 2; ++k) {
      if (explicit_dofs[k] > 0) {
        d[k] = explicit_dofs[k] - 1;
      } else if (k == 0 || nodes[k] >= 0) {
        if (nodes[k] < 1 || nodes[k] > n_nodes) {
          ThrowInvalid("nonlinearity." + std::to_string(i) + (k == 0 ? ".node" : ".nodes.1"),
                       "a node in 1.." + std::to_string(n_nodes), ToText(nodes[k]));
        }
        d[k] = TransverseDof(nodes[k]);
      }
    }
    dofs.push_back(d);
  }
  return dofs;
}

}  // namespace

NonlinearForces::NonlinearForces(const std::vector<NonlinearitySpec>& specs, int n_nodes)
    : NonlinearForces(specs, LegacyDofs(specs, n_nodes), 2 * n_nodes) {}

NonlinearForces::NonlinearForces(const std::vector<NonlinearitySpec>& specs,
                                 const std::vector<std::array<int, 2>>& dofs, int n_dofs) {
  PODID_CHECK(dofs.size() == specs.size());
  for (std::size_t i = 0; i < specs.size(); ++i) {
    for (int k = 0; k < 2; ++k) {
      const int d = dofs[i][k];
      if (k == 1 && d < 0) continue;
      if (d < 0 || d >= n_dofs) {
        ThrowInvalid("nonlinearity." + std::to_string(i) + (k == 0 ? ".dof" : ".dofs.1"),
                     "a model dof in 1.." + std::to_string(n_dofs) + " (not held by a support)",
                     d < 0 ? std::string("a constrained dof") : ToText(d + 1));
      }
      dofs_.push_back(d);
    }
    if (dofs[i][0] == dofs[i][1]) {
      ThrowInvalid("nonlinearity." + std::to_string(i) + ".dofs", "two different dofs",
                   "dof " + ToText(dofs[i][0] + 1) + " twice");
    }
  }
  std::sort(dofs_.begin(), dofs_.end());
  dofs_.erase(std::unique(dofs_.begin(), dofs_.end()), dofs_.end());
  auto local = [this](int dof) {
    return static_cast<int>(std::lower_bound(dofs_.begin(), dofs_.end(), dof) - dofs_.begin());
  };
  for (std::size_t i = 0; i < specs.size(); ++i) {
    NonlinearElement e;
    e.spec = specs[i];
    e.dof = dofs[i][0];
    e.local = local(e.dof);
    if (dofs[i][1] >= 0) {
      e.dof2 = dofs[i][1];
      e.local2 = local(e.dof2);
      has_joints_ = true;
    }
    elements_.push_back(e);
  }
}

void NonlinearForces::Evaluate(const Eigen::Ref<const Eigen::VectorXd>& x_a,
                               const Eigen::Ref<const Eigen::VectorXd>& v_a,
                               Eigen::Ref<Eigen::VectorXd> f_a,
                               Eigen::Ref<Eigen::MatrixXd> stiffness_a,
                               Eigen::Ref<Eigen::MatrixXd> damping_a) const {
  f_a.setZero();
  stiffness_a.setZero();
  damping_a.setZero();
  for (const NonlinearElement& e : elements_) {
    const int i = e.local, j = e.local2;
    if (j < 0) {
      internal::AddElement(e.spec, x_a[i], v_a[i], &f_a[i], &stiffness_a(i, i), &damping_a(i, i));
      continue;
    }
    // Joint: w = x_i - x_j; f on i, -f on j; K_t = k [1 -1; -1 1] (same for C_t).
    double f = 0.0, k = 0.0, c = 0.0;
    internal::AddElement(e.spec, x_a[i] - x_a[j], v_a[i] - v_a[j], &f, &k, &c);
    f_a[i] += f;
    f_a[j] -= f;
    stiffness_a(i, i) += k;
    stiffness_a(j, j) += k;
    stiffness_a(i, j) -= k;
    stiffness_a(j, i) -= k;
    damping_a(i, i) += c;
    damping_a(j, j) += c;
    damping_a(i, j) -= c;
    damping_a(j, i) -= c;
  }
}

}  // namespace podid
