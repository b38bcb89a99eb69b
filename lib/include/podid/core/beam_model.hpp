#pragma once
// The structural model: a finite-element Euler-Bernoulli beam (the paper's
// section 4, fig. 1; segments, end conditions, point masses, grounded springs)
// or imported matrices, with local nonlinear elements. Units are SI throughout.
//
// Element matrices (length l, bending stiffness EI, mass per length rho A;
// dofs w_i, theta_i, w_j, theta_j; Hermite cubic shape functions):
//   K_e = EI / l^3 [ 12  6l  -12  6l ; 6l 4l^2 -6l 2l^2 ; -12 -6l 12 -6l ; 6l 2l^2 -6l 4l^2 ]
//   M_e = rho A l / 420 [ 156 22l 54 -13l ; 22l 4l^2 13l -3l^2 ; 54 13l 156 -22l ;
//                         -13l -3l^2 -22l 4l^2 ]   (consistent mass)
// Each segment's elements use its own l, EI and rho A. The end conditions
// remove dofs: clamped (w and theta), pinned (w), free (none); the remaining
// dofs are ordered (w_0, theta_0, ..., w_N, theta_N), see BeamDof() in
// case_spec.hpp (node 0 clamped, the default: w_1 at 0, theta_1 at 1, ...).
// Point masses add m to M(w, w) and J to M(theta, theta); springs add k to K
// and c to C on their dof.
// Equation of motion (eq. 20): M x'' + C x' + K x = g(t) + f_nl(x, x').
// Damping: C = alpha M + beta K (Rayleigh, from the assembled M and K
// including masses and springs) + the springs' dashpots + an imported C.
// M, K and C are stored sparse (a beam's are banded; an imported model keeps
// its pattern), so a model of 10^4 dofs costs O(nnz) memory, not O(n^2).

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>
#include <string_view>
#include <vector>

#include "podid/core/case_spec.hpp"
#include "podid/core/nonlinear.hpp"

namespace podid {

/// Linear modal analysis: K phi = omega^2 M phi (generalised symmetric
/// eigenproblem), the lowest `modes` modes sorted by increasing frequency,
/// mass-normalised (phi^T M phi = 1), each shape's largest-|.| transverse
/// component positive.
struct ModalAnalysis {
  Eigen::VectorXd frequencies_Hz;   ///< (dim modes) undamped natural frequencies
  Eigen::VectorXd damping_ratios;   ///< (dim modes) phi^T C phi / (2 omega)
  Eigen::MatrixXd shapes;           ///< (n_dofs x modes), column k is mode k+1
};

/// Which eigensolver BeamModel::Modes uses.
enum class EigenSolverChoice {
  kAuto,    ///< dense up to kDenseModesLimit dofs or when all modes are asked, else kSparse
  kDense,   ///< Eigen's dense generalised solver: all n modes, O(n^3)
  kSparse,  ///< Spectra's shift-invert Lanczos with a sparse factor: the requested modes only
};

/// Largest model solved with the dense eigensolver by EigenSolverChoice::kAuto.
inline constexpr int kDenseModesLimit = 200;
/// Largest model the dense eigensolver takes (all modes, or the sparse
/// solver's fallback): 4096 dofs hold ~6 dense n x n matrices (0.8 GB) and
/// take about a minute on one core; 20000 dofs asked for 13 GB.
inline constexpr int kMaxDenseModesDofs = 4096;

/// The 0-based model dof a case refers to: `dof1` (1-based, > 0) for any model,
/// else the beam dof `which` of `node`. Throws std::invalid_argument naming
/// `key` when the dof is out of range, held by a support, or a node is used
/// with imported matrices.
int ResolveDof(const CaseSpec& spec, int node, int dof1, SensorDof which, std::string_view key);

/// The constant part of a simulation: matrices and elements. Built once,
/// never changed (the integrators keep their buffers in a separate workspace).
class BeamModel {
 public:
  /// Builds M, K, the nonlinear elements and C from the case (C after a modal
  /// analysis when damping is given as modal ratios): the beam with its masses
  /// and springs, or the imported matrices. Throws std::invalid_argument if
  /// the case is inconsistent (e.g. a node out of range, a matrix that is not
  /// symmetric or a mass matrix that is not positive definite).
  static BeamModel Build(const CaseSpec& spec);

  /// Assembles the beam's M and K only (segments and end conditions; no
  /// damping, no masses, springs or elements).
  static BeamModel BuildLinear(const BeamSpec& beam);

  /// Any linear system with local nonlinear elements: M (SPD), K and C
  /// (symmetric, n x n). Element `node` k acts on dof 2 (k - 1), as for a
  /// beam; for a single-dof oscillator use node 1. Throws
  /// std::invalid_argument for inconsistent sizes.
  static BeamModel FromMatrices(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& stiffness,
                                const Eigen::MatrixXd& damping,
                                const std::vector<NonlinearitySpec>& nonlinearities);
  /// Same with sparse matrices (kept sparse: for large models).
  static BeamModel FromMatrices(const Eigen::SparseMatrix<double>& mass,
                                const Eigen::SparseMatrix<double>& stiffness,
                                const Eigen::SparseMatrix<double>& damping,
                                const std::vector<NonlinearitySpec>& nonlinearities);

