// BeamModel::BuildStructure: the linear structure of a case (a beam with its
// masses and springs, or imported matrices) and the nonlinear elements placed
// on its dofs. Rayleigh damping is added by BeamModel::Build.
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "podid/core/beam_model.hpp"
#include "podid/core/error.hpp"

namespace podid {

int ResolveDof(const CaseSpec& spec, int node, int dof1, SensorDof which, std::string_view key) {
  const int n = spec.dofs();
  if (dof1 > 0) {
    if (dof1 > n) ThrowInvalid(key, "a model dof in 1.." + ToText(n), ToText(dof1));
    return dof1 - 1;
  }
  if (spec.model.type == ModelType::kMatrices) {
    ThrowInvalid(key, "a dof (1.." + ToText(n) + ") for a model of imported matrices",
                 "node " + ToText(node));
  }
  const int d = BeamDof(spec.beam, node, which);
  if (node < 0 || node > spec.beam.elements) {
    ThrowInvalid(key, "a node in 0.." + ToText(spec.beam.elements), ToText(node));
  }
  if (d < 0) {
    ThrowInvalid(key,
                 std::string("a node whose ") + (which == SensorDof::kW ? "w" : "theta") +
                     " is free (the " + (node == 0 ? "left" : "right") + " end is " +
                     ToString(node == 0 ? spec.beam.left : spec.beam.right) + ")",
                 "node " + ToText(node));
  }
  return d;
}

namespace {

/// Largest |A - A^T| relative to the largest |A| that counts as symmetric:
/// matrices written with 16 significant digits are symmetric to ~1e-16.
constexpr double kSymmetryTolerance = 1e-9;

void CheckSymmetric(const Eigen::SparseMatrix<double>& a, const std::string& what) {
  const Eigen::SparseMatrix<double> at = a.transpose();
  const Eigen::SparseMatrix<double> diff = a - at;
  const double scale = a.nonZeros() > 0 ? a.coeffs().cwiseAbs().maxCoeff() : 0.0;
  const double asym = diff.nonZeros() > 0 ? diff.coeffs().cwiseAbs().maxCoeff() : 0.0;
  if (!std::isfinite(scale) || !(asym <= kSymmetryTolerance * scale)) {
    ThrowInvalid(what, "a finite symmetric matrix (max |A - A^T| <= 1e-9 max |A|)",
                 "max |A - A^T| = " + ToText(asym) + ", max |A| = " + ToText(scale));
  }
}

/// Smallest pivot of a sparse LDL^T (fill-reducing ordering, no pivoting)
/// relative to the largest diagonal entry: PD needs > 0, PSD allows round-off
/// of the order n eps. A zero pivot (the factorisation stops) counts as 0.
double RelativeMinPivot(const Eigen::SparseMatrix<double>& a) {
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(a);
  const double scale = a.diagonal().cwiseAbs().maxCoeff();
  if (ldlt.info() != Eigen::Success || !(scale > 0)) return 0.0;
  const double dmin = ldlt.vectorD().minCoeff();
  return std::isfinite(dmin) ? dmin / scale : 0.0;
}

/// Relative LDL^T pivot below which an imported K is singular: a rigid-body
/// mode leaves a pivot of round-off size (~1e-16), a beam of 5000 elements
/// clamped at one end ~1e-12.
constexpr double kRigidPivot = 1e-14;

/// A beam's rigid motions w = a + b x are excluded when its supports and
/// springs give two independent conditions on (a, b): w(x) = 0 gives [1, x],
/// theta = 0 gives [0, 1].
bool BeamHasRigidBodyModes(const CaseSpec& spec) {
  std::vector<double> node_x(spec.beam.elements + 1, 0.0);
  if (spec.beam.segments.empty()) {
    for (int i = 0; i <= spec.beam.elements; ++i) node_x[i] = spec.beam.length_m * i / spec.beam.elements;
  } else {
    int node = 0;
    double x0 = 0.0;
    for (const BeamSegmentSpec& seg : spec.beam.segments) {
      for (int e = 1; e <= seg.elements; ++e) node_x[node + e] = x0 + seg.length_m * e / seg.elements;
      node += seg.elements;
      x0 += seg.length_m;
    }
  }
  bool rotation_held = false;
  std::vector<double> held_w;  // positions where w is held
  auto end = [&](BeamEnd e, double x) {
    if (e == BeamEnd::kClamped) rotation_held = true;
    if (e != BeamEnd::kFree) held_w.push_back(x);
  };
  end(spec.beam.left, node_x.front());
  end(spec.beam.right, node_x.back());
  for (const SpringSpec& k : spec.springs) {
    if (!(k.stiffness > 0) || k.node < 0 || k.node > spec.beam.elements) continue;
    if (k.dof == SensorDof::kTheta) {
      rotation_held = true;
    } else {
      held_w.push_back(node_x[k.node]);
    }
  }
  if (held_w.empty()) return true;
  if (rotation_held) return false;
  for (double x : held_w) {
    if (x != held_w.front()) return false;
  }
  return true;
}

}  // namespace

BeamModel BeamModel::BuildStructure(const CaseSpec& spec) {
  BeamModel model;
  if (spec.model.type == ModelType::kMatrices) {
    PODID_CHECK(spec.model.matrices != nullptr);
    const ImportedMatrices& imported = *spec.model.matrices;
    const Eigen::Index n = imported.mass.rows();
    const std::string& src = spec.source;
    auto check_size = [&](const Eigen::SparseMatrix<double>& m, const std::string& name) {
      if (m.rows() != n || m.cols() != n) {
        ThrowInvalid(src + ": model." + name,
                     "a square matrix of the mass matrix's size " + ToText(n) + " x " + ToText(n),
                     ToText(m.rows()) + " x " + ToText(m.cols()));
      }
    };
    check_size(imported.mass, "mass");
    check_size(imported.stiffness, "stiffness");
    // Sparse matrices stay sparse (a dense .mat variable arrives converted).
    model.mass_ = imported.mass;
    model.stiffness_ = imported.stiffness;
    CheckSymmetric(model.mass_, src + ": model.mass");
    CheckSymmetric(model.stiffness_, src + ": model.stiffness");
    if (imported.damping.size() > 0) {
      check_size(imported.damping, "damping");
      model.damping_ = imported.damping;
      CheckSymmetric(model.damping_, src + ": model.damping");
    } else {
      model.damping_.resize(n, n);
    }
    for (Eigen::SparseMatrix<double>* m : {&model.mass_, &model.stiffness_, &model.damping_})
      m->makeCompressed();
    if (!(RelativeMinPivot(model.mass_) > 0.0)) {
      ThrowInvalid(src + ": model.mass", "a positive definite mass matrix",
                   "a matrix without a Cholesky factor (a zero or negative mass)");
    }
    // K may be singular (rigid-body modes) but not indefinite.
    const double k_pivot = RelativeMinPivot(model.stiffness_);
    model.rigid_body_modes_ = k_pivot <= kRigidPivot;
    if (k_pivot < -1e-10) {
      ThrowInvalid(src + ": model.stiffness", "a positive semi-definite stiffness matrix",
                   "a negative pivot (relative " + ToText(k_pivot) + ")");
    }
    // Nor C: negative damping made the integrator's factorisation abort.
    if (model.damping_.nonZeros() > 0) {
      const double c_pivot = RelativeMinPivot(model.damping_);
      if (c_pivot < -1e-10) {
        ThrowInvalid(src + ": model.damping", "a positive semi-definite damping matrix",
                     "a negative pivot (relative " + ToText(c_pivot) + ")");
      }
    }
    for (Eigen::Index i = 0; i < n; ++i) model.transverse_.push_back(static_cast<int>(i));
  } else {
    model = BuildLinear(spec.beam);
    const int n = model.dofs();
    // Masses, springs and dashpots on the diagonal, added as sparse matrices.
    std::vector<Eigen::Triplet<double>> dm, dk, dc;
    for (std::size_t i = 0; i < spec.masses.size(); ++i) {
      const PointMassSpec& m = spec.masses[i];
      const std::string key = "mass." + std::to_string(i) + ".node";
      if (m.node < 0 || m.node > spec.beam.elements) {
        ThrowInvalid(key, "a node in 0.." + ToText(spec.beam.elements), ToText(m.node));
      }
      // A mass on a held dof moves with the support: it adds nothing.
      const int w = BeamDof(spec.beam, m.node, SensorDof::kW);
      const int theta = BeamDof(spec.beam, m.node, SensorDof::kTheta);
      if (w >= 0) dm.emplace_back(w, w, m.mass_kg);
      if (theta >= 0) dm.emplace_back(theta, theta, m.inertia_kg_m2);
    }
    for (std::size_t i = 0; i < spec.springs.size(); ++i) {
      const SpringSpec& k = spec.springs[i];
      const int d = ResolveDof(spec, k.node, 0, k.dof, "spring." + std::to_string(i) + ".node");
      dk.emplace_back(d, d, k.stiffness);
      dc.emplace_back(d, d, k.damping);
    }
    auto add = [n](Eigen::SparseMatrix<double>* target, const std::vector<Eigen::Triplet<double>>& t) {
      if (t.empty()) return;
      Eigen::SparseMatrix<double> extra(n, n);
      extra.setFromTriplets(t.begin(), t.end());
      *target += extra;
      target->makeCompressed();
    };
    add(&model.mass_, dm);
    add(&model.stiffness_, dk);
    add(&model.damping_, dc);
    model.rigid_body_modes_ = BeamHasRigidBodyModes(spec);
  }
  const int n = model.dofs();
  std::vector<std::array<int, 2>> dofs;
  for (std::size_t i = 0; i < spec.nonlinearities.size(); ++i) {
    const NonlinearitySpec& s = spec.nonlinearities[i];
    const std::string key = "nonlinearity." + std::to_string(i);
    std::array<int, 2> d{-1, -1};
    d[0] = ResolveDof(spec, s.node, s.dof, SensorDof::kW, key + (s.dof > 0 ? ".dof" : ".node"));
    if (s.dof2 > 0 || s.node2 >= 0) {
      d[1] = ResolveDof(spec, s.node2, s.dof2, SensorDof::kW,
                        key + (s.dof2 > 0 ? ".dofs.1" : ".nodes.1"));
    }
    dofs.push_back(d);
  }
  model.nonlinear_ = NonlinearForces(spec.nonlinearities, dofs, n);
  return model;
}

}  // namespace podid
