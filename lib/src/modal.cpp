// BeamModel::Modes: the lowest modes of K phi = omega^2 M phi, by Eigen's
// dense generalised solver (small models, or all modes) or by Spectra's
// shift-invert Lanczos (SymGEigsShiftSolver) with a sparse LDL^T of K - sigma M.
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <Spectra/MatOp/SparseSymMatProd.h>
#include <Spectra/SymGEigsShiftSolver.h>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "podid/core/beam_model.hpp"
#include "podid/core/error.hpp"

namespace podid {
namespace {

constexpr const char* kModelKeys =
    "model (beam.length, beam.elements, beam.youngs_modulus, beam.density, beam.area (or width, "
    "height), or the imported matrices)";

/// y = (K - sigma M)^-1 x with one sparse LDL^T (Spectra's OpType interface).
class ShiftInvertLdlt {
 public:
  using Scalar = double;
  ShiftInvertLdlt(const Eigen::SparseMatrix<double>& k, const Eigen::SparseMatrix<double>& m)
      : k_(k), m_(m) {}
  Eigen::Index rows() const { return k_.rows(); }
  Eigen::Index cols() const { return k_.cols(); }
  void set_shift(double sigma) {
    const Eigen::SparseMatrix<double> shifted = k_ - sigma * m_;
    ldlt_.compute(shifted);
    if (ldlt_.info() != Eigen::Success || !ldlt_.vectorD().allFinite()) {
      throw std::invalid_argument("no LDL^T factor of K - sigma M at sigma = " + ToText(sigma));
    }
  }
  void perform_op(const double* x_in, double* y_out) const {
    Eigen::Map<const Eigen::VectorXd> x(x_in, rows());
    Eigen::Map<Eigen::VectorXd> y(y_out, rows());
    y = ldlt_.solve(x);
  }

