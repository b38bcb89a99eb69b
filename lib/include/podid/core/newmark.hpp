#pragma once
// Newmark time integration of M x'' + C x' + K x = g(t) + f_nl(x, x') (eq. 20).
//
// Newmark relations (gamma, beta; average acceleration 1/2, 1/4 by default):
//   x'' _{n+1} = a0 (x_{n+1} - x_n) - a2 x'_n - a3 x''_n,   a0 = 1/(beta dt^2),
//                a2 = 1/(beta dt), a3 = 1/(2 beta) - 1
//   x' _{n+1} = x'_n + dt ((1 - gamma) x''_n + gamma x''_{n+1})
// which turn the equation at t_{n+1} into S x_{n+1} = b_n + g_{n+1} + f_nl (eq. 23)
// with the constant S = a0 M + a1 C + K, a1 = gamma / (beta dt).
//
// Two integrators solve it:
//  * kNewmark: Newton-Raphson on all n dofs, the jacobian (eq. 25) refactored at
//    every iteration. The reference implementation.
//  * kModifiedNewmark (default): the paper's section 4.1 (Zheng & Hasebe 1999).
//    Dofs are split into nonlinear `a` and linear `b` (eq. 21); the projection
//    S_ab S_b^-1 S_ba is computed once for the step; Newton iterates on the
//    condensed equation (eq. 29) on the `a` dofs only, and x_b follows from
//    eq. 28. Both solve the same equations, so they agree to the Newton tolerance.
//    Up to kDenseDofLimit dofs the condensation is dense (S_b^-1 precomputed,
//    one n x 3n product per step: fastest for small models). Above it, M, C
//    and S_bb are sparse and S_bb is factorised once (SimplicialLDLT in
//    METIS's nested-dissection order, listed level by level so that the
//    triangular solves' rows overlap: sparse_status()): no dense n x n matrix
//    is formed, set-up and a step cost O(nnz(M) + nnz(C) + nnz(L)), linear in
//    n for banded models.
//  The full-Newton reference integrator is dense (n x n jacobian) at any size.
//  On the dense condensed path, when the undamped modes also diagonalise C
//  (proportional damping: Rayleigh, or none), the linear part is integrated
//  in modal coordinates instead (NewmarkOptions::modal, lib/src/newmark_modal.hpp):
//  each mode a scalar recurrence, the nonlinear dofs through their rows of the
//  mode shapes: the same equations, O(n n_a) per step plus the recorded dofs.
//  It is the faster step only in its AVX2 loop (one nonlinear dof), so by
//  default it runs only there.
//
// Model/workspace split: a NewmarkIntegrator holds constant precomputed
// matrices; a NewmarkWorkspace holds every buffer the time loop uses, so Run()
// allocates nothing inside the loop and is const (thread-safe with one
// workspace per thread). Units are SI.

#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "podid/core/beam_model.hpp"
#include "podid/core/case_spec.hpp"