  int dofs() const { return static_cast<int>(mass_.rows()); }
  const Eigen::SparseMatrix<double>& mass() const { return mass_; }            ///< kg, kg m, kg m^2
  const Eigen::SparseMatrix<double>& stiffness() const { return stiffness_; }  ///< N/m, N, N m
  const Eigen::SparseMatrix<double>& damping() const { return damping_; }      ///< N s/m ...
  /// Dense copies for small models (tests, POD weighting): n x n.
  Eigen::MatrixXd DenseMass() const { return Eigen::MatrixXd(mass_); }
  Eigen::MatrixXd DenseStiffness() const { return Eigen::MatrixXd(stiffness_); }
  Eigen::MatrixXd DenseDamping() const { return Eigen::MatrixXd(damping_); }
  const NonlinearForces& nonlinear() const { return nonlinear_; }
  /// True when K leaves the structure free to move as a rigid body (a
  /// free-free or pinned-free beam without springs; an imported K with a
  /// zero pivot): there is then no static equilibrium under a force.
  bool has_rigid_body_modes() const { return rigid_body_modes_; }
  double rayleigh_alpha_per_s() const { return alpha_per_s_; }
  double rayleigh_beta_s() const { return beta_s_; }

  /// Modal analysis of the linear part (M, K, C): all n modes (dense solver).
  ModalAnalysis Modes() const;
  /// The lowest `count` modes (1..n). kAuto uses the sparse solver above
  /// kDenseModesLimit dofs when count < n, and the dense one when a sparse
  /// mode's residual in K phi = lambda M phi exceeds 1e-8 (relative). Throws
  /// std::invalid_argument when the modes cannot be computed (M and K too far
  /// apart in scale, the sparse solver does not converge or its modes are
  /// inaccurate), or the dense solver would take more than kMaxDenseModesDofs.
  ModalAnalysis Modes(int count, EigenSolverChoice solver = EigenSolverChoice::kAuto) const;

  /// The one change a built model takes: new coefficients of its nonlinear
  /// elements (NonlinearForces::SetCoefficients), which leave M, K and C as
  /// they are. For the owner of the model (Simulator, simulator.hpp).
  void SetNonlinearCoefficients(const std::vector<NonlinearitySpec>& specs) {
    nonlinear_.SetCoefficients(specs);
  }

 private:
  /// M, K, the springs' and imported damping (in damping_) and the transverse
  /// mask, before Rayleigh damping and the nonlinear elements (model_builder.cpp).
  static BeamModel BuildStructure(const CaseSpec& spec);
  /// The lowest `count` < n modes by shift-invert Lanczos (modal.cpp).
  void SparseModes(int count, Eigen::VectorXd* eigenvalues, Eigen::MatrixXd* shapes) const;

  Eigen::SparseMatrix<double> mass_, stiffness_, damping_;
  /// Dofs whose sign fixes a mode shape's sign (beam: the w dofs; else all).
  std::vector<int> transverse_;
  NonlinearForces nonlinear_;
  double alpha_per_s_ = 0.0, beta_s_ = 0.0;
  bool rigid_body_modes_ = false;
};

/// Rayleigh coefficients giving damping ratios zeta_1, zeta_2 at circular
/// frequencies omega_1 != omega_2 (rad/s): zeta_i = alpha / (2 omega_i) + beta omega_i / 2.
void RayleighFromModalRatios(double omega1_rad_per_s, double zeta1, double omega2_rad_per_s,
                             double zeta2, double* alpha_per_s, double* beta_s);

struct StaticSolveOptions {
  /// Converged when ||r|| <= tolerance ||F||, or, once Newton stops making
  /// progress, when ||r||_inf <= tolerance (||K||_inf ||x||_inf + ||f_nl||_inf
  /// + ||F||_inf) (a backward error: the round-off floor of a fine mesh).
  double tolerance = 1e-12;
  int max_iterations = 100;
};

/// Largest estimated relative error (StaticSolveSummary::relative_error_estimate)
/// of a usable static deflection. The worst uniform beam a case file allows
/// (a 1000-element cantilever) estimates 2.1e-6, its measured error; the bound
/// leaves 50x for orderings and compilers and refuses the meshes measured to
/// lose 4.5e-4 and more (a pinned-pinned beam loaded at 0.99 m, its last
/// 0.01 m in 998 elements: element lengths 50000x apart).
inline constexpr double kMaxStaticRelativeError = 1e-4;

struct StaticSolveSummary {
  /// The residual test passed and relative_error_estimate <= kMaxStaticRelativeError.
  bool converged = false;
  int iterations = 0;
  double relative_residual = 0.0;  ///< ||K x - f_nl(x, 0) - F|| / ||F||
  /// ||J^-1 r||_inf / ||x||_inf at the solution (J the tangent stiffness): an
  /// estimate of x's relative error (one step of iterative refinement).
  double relative_error_estimate = 0.0;
  std::string message;
};

/// Static equilibrium K x - f_nl(x, 0) = F (dim n_dofs), by Newton with
/// backtracking (the step is halved until the residual decreases). x starts
/// from the linear solution. K is factorised once (sparse LDL^T); each Newton
/// step condenses the nonlinear dofs' tangent onto an n_a x n_a system. Throws std::invalid_argument when K is not
/// positive definite (a model free to move as a rigid body).
Eigen::VectorXd SolveStatic(const BeamModel& model, const Eigen::VectorXd& force,
                            const StaticSolveOptions& options, StaticSolveSummary* summary);

}  // namespace podid
