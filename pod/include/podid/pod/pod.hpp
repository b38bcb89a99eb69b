#pragma once
// Proper orthogonal decomposition (POD) of a snapshot matrix, after
// Lenaerts, Kerschen & Golinval, sections 2.1-2.3 (equation numbers below are
// the paper's). The module knows nothing of beams: X is any (M x N) matrix of
// M sensors (rows) by N samples (columns), eq. 17, in the data's own units.
//
// Definitions (Y is the centred, optionally weighted data, see PodOptions):
//   Y = L^T (X - mean 1^T),  W = L L^T (Cholesky), L = I without weighting;
//   Y = Psi Sigma V^T                         (eq. 18, thin SVD);
//   POMs      U = L^{-T} Psi (M x k)          unit columns: U^T W U = I;
//   sigma_k   singular values, descending     (data units * sqrt(samples));
//   lambda_k  = sigma_k^2 / N                 proper orthogonal values, the
//             eigenvalues of C = Y Y^T / N    (eqs. 7-8) (data units^2);
//   V         right-singular vectors (N x k), unit columns, the "time modes";
//   X ~= mean 1^T + U Sigma V^T               (eq. 6, exact with all modes).
//
// Methods (all give the same result up to rounding):
//   kDirect   eigenvectors of the M x M matrix Y Y^T (eqs. 7-8), V = Y^T Psi / sigma;
//   kSnapshot eigenvectors A_k of the N x N matrix C* = Y^T Y (eqs. 13-16),
//             Psi_k = Y A_k / sigma_k, V = A;
//   kSvd      thin SVD of Y with Eigen's BDCSVD (Jacobi inside below 16 columns);
//   kAuto     the fastest for the shape (see docs/pod.md, "The auto rule"):
//             kDirect when M <= N, kSnapshot when M > N, and kSvd when a kept
//             mode is too small for the Gram methods' accuracy
//             (lambda_k < kAutoGramRatio * lambda_1, lambda_k above the rank floor)
//             or the Gram matrix would exceed kMaxGramDimension on a side.
//
// Rank and zero modes (section 2.2): modes beyond the numerical rank have
// sigma = lambda = 0 and zero U and V columns (the "additional eigenmodes will
// be zero" of the paper), never NaN. Their null-space basis is arbitrary, so a
// zero column is also the only answer on which all methods agree. The rank
// floor is sigma_k <= max(M, N) eps sigma_1 for kSvd and
// lambda_k <= max(M, N) eps lambda_1 for the Gram methods (kDirect,
// kSnapshot), which resolve singular values down to about sqrt(eps) sigma_1.
//
// Sign convention (deterministic): in each nonzero POM, the first component
// whose magnitude is within a relative 1e-8 of the largest magnitude is
// positive; U and V columns are flipped together so U Sigma V^T is unchanged.
//
// Invalid input (empty matrix, NaN/Inf, weighting of the wrong size or not
// symmetric positive definite, more modes than min(M, N)) throws
// std::invalid_argument "<where>: expected X, got Y".

#include <Eigen/Core>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "podid/core/time_series.hpp"