namespace podid {

/// Largest number of dofs integrated with dense matrices (above: sparse).
inline constexpr int kDenseDofLimit = 64;

struct NewmarkOptions {
  IntegratorType type = IntegratorType::kModifiedNewmark;
  double gamma = 0.5;        ///< in [0.5, 1]
  double beta = 0.25;        ///< in (0, 0.5]; unconditionally stable when beta >= gamma / 2
  double step_s = 0.0;       ///< > 0, constant
  int steps = 0;             ///< >= 1; samples = steps + 1
  double tolerance = 1e-10;  ///< Newton: ||r||_inf <= tolerance * (force scale of the step)
  int max_iterations = 50;   ///< Newton iterations per step
  /// A step whose largest |x| (m or rad) exceeds this ends the run as
  /// kDiverged: an unstable system (negative stiffness) can grow without ever
  /// overflowing, since the implicit scheme damps the runaway. 1e3 is far
  /// beyond any structure podid models. > 0.
  double max_displacement = 1e3;
  /// Largest number of dofs the modified method integrates with dense
  /// matrices; above it the sparse path (tests compare the two). >= 0.
  int dense_dof_limit = kDenseDofLimit;
  /// The dense condensed step's product (AVX2 + FMA) and update (AVX2) use the CPU's SIMD
  /// when it has them (run-time check; the build targets baseline x86-64). false forces the
  /// portable kernels (tests compare: products round-off apart, updates bit for bit).
  bool cpu_dispatch = true;
  /// The dense condensed path steps in modal coordinates when the undamped
  /// modes diagonalise M, C and K to internal::kModalCouplingTolerance and
  /// the modal loop runs in AVX2 (one nonlinear dof, cpu_dispatch and a CPU
  /// with AVX2; NewmarkIntegrator::modal() and modal_status() say which and
  /// why). Its portable loops are slower than the dense step (120 against
  /// 106 ns a step of the reference case, docs/benchmarks.md), so the dense
  /// condensation runs elsewhere. false keeps the dense condensation
  /// (tests compare the two). No effect on full Newton or the sparse path,
  /// nor on a one-dof model, which steps in its own loop (one_dof()).
  bool modal = true;
  /// With `modal`: take the modal path with its portable loop too, where the
  /// dense step is faster (the tests hold that loop to the AVX2 one and to
  /// the references), and on a one-dof model instead of its own loop (with
  /// `modal` false there: the generic dense step).
  bool modal_portable = false;
  /// Run() records every record_stride-th step (sub-stepping: step_s is the
  /// sampling step / record_stride): rows 0..steps / record_stride. >= 1 and
  /// divides steps.
  int record_stride = 1;
  bool IsValid(std::string* why) const;
  /// From the case's [time] and [integrator] tables: step_s = time.step /
  /// substeps, steps = (samples - 1) substeps, record_stride = substeps.
  /// Throws std::invalid_argument when substeps < 1 or the fine steps exceed an int.
  static NewmarkOptions FromCase(const CaseSpec& spec);
};

struct State {
  Eigen::VectorXd displacement;  ///< (dim n_dofs) m, rad
  Eigen::VectorXd velocity;      ///< (dim n_dofs) m/s, rad/s
};

/// External load g(t_n) = sum_k pattern.col(k) history(k, n) at t_n = n dt,
/// dt the integration step (the fine grid when sub-stepping), n = 0..steps.
/// A point force on dof d is a column e_d with its force (N) as history; base
/// excitation is the column -M r with a_g (m/s^2) as history (load.hpp).
/// No columns means no external load.
struct ExternalLoad {
  Eigen::SparseMatrix<double> pattern;  ///< n_dofs x K (N per unit of the history)
  Eigen::MatrixXd history;              ///< K x (steps + 1)
  /// Base excitation: the row of `history` holding a_g (m/s^2), or -1; and r
  /// (dim n_dofs), the dofs' motion per unit base motion (absolute sensors).
  int base_row = -1;
  Eigen::VectorXd base_influence;

  int columns() const { return static_cast<int>(pattern.cols()); }
  /// A single point force on `dof` (0-based) of an n_dofs model.
  static ExternalLoad PointForce(int n_dofs, int dof, const Eigen::VectorXd& values_N);
};

enum class SimulationTermination {
  kNotRun,            ///< nothing computed
  kCompleted,         ///< all steps done
  kStaticSolveFailed, ///< the initial static deflection did not converge
  kNewtonFailed,      ///< a step's Newton iterations did not converge; history kept up to it
  kNonFinite,         ///< the state became NaN/Inf; history kept up to the step before
  kDiverged,          ///< |x| exceeded NewmarkOptions::max_displacement; history kept up to the step before
};

/// Largest NewmarkIntegrator::step_error_estimate() `podid simulate` passes
/// without a warning: the static solve's bound (kMaxStaticRelativeError), for
/// one solve. Not a failure: the estimate is a bound over every dof, and the
/// sensors' error can be far smaller (docs/case-file.md).
inline constexpr double kMaxStepRelativeError = 1e-4;

const char* ToString(SimulationTermination termination);

struct SimulationSummary {
  SimulationTermination termination = SimulationTermination::kNotRun;
  std::string message = "Simulation was not run.";
  IntegratorType integrator = IntegratorType::kModifiedNewmark;
  int dofs = 0;
  int nonlinear_dofs = 0;
  int steps_requested = 0;
  int steps_completed = 0;
  int rows_recorded = 0;            ///< valid rows of the Recording (steps_completed / stride + 1)
  long long newton_iterations = 0;  ///< total Newton corrections
  int max_step_iterations = 0;      ///< worst step
  double worst_step_time_s = 0.0;   ///< time of the worst step
  double failure_time_s = std::numeric_limits<double>::quiet_NaN();
  double failure_residual = std::numeric_limits<double>::quiet_NaN();  ///< relative
  /// NewmarkIntegrator::step_error_estimate() of the run's integrator.
  double step_error_estimate = std::numeric_limits<double>::quiet_NaN();
  double wall_time_s = 0.0;

