#pragma once
// The modal form of the dense condensed step (not installed; newmark.hpp).
//
// When the undamped modes Phi (K Phi = M Phi Lambda) diagonalise C as well as
// M and K (proportional damping: Rayleigh C = alpha M + beta K, or none),
// Newmark's linear step commutes with x = Phi q: mode i is the scalar
// recurrence s_i q_{n+1} = m_i u1_i + c_i u2_i + phi_i^T (g + f_nl), with
// s_i = a0 m_i + a1 c_i + k_i and u1, u2 as on the dense path. It is taken in
// increments, s_i (q_{n+1} - q_n) = m_i (a2 q' + a3 q'') + c_i (a4 q' + a5 q'')
// - k_i q_n + phi_i^T (g + f_nl): k_i q_n is not the small difference of
// a0 m_i q_n terms that the dense path's S x cancels, so a low mode's
// frequency carries no rounding of a0 m_i (the dense path's: 2e-13 relative
// for the reference beam's first mode, a phase drift of 6e-11 after 1 s).
// With d the modes' increment without f_nl and da = Phi_a d (Phi_a: the `a`
// dofs' rows), x_a = x_a,n + da + F f_a, F = Phi_a diag(1/s) Phi_a^T, so
// eq. 29 is Shat x_a - bhat - f_a = 0 with Shat = F^-1 (the dense path's
// Schur complement: the same equation) and bhat = Shat (x_a,n + da), and
// eq. 28 becomes
//   q_{n+1} = q_n + d + E delta,   delta = x_a - x_a,n - da,   E = diag(1/s) Phi_a^T Shat.
// A step costs O(n n_a) plus the recorded dofs' rows of Phi, instead of the
// dense path's n x 2n product. Units are SI.

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "podid/core/newmark.hpp"

namespace podid::internal {

/// Largest coupling the modal step neglects: for modes i != j, the largest
/// of a0 |m_ij|, a1 |c_ij|, |k_ij| (Phi^T M Phi, Phi^T C Phi, Phi^T K Phi)
/// over sqrt(s_i s_j), a relative perturbation of the step's matrix. Rayleigh
/// damping leaves round-off, 2.7e-15 on the reference beam (measured:
/// tests/core/newmark_modal_test.cpp); the least non-proportional damping of
/// interest (a dashpot on one dof) is above 1e-6. 1e-13 keeps the modal
/// response within 1e-12 of the dense one.
inline constexpr double kModalCouplingTolerance = 1e-13;

/// Everything the modal step needs, built once; per-mode arrays are padded
/// to n_pad (a multiple of 4) with zeros, so the padded modes stay at rest.
struct ModalStep {
  int n = 0, n_pad = 0, na = 0;
  double coupling = 0.0;      ///< the largest coupling neglected (above)
  Eigen::MatrixXd phi;        ///< n x n: x = phi q, rows in the permuted dof order
  Eigen::MatrixXd to_modal;   ///< n x n: q = diag(1/m) phi^T M x
  Eigen::MatrixXd force_map;  ///< n_pad x n: a force's share of d, diag(1/s) phi^T
  /// d = beta q' + gamma q'' - kappa q (+ the load's share): the increment's
  /// known part over s (kappa = k / s).
  Eigen::VectorXd beta, gamma, kappa;
  /// The next step's d' = P + Q delta with
  /// P = next_d d + next_x q_{n+1} + next_v q'_{n+1} + next_a q''_{n+1},
  /// known before the Newton iterations (the .cpp derives it).
  Eigen::VectorXd next_d, next_x, next_v, next_a;
  Eigen::VectorXd bound;   ///< max_j |phi_ji|: max_j |x_j| <= sum_i bound_i |q_i|
  Eigen::MatrixXd e;       ///< n_pad x na: E
  Eigen::MatrixXd q_gain;  ///< n_pad x na: Q = diag(next_d) E
  Eigen::MatrixXd phi_a;   ///< n_pad x na: Phi_a^T
  Eigen::MatrixXd qa;      ///< na x na: Phi_a Q
  Eigen::MatrixXd shat;    ///< na x na: F^-1
};

/// The modal step for the dense M, C, K in the permuted order (the na `a`
/// dofs first) and the step's coefficients, or nullptr with the reason in
/// *why when it does not apply: the generalised eigenproblem fails, a mode's
/// s_i is not positive, or the modes couple by more than
/// kModalCouplingTolerance (non-proportional damping).
std::shared_ptr<const ModalStep> BuildModalStep(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& damping,
                                                const Eigen::MatrixXd& stiffness, int na,
                                                const NewmarkCoefficients& c, std::string* why);

/// Whether the modal loop for na nonlinear dofs runs in its AVX2 build (one
/// nonlinear dof, cpu_dispatch and a CPU with AVX2): the only build faster
/// than the dense step, so the integrator takes the modal path only then
/// (unless NewmarkOptions::modal_portable). Otherwise *why says which is
/// missing.
bool ModalLoopVectorised(int na, bool cpu_dispatch, std::string* why);

/// The modal path's time loop, a friend of the integrator and its workspace.
struct ModalRunner {
  /// Before the loop (may allocate): the modal state from w.z (the physical
  /// x, x', x'' at t = 0, permuted), the recorded dofs' rows of phi, the
  /// load's modal images and the first step's predicted increment.
  static void Prepare(const NewmarkIntegrator& integrator, const ExternalLoad& load,
                      const std::vector<int>& recorded, NewmarkWorkspace& w);
  /// The steps (allocation-free), as Run()'s dense loop: the summary's
  /// counters, termination and rows_recorded; the recording's rows 1...
  static void Run(const NewmarkIntegrator& integrator, const ExternalLoad& load,
                  const std::vector<int>& recorded, int rows, Recording* recording, NewmarkWorkspace& w,
                  SimulationSummary* summary);
  /// The loop for kNa nonlinear dofs (0: any number); kVector: the pass over
  /// the modes in 4-wide vectors (the AVX2 build; the portable build keeps
  /// scalar lanes, faster in SSE2), the same operations and bits.
  template <int kNa, bool kVector>
  static void Steps(const NewmarkIntegrator& integrator, const ExternalLoad& load, int n_recorded, int rows, Recording* recording, NewmarkWorkspace& w,
                    SimulationSummary* summary);
};

}  // namespace podid::internal