namespace podid {

enum class PodMethod { kAuto, kSvd, kDirect, kSnapshot };

/// "auto", "svd", "direct", "snapshot".
const char* ToString(PodMethod method);
/// Inverse of ToString; throws std::invalid_argument naming the choices.
PodMethod ParsePodMethod(std::string_view name);

/// kAuto leaves the Gram methods for kSvd when a kept nonzero mode has
/// lambda_k / lambda_1 below this (sigma_k / sigma_1 < 1e-4): there the Gram
/// methods' relative error on sigma_k, about eps (sigma_1 / sigma_k)^2, would
/// exceed 1e-8.
inline constexpr double kAutoGramRatio = 1e-8;

/// The Gram methods, when chosen, refuse a Gram matrix larger than this on a
/// side (kSnapshot: N, kDirect: M; kAuto then takes kSvd): 16384^2 doubles are 2 GiB.
inline constexpr Eigen::Index kMaxGramDimension = 16384;

struct PodOptions {
  PodMethod method = PodMethod::kAuto;
  /// Subtract each sensor's time mean first (eq. 1: u = U + v).
  bool remove_mean = true;
  /// Optional symmetric positive definite (M x M) weighting W; empty = none.
  /// With W = the mass matrix and free vibration, the POMs estimate the
  /// normal modes (Feeny 1998): U then holds eigenvectors of C W, W-normalised.
  Eigen::MatrixXd weighting;
  /// Truncation; the result keeps the fewest modes allowed by all three.
  /// At most this many modes; 0 = all min(M, N).
  int max_modes = 0;
  /// The fewest modes whose cumulative energy reaches this fraction, in (0, 1];
  /// 1 keeps all. Ignored when the data hold no energy.
  double energy_fraction = 1.0;
  /// > 0: drop modes with sigma_k <= sigma_threshold (section 2.3, noise
  /// filtering); 0 drops none (zero modes are kept); finite, >= 0. In sigma's
  /// units (data units * sqrt(samples)); see NoiseSigmaThreshold().
  double sigma_threshold = 0.0;
  /// Compute V (N x k). Without it V is empty and Reconstruct() is unavailable;
  /// the Gram methods then skip an (N x M x k) product.
  bool compute_time_modes = true;
  /// kAuto: the number of leading modes that must be accurate to the SVD's
  /// precision (the Gram methods are abandoned for kSvd when one of them has
  /// lambda_k < kAutoGramRatio * lambda_1); 0 = every kept mode. The modes
  /// after them then carry the Gram methods' accuracy, about sqrt(eps)
  /// sigma_1 absolute (e.g. the trailing modes an objective keeps only to
  /// match swapped modes by MAC). >= 0.
  int accurate_modes = 0;

  /// True when every field is in range; otherwise `why` (if not null) says which.
  bool IsValid(std::string* why) const;
};

/// The largest singular value expected from pure noise of standard deviation
/// `noise_std` (data units) in an (M x N) matrix: noise_std (sqrt(M) + sqrt(N))
/// (Marchenko-Pastur edge). A PodOptions::sigma_threshold for unweighted data.
double NoiseSigmaThreshold(double noise_std, Eigen::Index sensors, Eigen::Index samples);

struct PodResult {
  PodMethod method = PodMethod::kAuto;       ///< the method that ran (never kAuto after a run)
  Eigen::Index sensors = 0;                  ///< M
  Eigen::Index samples = 0;                  ///< N
  Eigen::MatrixXd poms;                      ///< U (M x k), unit columns (U^T W U = I)
  Eigen::VectorXd singular_values;           ///< sigma (dim k), descending, >= 0
  Eigen::VectorXd proper_orthogonal_values;  ///< lambda = sigma^2 / N (dim k), eqs. 8, 16
  Eigen::MatrixXd time_modes;                ///< V (N x k), unit columns; empty if not computed
  Eigen::VectorXd energy_fraction;           ///< lambda_k / sum of all lambda (dim k), in [0, 1]
  Eigen::VectorXd cumulative_energy;         ///< running sum of energy_fraction (dim k)
  Eigen::VectorXd mean;                      ///< removed mean (dim M); zeros without remove_mean
  double total_energy = 0.0;                 ///< sum of all min(M, N) lambda = ||Y||_F^2 / N
  int numerical_rank = 0;                    ///< nonzero modes of Y among all min(M, N)
  /// Empty, or why the data are degenerate (numerical_rank == 0: every value
  /// equal to its sensor's mean, or deviations so small, below ~1e-154, that
  /// their squares underflow). No mode of degenerate data carries information.
  std::string message;

  bool IsDegenerate() const { return numerical_rank == 0; }

  Eigen::Index modes() const { return poms.cols(); }
};

/// A reusable POD: validates the options and factors the weighting once, keeps
/// every buffer between calls. For a fixed shape, repeated Compute() calls with
/// kDirect or kSnapshot allocate nothing after the first (kSvd allocates inside
/// Eigen, and so does a Gram method whose matrix is solved on its range: from
/// 256 on a side, with min(M, N) + 10 at most a quarter of it, as snapshot on a
/// long record). This is the object to keep across an optimiser's evaluations.
class PodSolver {
 public:
  /// Throws std::invalid_argument for invalid options or a weighting that is
  /// not symmetric positive definite.
  explicit PodSolver(PodOptions options = {});
  ~PodSolver();
  PodSolver(PodSolver&&) noexcept;
  PodSolver& operator=(PodSolver&&) noexcept;