  bool IsSolutionUsable() const { return termination == SimulationTermination::kCompleted; }
  std::string BriefReport() const;  ///< one line
  std::string FullReport() const;  ///< several lines
};

/// What Run() records at each sample (rows 0..steps / record_stride; row r is
/// t = r record_stride dt).
struct Recording {
  std::vector<int> dofs;        ///< free-dof indices to record
  bool record_velocity = false;
  bool record_acceleration = false;
  Eigen::MatrixXd displacement;  ///< (steps / record_stride + 1) x dofs.size(), sized by Run()
  Eigen::MatrixXd velocity;      ///< same, when record_velocity
  Eigen::MatrixXd acceleration;  ///< same, when record_acceleration (m/s^2, rad/s^2)
};

class NewmarkIntegrator;

namespace internal {
struct ModalStep;
struct SparseStep;
struct ModalRunner;
struct OneDofRunner;
/// The Newmark relations' coefficients (above) and the divergence bound, as
/// the dense condensed path's update kernel takes them (newmark_kernels.hpp).
struct NewmarkCoefficients {
  double a0 = 0, a1 = 0, a2 = 0, a3 = 0, a4 = 0, a5 = 0;
  double step_s = 0, gamma = 0;
  double max_displacement = 0;  ///< NewmarkOptions::max_displacement
};
}  // namespace internal

/// Every buffer the time loop needs, allocated once for an integrator.
class NewmarkWorkspace {
 public:
  explicit NewmarkWorkspace(const NewmarkIntegrator& integrator);

 private:
  friend class NewmarkIntegrator;
  friend struct internal::ModalRunner;
  friend struct internal::OneDofRunner;
  Eigen::VectorXd z;  ///< state (dim 3 n): x, x', x'' in the permuted order
  Eigen::VectorXd x_new, rhs, r, dx;
  Eigen::VectorXd xa, xa_n, va, fa, ra, dxa, xa_trial;
  // The load (set by Run() before the loop): the permuted pattern, how its
  // columns enter [bhat; y] on the dense condensed path, and this step's
  // history values (dim K).
  Eigen::SparseMatrix<double> load_pattern;
  Eigen::MatrixXd load_y, load_bhat;  ///< n_b x K, n_a x K
  Eigen::VectorXd load_now;
  Eigen::VectorXd u;       ///< condensed paths: [u1; u2], the operands of M and C (dim 2 n)
  Eigen::MatrixXd ka, ca;  ///< tangents of the nonlinear forces (n_a x n_a)
  Eigen::MatrixXd jac, jac_a;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu, lu_a;
  // Modal path (dim n_pad, newmark_modal.hpp): the modes' q, q', q'' (3 n_pad),
  // the step's predicted increment d, the next one's part P known before the
  // Newton iterations, the load's share of the next d; per Run(): the
  // recorded dofs' rows of phi (padded to 4, column-major) and the load's
  // modal images.
  Eigen::VectorXd modal_state, modal_d, modal_p, modal_load_next, modal_out;
  Eigen::VectorXd modal_pa_lanes;         ///< dim 4 n_a: P's image on the `a` dofs, per lane
  Eigen::VectorXd da, pa, delta, load_a;  ///< dim n_a: images on the `a` dofs
  Eigen::MatrixXd modal_sensors, modal_load, modal_load_a;
};

class NewmarkIntegrator {
 public:
  /// Precomputes S and, for the modified method, the condensation. Throws
  /// std::invalid_argument if !options.IsValid().
  NewmarkIntegrator(const BeamModel& model, const NewmarkOptions& options);