 private:
  const Eigen::SparseMatrix<double>& k_;
  const Eigen::SparseMatrix<double>& m_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
};

[[noreturn]] void ThrowModesFailed(const Eigen::SparseMatrix<double>& m,
                                   const Eigen::SparseMatrix<double>& k, const std::string& why) {
  const double m_max = m.nonZeros() ? m.coeffs().cwiseAbs().maxCoeff() : 0.0;
  const double k_max = k.nonZeros() ? k.coeffs().cwiseAbs().maxCoeff() : 0.0;
  ThrowInvalid(kModelKeys,
               "finite M (positive definite) and K whose modes double precision can compute",
               why + " (max |M| " + ToText(m_max) + ", max |K| " + ToText(k_max) + ")");
}

/// Lanczos tolerance on the Ritz values of (K - sigma M)^-1 (relative):
/// frequencies agree with the dense solver to ~1e-10 (model_test).
constexpr double kLanczosTolerance = 1e-12;
constexpr int kLanczosMaxIterations = 1000;

/// Largest residual of a sparse eigenpair, relative to the scale of the two
/// products: ||K phi - lambda M phi||_inf / ((||K||_inf + lambda ||M||_inf)
/// ||phi||_inf). Measured: 1e-16 on the sparse modes of 150- and 1000-element
/// beams, 1.2e-15 on a 10^4-dof chain; 3.5e-4 on 250 of a 300-dof beam's
/// modes, whose highest were wrong.
constexpr double kModeResidualTolerance = 1e-8;

/// The worst relative residual (above) of the columns of `shapes`.
double WorstResidual(const Eigen::SparseMatrix<double>& k,
                     const Eigen::SparseMatrix<double>& m,
                     const Eigen::VectorXd& lambda,
                     const Eigen::MatrixXd& shapes) {
  const auto row_sum = [](const Eigen::SparseMatrix<double>& a) {
    return (a.cwiseAbs() * Eigen::VectorXd::Ones(a.cols())).maxCoeff();
  };
  const double k_norm = row_sum(k), m_norm = row_sum(m);
  double worst = 0.0;
  for (Eigen::Index j = 0; j < shapes.cols(); ++j) {
    const Eigen::VectorXd r = k * shapes.col(j) - lambda[j] * (m * shapes.col(j));
    const double scale =
        (k_norm + std::abs(lambda[j]) * m_norm) * shapes.col(j).lpNorm<Eigen::Infinity>();
    worst = std::max(worst, scale > 0.0 ? r.lpNorm<Eigen::Infinity>() / scale : 0.0);
  }
  return worst;
}

}  // namespace

void BeamModel::SparseModes(int count,
                            Eigen::VectorXd* eigenvalues,
                            Eigen::MatrixXd* shapes) const {
  const int n = dofs();
  // Shift-invert about sigma: the modes nearest sigma converge first. K is
  // positive definite unless the model moves as a rigid body; then a small
  // negative shift (a millionth of the mean K_ii / M_ii) keeps K - sigma M
  // positive definite while the zero eigenvalues stay nearest to it.
  // Rigid when flagged, or when K's LDL^T has a pivot at round-off level
  // relative to its diagonal (a model from BuildLinear or FromMatrices).
  // The shift, -1e-6 of the mean K_ii / M_ii (tens of times the lowest
  // flexible eigenvalue of a 150-element free beam, below it for a chain):
  // a smaller one (1e-12) leaves K - sigma M too ill-conditioned and the
  // flexible shapes lose 4 digits (large_model_test).
  bool rigid = rigid_body_modes_;
  if (!rigid) {
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> k_ldlt(stiffness_);
    const double scale = stiffness_.diagonal().cwiseAbs().maxCoeff();
    rigid = k_ldlt.info() != Eigen::Success || !(k_ldlt.vectorD().minCoeff() > 1e-13 * scale);
  }
  const double sigma =
      rigid ? -1e-6 * std::abs(stiffness_.diagonal().sum() / mass_.diagonal().sum()) : 0.0;
  ShiftInvertLdlt op(stiffness_, mass_);
  Spectra::SparseSymMatProd<double> bop(mass_);
  const int ncv = std::min(n, std::max(2 * count + 1, count + 20));
  // The Lanczos basis holds ncv x n doubles: 2000 modes of a 10^6-dof model
  // asked for 32 GB. Bounded as the readers are (1 GiB).
  constexpr double kMaxBasisDoubles = double{1 << 27};
  if (static_cast<double>(ncv) * n > kMaxBasisDoubles) {
    const long long most = std::max(1LL, (static_cast<long long>(kMaxBasisDoubles / n) - 1) / 2);
    ThrowInvalid("modes: count",
                 "at most " + ToText(most) + " modes of this " + ToText(n) +
                     "-dof model (the sparse solver's basis of about 2 x count x dofs doubles "
                     "stays within 1 GiB)",
                 ToText(count));
  }
  bool converged = false;
  std::string failure;
  try {
    Spectra::SymGEigsShiftSolver<ShiftInvertLdlt, Spectra::SparseSymMatProd<double>,
                                 Spectra::GEigsMode::ShiftInvert>
        eig(op, bop, count, ncv, sigma);
    eig.init();
    eig.compute(Spectra::SortRule::LargestMagn, kLanczosMaxIterations, kLanczosTolerance,
                Spectra::SortRule::SmallestAlge);
    converged = eig.info() == Spectra::CompInfo::Successful;
    if (converged) {
      *eigenvalues = eig.eigenvalues();
      *shapes = eig.eigenvectors();
    }
  } catch (const std::invalid_argument& e) {  // from set_shift: no factor
    failure = e.what();
  }
  if (!failure.empty()) ThrowModesFailed(mass_, stiffness_, failure);
  if (!converged) {
    ThrowModesFailed(mass_, stiffness_,
                     "the sparse eigensolver did not converge on " + ToText(count) + " modes");
  }
  if (!eigenvalues->allFinite() || !shapes->allFinite() || eigenvalues->size() != count) {
    ThrowModesFailed(mass_, stiffness_, "a failed sparse eigensolution");
  }
}

ModalAnalysis BeamModel::Modes() const { return Modes(dofs(), EigenSolverChoice::kDense); }

ModalAnalysis BeamModel::Modes(int count, EigenSolverChoice solver) const {
  const int n = dofs();
  if (count < 1 || count > n) ThrowInvalid("modes: count", "a number of modes in 1.." + ToText(n), ToText(count));
  bool sparse = solver == EigenSolverChoice::kSparse ||
                (solver == EigenSolverChoice::kAuto && n > kDenseModesLimit && count < n);
  Eigen::VectorXd eigenvalues;
  ModalAnalysis result;
  if (sparse) {
    if (count >= n)
      ThrowInvalid("modes: count",
                   "fewer modes than dofs (" + ToText(n) + ") for the sparse solver",
                   ToText(count));
    SparseModes(count, &eigenvalues, &result.shapes);
    // Lanczos's tolerance is on the Ritz values of (K - sigma M)^-1: the
    // highest of many modes can converge there and still be wrong (a 300-dof
    // beam's modes 200-250). Checked in K phi = lambda M phi itself; the dense
    // solver takes over where it can.
    const double worst = WorstResidual(stiffness_, mass_, eigenvalues, result.shapes);
    if (!(worst <= kModeResidualTolerance)) {
      if (solver == EigenSolverChoice::kSparse || n > kMaxDenseModesDofs) {
        ThrowModesFailed(mass_, stiffness_,
                         "the sparse eigensolver's " + ToText(count) +
                             " modes have a relative residual of " + ToText(worst) + " (at most " +
                             ToText(kModeResidualTolerance) + "): ask for fewer modes");
      }
      sparse = false;
    }
  }
  if (!sparse) {
    if (n > kMaxDenseModesDofs) {
      ThrowInvalid(
          "modes",
          "a model of at most " + ToText(kMaxDenseModesDofs) +
              " dofs for the dense eigensolver (all modes, O(n^3) time and 8 n^2 doubles); "
              "the lowest modes of a larger model come from the sparse solver",
          ToText(n) + " dofs (" + ToText(count) + " modes asked)");
    }
    const Eigen::MatrixXd k = DenseStiffness(), m = DenseMass();
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(k, m);
    // Values that pass the input checks can still give M and K too far apart in
    // scale for double precision: an input error, not a bug.
    if (eig.info() != Eigen::Success || !eig.eigenvalues().allFinite() ||
        !eig.eigenvectors().allFinite()) {
      ThrowModesFailed(mass_, stiffness_, "a failed eigensolution");
    }
    eigenvalues = eig.eigenvalues().head(count);  // ascending, M-normalised vectors
    result.shapes = eig.eigenvectors().leftCols(count);
    // The dense solver's lambda_k errs by ~eps lambda_max / lambda_k (mode 1
    // of a 500-element cantilever: 1.3e-5); its vectors are better, and their
    // Rayleigh quotient phi^T K phi / phi^T M phi (sparse, O(nnz) each) errs by
    // about the square of their error: 2.3e-7 there (large_model_test).
    for (int j = 0; j < count; ++j) {
      const auto phi = result.shapes.col(j);
      const double modal_mass = phi.dot(mass_ * phi);
      if (modal_mass > 0.0) eigenvalues[j] = phi.dot(stiffness_ * phi) / modal_mass;
    }
  }
  result.frequencies_Hz.resize(count);
  result.damping_ratios.resize(count);
  for (int k = 0; k < count; ++k) {
    const double omega = std::sqrt(std::max(eigenvalues[k], 0.0));
    result.frequencies_Hz[k] = omega / (2 * std::numbers::pi);
    auto phi = result.shapes.col(k);
    // Sign convention: the largest-magnitude transverse component is positive.
    Eigen::Index best = transverse_.empty() ? 0 : transverse_.front();
    for (const int i : transverse_) {
      if (std::abs(phi[i]) > std::abs(phi[best])) best = i;
    }
    if (phi[best] < 0) phi = -phi;
    const Eigen::VectorXd c_phi = damping_ * phi;
    result.damping_ratios[k] = omega > 0 ? phi.dot(c_phi) / (2 * omega) : 0.0;
  }
  return result;
}

}  // namespace podid