  /// POD of the snapshot matrix x (M x N), eq. 17. The reference stays valid
  /// until the next Compute() on this solver.
  const PodResult& Compute(const Eigen::Ref<const Eigen::MatrixXd>& x);
  /// POD of a time series: X = series.values^T (channels x samples), no copy.
  const PodResult& Compute(const TimeSeries& series);
  /// POD of X = values^T for `values` in TimeSeries::values' layout (N
  /// samples x M sensors, any outer stride, e.g. the top rows of a
  /// recording), no copy. The same result as Compute(values.transpose()).
  const PodResult& ComputeFromSamples(const Eigen::Ref<const Eigen::MatrixXd>& values);

  /// *v = the first `count` time modes of `result`, the last Compute()'s
  /// (also after SwapResult, and reordered and flipped by AlignToReference)
  /// when it ran without compute_time_modes: v_j = Y^T u_j / sigma_j (zero
  /// where sigma_j = 0) from the centred data this solver keeps, so that a
  /// caller forms only the modes it uses (an objective: 1 of 6 on the
  /// reference beam). The unweighted direct method's V bit for bit, the
  /// other methods' to rounding. v is resized to N x count (no allocation
  /// once it has that size). Throws std::invalid_argument for a weighted
  /// solver, count outside 0..result.modes() or a result of another shape.
  void TimeModes(const PodResult& result, Eigen::Index count, Eigen::MatrixXd* v);

  const PodResult& result() const { return result_; }
  /// Exchanges the result's buffers with *other's, no copy: *other receives
  /// the last result, and the next Compute() refills the buffers it gave.
  void SwapResult(PodResult* other) noexcept { std::swap(result_, *other); }
  const PodOptions& options() const { return options_; }

 private:
  struct Workspace;
  template <typename Derived>
  const PodResult& ComputeImpl(const Eigen::MatrixBase<Derived>& xt);  // xt = X^T (N x M)

  PodOptions options_;
  PodResult result_;
  std::unique_ptr<Workspace> workspace_;
};

/// One-shot POD of x (M x N); see PodSolver for repeated calls.
PodResult ComputePod(const Eigen::Ref<const Eigen::MatrixXd>& x, const PodOptions& options = {});
PodResult ComputePod(const TimeSeries& series, const PodOptions& options = {});

/// Modal assurance criterion between the columns of a (M x p) and b (M x q):
/// MAC(i, j) = (a_i^T b_j)^2 / ((a_i^T a_i)(b_j^T b_j)), in [0, 1]; 0 where a
/// column is zero. Returns (p x q).
Eigen::MatrixXd ModalAssuranceCriterion(const Eigen::Ref<const Eigen::MatrixXd>& a,
                                        const Eigen::Ref<const Eigen::MatrixXd>& b);

struct PodAlignment {
  /// MAC(reference POM i, POM j) before alignment (k_ref x k).
  Eigen::MatrixXd mac;
  /// order[i] = the original index of the mode now at position i (dim k).
  std::vector<int> order;
  /// +1 or -1 applied to the U and V columns now at position i (dim k).
  std::vector<int> sign;
};

/// Aligns `result` to `reference` in place (same M; result->modes() >=
/// reference.modes()): the reference's modes are matched greedily by largest
/// MAC first, so two POMs that swapped order are put back; the matched modes
/// go to the reference's positions and the unmatched ones follow in their
/// order. Each U column and its V column are then flipped together so that
/// u_ref^T u >= 0. sigma, lambda, energy fractions follow their modes;
/// cumulative_energy is recomputed in the new order.
PodAlignment AlignToReference(const PodResult& reference, PodResult* result);
/// The same into `alignment`, whose buffers are reused: no allocation once
/// they have the sizes (an objective's evaluations). Modes already in the
/// reference's order are only flipped in place; a permutation swaps columns in
/// place, cycle by cycle.
void AlignToReference(const PodResult& reference, PodResult* result, PodAlignment* alignment);

/// mean 1^T + U_k Sigma_k V_k^T (M x N) from the first `modes` modes (the
/// paper's fig. 2). Needs time modes; 0 <= modes <= result.modes().
Eigen::MatrixXd Reconstruct(const PodResult& result, int modes);

/// ||X - Reconstruct(result, modes)||_F / ||X||_F for the original data x
/// (M x N); 0 when x is zero and reconstructed exactly.
double ReconstructionError(const PodResult& result,
                           const Eigen::Ref<const Eigen::MatrixXd>& x,
                           int modes);

}  // namespace podid