  const NewmarkOptions& options() const { return options_; }
  int dofs() const { return n_; }
  /// True when the condensed steps use sparse matrices (dofs() > options().dense_dof_limit).
  bool sparse() const { return sparse_; }
  /// True when the steps are taken in modal coordinates (NewmarkOptions::modal);
  /// modal_status() says why or why not.
  bool modal() const { return modal_ != nullptr; }
  const std::string& modal_status() const { return modal_status_; }
  /// True when a one-dof model (every dof nonlinear) steps in its own scalar
  /// loop on the dense condensed path (lib/src/newmark_one_dof.hpp): the
  /// default there unless NewmarkOptions::modal_portable asks for the modal one.
  bool one_dof() const { return one_dof_; }
  /// The sparse path's ordering of S_bb's factor: method, elimination tree
  /// height (the triangular solves' dependency chain) and nonzeros; empty on
  /// the dense path.
  const std::string& sparse_status() const { return sparse_status_; }
  int nonlinear_dofs() const { return na_; }
  /// The relative error of one solve with the step matrix S = M / (beta dt^2)
  /// + gamma C / (beta dt) + K (eq. 23), measured once when the integrator is
  /// built on two probes of known answer (lib/src/step_conditioning.hpp): on
  /// the sparse path with its own factor of S_bb (the linear dofs' block),
  /// else with a sparse factor of S made for it. Round-off sets it (4e-15 for the
  /// reference case, 1e-8 for 1000 uniform elements); lengths or stiffnesses
  /// many orders apart raise it (2.4e-2 for a pinned beam with elements
  /// 49,500x apart, whose transient is then 1e-2 off). Measured over every
  /// dof, rotations included, it can exceed the sensors' error by far, so it
  /// is reported (SimulationSummary), not enforced. NaN if S has no LDL^T
  /// factor.
  double step_error_estimate() const { return step_error_estimate_; }
  /// New coefficients of the nonlinear elements (NonlinearForces::
  /// SetCoefficients): no matrix depends on them, nothing is refactored.
  void SetNonlinearCoefficients(const std::vector<NonlinearitySpec>& specs) {
    nonlinear_.SetCoefficients(specs);
  }

  /// Integrates from `initial` (dim n_dofs each) over options().steps steps.
  /// On failure the recording keeps the samples up to the last good step
  /// (summary.rows_recorded = steps_completed / record_stride + 1 rows are valid). No allocation in
  /// the loop.
  SimulationSummary Run(const State& initial, const ExternalLoad& load, Recording* recording,
                        NewmarkWorkspace* workspace) const;
  /// Same, with a workspace of its own.
  SimulationSummary Run(const State& initial, const ExternalLoad& load, Recording* recording) const;

 private:
  friend class NewmarkWorkspace;
  friend struct internal::ModalRunner;
  friend struct internal::OneDofRunner;
  bool StepModified(NewmarkWorkspace& w, bool has_load, int* iterations, double* residual) const;
  /// rhs += the load's pattern times w.load_now (allocation-free; newmark_load.cpp).
  static void AddLoad(NewmarkWorkspace& w, Eigen::VectorXd& rhs);
  /// Before the loop: the load in w (permuted pattern, its dense condensed
  /// images load_y and load_bhat, load_now at t = 0).
  void PrepareLoad(const ExternalLoad& load, NewmarkWorkspace& w) const;
  bool SolveScalar(NewmarkWorkspace& w, int* iterations, double* residual) const;
  /// eq. 29 on n_a >= 2 dofs by Newton from x_a = the `a` entries of w.z, bhat in w.ra.
  bool SolveCondensed(NewmarkWorkspace& w, const Eigen::MatrixXd& shat, int* iterations,
                      double* residual) const;
  /// The dense condensed step with one nonlinear dof, product, Newton (eq. 29),
  /// eq. 28 and the Newmark update fused; *bounded = false (state untouched)
  /// when x_new exceeds max_displacement or is not finite.
  bool StepDenseScalar(NewmarkWorkspace& w, bool has_load, int* iterations, double* residual,
                       bool* bounded) const;
  bool StepFull(NewmarkWorkspace& w, bool has_load, int* iterations, double* residual) const;
  void NonlinearVelocity(NewmarkWorkspace& w) const;

  NewmarkOptions options_;
  int n_ = 0, na_ = 0, nb_ = 0;
  double a0_ = 0, a1_ = 0, a2_ = 0, a3_ = 0;
  double a4_ = 0, a5_ = 0;  ///< C's coefficients of x' and x'' in rhs: g/b - 1, dt (g/(2b) - 1)
  // All matrices are in the permuted order (a dofs first, then b dofs).
  std::vector<int> perm_;      ///< perm_[k] = original dof of permuted index k
  std::vector<int> inv_perm_;  ///< inverse of perm_
  Eigen::MatrixXd mass_, damping_, stiffness_, s_;
  double s_norm_ = 0.0;  ///< ||S||_inf, for the round-off floor of full Newton
  double step_error_estimate_ = 0.0;
  /// rhs = A [x; x'; x''] (n x 3n): the known part of S x_{n+1} = rhs + g + f_nl.
  Eigen::MatrixXd rhs_matrix_;
  // Condensation (modified method): S_b^-1, S_ab, H = S_b^-1 S_ba,
  // Shat = S_a - S_ab S_b^-1 S_ba, and the state-to-(y, bhat) maps
  // y = S_b^-1 rhs_b and bhat = rhs_a - S_ab y. With T = [I, -S_ab S_b^-1; 0, S_b^-1]
  // and rhs = M u1 + C u2 (u1 = a0 x + a2 x' + a3 x'', u2 = a1 x + a4 x' + a5 x''),
  // [bhat; y] = T rhs = condensed_mc_ [u1; u2] with condensed_mc_ = T [M, C]
  // (n x 2n, column-major): one product of 2 n^2 multiply-adds per step.
  Eigen::MatrixXd sbb_inv_, sab_, h_, shat_, condensed_mc_;
  /// out = A u for condensed_mc_ (column-major rows x cols): SSE2 or AVX2 + FMA kernel.
  void (*multiply_small_)(const double* a, int rows, int cols, const double* u, double* out) = nullptr;
  /// The Newmark update of the condensed paths, dense and sparse (newmark_kernels.hpp):
  /// portable or AVX2, the same bits.
  bool (*update_)(const internal::NewmarkCoefficients& c, int n, const double* y, const double* h,
                  double x_a, double* x_new, double* z, double* u) = nullptr;
  internal::NewmarkCoefficients coefficients_;
  /// One nonlinear dof: H's column with a 0 for the `a` dof (dim n), so that
  /// x_new = y - h x_a holds for every dof once y[0] = x_a.
  Eigen::VectorXd h_padded_;
  double shat_scalar_ = 0.0;      ///< Shat (1 x 1)
  double v0_velocity_ = 0.0;      ///< 1 - g/b: x'_n's coefficient in the implied velocity
  double v0_acceleration_ = 0.0;  ///< dt (1 - g/(2b)): x''_n's coefficient
  Eigen::MatrixXd mass_inverse_;  ///< dense path only
  // Sparse path (modified method, n > kDenseDofLimit).
  bool sparse_ = false;
  // Permuted M, C, K (always; the dense copies above exist only on the dense path).
  Eigen::SparseMatrix<double> mass_sparse_, damping_sparse_, stiffness_sparse_;
  /// S_ab (n_a x n_b) by rows: a product over its nonzeros, not over n_b columns.
  Eigen::SparseMatrix<double, Eigen::RowMajor> sab_sparse_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> mass_ldlt_;
  /// [M, C] u and y = S_bb^-1 rhs_b by rows (sparse_step.hpp); the `b` dofs
  /// are in the order of S_bb's factor (sparse_ordering.hpp).
  std::shared_ptr<const internal::SparseStep> sparse_step_;
  std::string sparse_status_;
  NonlinearForces nonlinear_;  ///< with `local` indices = permuted indices
  /// The modal path (dense condensed, proportional damping), or null.
  std::shared_ptr<const internal::ModalStep> modal_;
  std::string modal_status_;
  bool one_dof_ = false;  ///< the one-dof loop (one_dof())
};

}  // namespace podid
