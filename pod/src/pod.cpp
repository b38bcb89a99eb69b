#include "podid/pod/pod.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "kernels.hpp"
#include "podid/core/error.hpp"
#include "range_eigen.hpp"

namespace podid {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
// Sign convention: components within this relative margin of the largest
// magnitude count as tied; the first of them is made positive.
constexpr double kSignTieMargin = 1e-8;
// A weighting matrix is symmetric when max |W - W^T| <= this * max |W|.
constexpr double kSymmetryTolerance = 1e-10;

/// -1 when the sign convention (header) flips this POM, else +1: the first
/// component within kSignTieMargin of the largest magnitude must be positive.
double ConventionSign(const Eigen::Ref<const Eigen::VectorXd>& pom) {
  const double largest = pom.cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < pom.size(); ++i) {
    if (std::abs(pom(i)) >= largest * (1.0 - kSignTieMargin)) return pom(i) < 0.0 ? -1.0 : 1.0;
  }
  return 1.0;
}

std::string Shape(Eigen::Index rows, Eigen::Index cols) {
  return std::to_string(rows) + " x " + std::to_string(cols);
}

}  // namespace

const char* ToString(PodMethod method) {
  switch (method) {
    case PodMethod::kAuto:
      return "auto";
    case PodMethod::kSvd:
      return "svd";
    case PodMethod::kDirect:
      return "direct";
    case PodMethod::kSnapshot:
      return "snapshot";
  }
  return "unknown";
}

PodMethod ParsePodMethod(std::string_view name) {
  for (PodMethod m :
       {PodMethod::kAuto, PodMethod::kSvd, PodMethod::kDirect, PodMethod::kSnapshot}) {
    if (name == ToString(m)) return m;
  }
  ThrowInvalid("POD method", "one of auto, svd, direct, snapshot", Excerpt(name));
}

bool PodOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& message) {
    if (why != nullptr) *why = message;
    return false;
  };
  switch (method) {
    case PodMethod::kAuto:
    case PodMethod::kSvd:
    case PodMethod::kDirect:
    case PodMethod::kSnapshot:
      break;
    default:
      return fail("PodOptions.method: expected auto, svd, direct or snapshot, got " +
                  std::to_string(static_cast<int>(method)));
  }
  if (accurate_modes < 0) {
    return fail("PodOptions.accurate_modes: expected >= 0 (0 = all), got " +
                std::to_string(accurate_modes));
  }
  if (max_modes < 0) {
    return fail("PodOptions.max_modes: expected >= 0 (0 = all), got " + std::to_string(max_modes));
  }
  if (!(energy_fraction > 0.0 && energy_fraction <= 1.0)) {
    return fail("PodOptions.energy_fraction: expected a fraction in (0, 1], got " +
                ToText(energy_fraction));
  }
  if (!(sigma_threshold >= 0.0 && std::isfinite(sigma_threshold))) {
    return fail("PodOptions.sigma_threshold: expected a finite value >= 0, got " +
                ToText(sigma_threshold));
  }
  if (weighting.size() != 0) {
    if (weighting.rows() != weighting.cols()) {
      return fail("PodOptions.weighting: expected a square (M x M) matrix, got " +
                  Shape(weighting.rows(), weighting.cols()));
    }
    if (!weighting.allFinite()) {
      return fail("PodOptions.weighting: expected finite values, got NaN or Inf");
    }
    const double scale = weighting.cwiseAbs().maxCoeff();
    const double asymmetry = (weighting - weighting.transpose()).cwiseAbs().maxCoeff();
    if (asymmetry > kSymmetryTolerance * scale) {
      return fail("PodOptions.weighting: expected a symmetric matrix, got max |W - W^T| = " +
                  ToText(asymmetry));
    }
  }
  return true;
}

double NoiseSigmaThreshold(double noise_std, Eigen::Index sensors, Eigen::Index samples) {
  if (!(noise_std >= 0.0 && std::isfinite(noise_std))) {
    ThrowInvalid("NoiseSigmaThreshold: noise_std", "a finite value >= 0", ToText(noise_std));
  }
  return noise_std *
         (std::sqrt(static_cast<double>(sensors)) + std::sqrt(static_cast<double>(samples)));
}

namespace {

// V = Y^T U diag(1 / sigma) for the first `count` modes (zero columns for
// zero modes): the unweighted direct method's time modes (eq. 17), from
// centred yt = Y^T (N x M). *v is resized to N x count.
void DirectTimeModes(const Eigen::MatrixXd& yt,
                     const Eigen::MatrixXd& poms,
                     const Eigen::VectorXd& sigma,
                     Eigen::Index count,
                     Eigen::MatrixXd* coefficients,
                     Eigen::MatrixXd* v) {
  coefficients->resize(yt.cols(), count);
  for (Eigen::Index j = 0; j < count; ++j) {
    const double s = sigma(j);
    if (s == 0.0) {
      coefficients->col(j).setZero();
    } else {
      coefficients->col(j) = poms.col(j) / s;
    }
  }
  v->resize(yt.rows(), count);
  if (yt.cols() <= internal::kSmallKernelMaxSensors) {
    internal::SmallTimesSmall(yt, *coefficients, *v);
  } else {
    v->noalias() = yt * *coefficients;
  }
}

}  // namespace

// Every buffer a Compute() needs; sized on the first call of a shape.
struct PodSolver::Workspace {
  bool weighted = false;
  Eigen::MatrixXd upper;         // L^T (M x M), W = L L^T
  Eigen::MatrixXd yt;            // centred, weighted data, transposed: Y^T (N x M)
  Eigen::MatrixXd weighted_yt;   // (X - mean)^T L before the swap into yt (N x M)
  Eigen::MatrixXd coefficients;  // kSnapshot: the kept A_k (N x k)
  Eigen::MatrixXd gram;          // Y Y^T (M x M) or Y^T Y (N x N)
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen;
  internal::RangeEigenSolver range;  // the Gram's range only (range_eigen.hpp)
  Eigen::VectorXd sigma_all;  // all min(M, N) singular values, descending
  Eigen::BDCSVD<Eigen::MatrixXd> bdc;
};

PodSolver::PodSolver(PodOptions options)
    : options_(std::move(options)), workspace_(std::make_unique<Workspace>()) {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument(why);
  if (options_.weighting.size() != 0) {
    Eigen::LLT<Eigen::MatrixXd> llt(options_.weighting);
    if (llt.info() != Eigen::Success) {
      ThrowInvalid("PodOptions.weighting", "a symmetric positive definite matrix",
                   "a matrix whose Cholesky factorisation fails");
    }
    workspace_->weighted = true;
    workspace_->upper = llt.matrixU();
  }
}

PodSolver::~PodSolver() = default;
PodSolver::PodSolver(PodSolver&&) noexcept = default;
PodSolver& PodSolver::operator=(PodSolver&&) noexcept = default;

const PodResult& PodSolver::Compute(const Eigen::Ref<const Eigen::MatrixXd>& x) {
  return ComputeImpl(x.transpose());
}

const PodResult& PodSolver::Compute(const TimeSeries& series) { return ComputeImpl(series.values); }

const PodResult& PodSolver::ComputeFromSamples(const Eigen::Ref<const Eigen::MatrixXd>& values) {
  return ComputeImpl(values);
}

template <typename Derived>
const PodResult& PodSolver::ComputeImpl(const Eigen::MatrixBase<Derived>& xt) {
  using Eigen::Index;
  Workspace& w = *workspace_;
  PodResult& r = result_;
  const Index m = xt.cols();
  const Index n = xt.rows();
  if (m == 0 || n == 0) {
    ThrowInvalid("POD data", "a non-empty snapshot matrix (M sensors x N samples)", Shape(m, n));
  }
  if (w.weighted && w.upper.rows() != m) {
    ThrowInvalid("PodOptions.weighting",
                 "an M x M matrix for M = " + std::to_string(m) + " sensors",
                 Shape(w.upper.rows(), w.upper.cols()));
  }
  const Index available = std::min(m, n);
  if (options_.max_modes > available) {
    ThrowInvalid("PodOptions.max_modes", "<= min(M, N) = " + std::to_string(available),
                 std::to_string(options_.max_modes));
  }

  PodMethod method = options_.method;
  if (method == PodMethod::kAuto) method = m <= n ? PodMethod::kDirect : PodMethod::kSnapshot;
  const Index gram_size = method == PodMethod::kDirect ? m : n;
  if (method != PodMethod::kSvd && gram_size > kMaxGramDimension) {
    if (options_.method != PodMethod::kAuto) {
      ThrowInvalid(std::string("POD method ") + ToString(method),
                   "a Gram matrix side <= " + std::to_string(kMaxGramDimension),
                   std::to_string(gram_size) + " (use svd)");
    }
    method = PodMethod::kSvd;
  }

  // eq. 1: v = u - U, U the time mean of each sensor, taken from the
  // contiguous copy so that both layouts of X give the same bits. The direct
  // method for few unweighted sensors centres Y block by block inside its Gram
  // kernel (one pass fewer over Y); every other path centres it here.
  w.yt.resize(n, m);
  w.yt.noalias() = xt;
  r.mean.resize(m);
  if (options_.remove_mean) {
    r.mean.noalias() = w.yt.colwise().mean().transpose();
  } else {
    r.mean.setZero();
  }
  const bool small_direct =
      method == PodMethod::kDirect && !w.weighted && m <= internal::kSmallKernelMaxSensors;
  if (options_.remove_mean && !small_direct) w.yt.rowwise() -= r.mean.transpose();
  if (w.weighted) {
    w.weighted_yt.resize(n, m);  // Y^T = (X - mean)^T L
    w.weighted_yt.noalias() = w.yt * w.upper.transpose().triangularView<Eigen::Lower>();
    w.yt.swap(w.weighted_yt);
  }
  // ||Y||_F^2 = sum of all sigma^2: the Gram trace for the Gram methods,
  // else a pass over Y. Non-finite input makes it non-finite.
  double energy = 0.0;
  auto check_energy = [&] {
    if (std::isfinite(energy)) return;
    for (Index j = 0; j < n; ++j) {
      for (Index i = 0; i < m; ++i) {
        if (!std::isfinite(xt(j, i))) {
          ThrowInvalid("POD data", "finite values",
                       ToText(xt(j, i)) + " at sensor " + std::to_string(i) + ", sample " +
                           std::to_string(j));
        }
      }
    }
    ThrowInvalid("POD data", "values whose squares sum to a finite number", "an overflow");
  };

  // Number of modes kept from the singular values, all min(M, N) of them.
  auto kept_modes = [&](const Eigen::VectorXd& sigma) {
    Index k = options_.max_modes == 0 ? available : options_.max_modes;
    if (options_.energy_fraction < 1.0 && energy > 0.0) {
      double cumulative = 0.0;
      for (Index j = 0; j < k; ++j) {
        cumulative += sigma(j) * sigma(j) / energy;
        if (cumulative >= options_.energy_fraction * (1.0 - 4 * kEps)) {
          k = j + 1;
          break;
        }
      }
    }
    Index above = 0;
    while (above < k && sigma(above) > options_.sigma_threshold) ++above;
    if (options_.sigma_threshold > 0.0) k = above;
    return k;
  };

  Index k = 0;
  Index rank = 0;
  const double size_eps = static_cast<double>(std::max(m, n)) * kEps;
  // Removing the means leaves their round-off, about eps |x| per value: a
  // sigma below max(M, N) eps ||X||_F is that, not a mode (sensors constant
  // at 0.1 and 0.3 gave a "mode" of sigma 4.5e-14 and 100 % of the energy).
  // ||X||_F^2 = ||Y||_F^2 + N ||mean||^2, by hypot against overflow.
  auto centring_floor = [&] {
    if (!options_.remove_mean || w.weighted) return 0.0;
    return size_eps *
           std::hypot(std::sqrt(energy), std::sqrt(static_cast<double>(n)) * r.mean.stableNorm());
  };
  bool done = false;
  if (method == PodMethod::kDirect || method == PodMethod::kSnapshot) {
    const bool direct = method == PodMethod::kDirect;
    w.gram.resize(gram_size, gram_size);
    w.gram.setZero();
    if (direct) {
      // Y Y^T, eqs. 7-8 (times N). For few sensors, blocked dot products of
      // the contiguous columns of Y^T beat Eigen's product (pod_benchmark).
      if (small_direct) {
        internal::SmallCentredGramLower(r.mean, w.yt, w.gram);
      } else {
        w.gram.selfadjointView<Eigen::Lower>().rankUpdate(w.yt.transpose());
      }
    } else {
      w.gram.selfadjointView<Eigen::Lower>().rankUpdate(w.yt);  // C*, eq. 14
    }
    energy = w.gram.trace();
    check_energy();
    // Each Gram entry sums `terms` products; below DBL_MIN a product is
    // subnormal and keeps fewer digits, about terms 2^-1074 absolute in all.
    // Unless that is below eps of the trace (lambda_1 and more), the values
    // are garbage (sigma 50 % off at |y| ~ 1e-162, without a message): such
    // data are degenerate, as those whose squares underflow to 0 are.
    const double terms = static_cast<double>(direct ? n : m);
    if (energy < terms * std::numeric_limits<double>::denorm_min() / kEps) {
      w.gram.setZero();
      energy = 0.0;
    }
    // The Gram's rank is at most `available`: when that is far below its
    // side (snapshot with N >> M, direct with M >> N), only the range is
    // solved (range_eigen.hpp), else every eigenpair.
    const bool by_range = internal::UseRangeEigen(gram_size, available);
    if (by_range) {
      w.range.Compute(w.gram, available);
    } else {
      w.eigen.compute(w.gram, Eigen::ComputeEigenvectors);
      PODID_CHECK_MSG(w.eigen.info() == Eigen::Success, "Gram eigensolver did not converge");
    }
    // The j-th largest eigenpair (= sigma_j^2): descending from the range,
    // ascending from the dense solver.
    const Eigen::VectorXd& values = by_range ? w.range.values() : w.eigen.eigenvalues();
    const auto at = [&](Index j) { return by_range ? j : gram_size - 1 - j; };
    const double largest = std::max(values(at(0)), 0.0);
    const double floor = centring_floor();
    w.sigma_all.resize(available);
    for (Index j = 0; j < available; ++j) {
      const double value = values(at(j));
      const bool nonzero = largest > 0.0 && value > size_eps * largest && value > floor * floor;
      w.sigma_all(j) = nonzero ? std::sqrt(value) : 0.0;
      rank += nonzero ? 1 : 0;
    }
    k = kept_modes(w.sigma_all);
    bool accurate = true;
    const Index must_be_accurate =
        options_.accurate_modes > 0 ? std::min<Index>(k, options_.accurate_modes) : k;
    for (Index j = 0; j < must_be_accurate; ++j) {
      const double value = w.sigma_all(j) * w.sigma_all(j);
      if (value > 0.0 && value < kAutoGramRatio * largest) accurate = false;
    }
    if (accurate || options_.method != PodMethod::kAuto) {
      const Eigen::MatrixXd& vectors = by_range ? w.range.vectors() : w.eigen.eigenvectors();
      r.poms.resize(m, k);
      r.time_modes.resize(options_.compute_time_modes ? n : 0, options_.compute_time_modes ? k : 0);
      if (direct) {
        for (Index j = 0; j < k; ++j) {
          r.poms.col(j) = vectors.col(at(j));
          // Signs now when U = Psi, so that V is formed with them (one pass fewer).
          if (!w.weighted && ConventionSign(r.poms.col(j)) < 0.0) r.poms.col(j) *= -1.0;
        }
        if (options_.compute_time_modes) {
          DirectTimeModes(w.yt, r.poms, w.sigma_all, k, &w.coefficients, &r.time_modes);
        }
      } else {
        // eq. 10: phi_k = sum_j a_kj v_j; V = A.
        w.coefficients.resize(n, k);
        for (Index j = 0; j < k; ++j) w.coefficients.col(j) = vectors.col(at(j));
        r.poms.noalias() = w.yt.transpose() * w.coefficients;
        if (options_.compute_time_modes) r.time_modes = w.coefficients;
      }
      for (Index j = 0; j < k; ++j) {
        const double s = w.sigma_all(j);
        if (s == 0.0) {
          r.poms.col(j).setZero();
          if (options_.compute_time_modes) r.time_modes.col(j).setZero();
        } else if (!direct) {
          r.poms.col(j) /= s;
        }
      }
      done = true;
    } else {
      method = PodMethod::kSvd;  // kAuto: a kept mode is below the Gram accuracy
      rank = 0;
    }
  }
  if (!done) {
    energy = w.yt.squaredNorm();
    check_energy();
    // BDCSVD of Y (M x N); below 16 columns it runs Jacobi itself. On the
    // wide shapes this is 2x faster than the SVD of Y^T (pod_benchmark).
    const unsigned int what = options_.compute_time_modes
                                  ? (Eigen::ComputeThinU | Eigen::ComputeThinV)
                                  : Eigen::ComputeThinU;
    w.bdc.compute(w.yt.transpose(), what);
    const Eigen::VectorXd& sigma = w.bdc.singularValues();
    const double floor = centring_floor();
    w.sigma_all.resize(available);
    for (Index j = 0; j < available; ++j) {
      const bool nonzero = sigma(0) > 0.0 && sigma(j) > size_eps * sigma(0) && sigma(j) > floor;
      w.sigma_all(j) = nonzero ? sigma(j) : 0.0;
      rank += nonzero ? 1 : 0;
    }
    k = kept_modes(w.sigma_all);
    r.poms = w.bdc.matrixU().leftCols(k);
    if (options_.compute_time_modes) {
      r.time_modes = w.bdc.matrixV().leftCols(k);
    } else {
      r.time_modes.resize(0, 0);
    }
    for (Index j = 0; j < k; ++j) {
      if (w.sigma_all(j) == 0.0) {
        r.poms.col(j).setZero();
        if (options_.compute_time_modes) r.time_modes.col(j).setZero();
      }
    }
  }

  // U = L^{-T} Psi: back to physical coordinates, W-orthonormal.
  if (w.weighted) w.upper.triangularView<Eigen::Upper>().solveInPlace(r.poms);

  // Deterministic signs (header): first near-largest component positive.
  // (The unweighted direct method has applied them before forming V.)
  for (Index j = 0; j < k; ++j) {
    if (w.sigma_all(j) != 0.0 && ConventionSign(r.poms.col(j)) < 0.0) {
      r.poms.col(j) *= -1.0;
      if (options_.compute_time_modes) r.time_modes.col(j) *= -1.0;
    }
  }

  r.method = method;
  r.sensors = m;
  r.samples = n;
  r.singular_values = w.sigma_all.head(k);
  const double samples = static_cast<double>(n);
  r.proper_orthogonal_values = r.singular_values.array().square() / samples;  // lambda = sigma^2/N
  r.total_energy = energy / samples;
  r.energy_fraction.resize(k);
  r.cumulative_energy.resize(k);
  double cumulative = 0.0;
  for (Index j = 0; j < k; ++j) {
    r.energy_fraction(j) =
        energy > 0.0 ? r.singular_values(j) * r.singular_values(j) / energy : 0.0;
    cumulative += r.energy_fraction(j);
    r.cumulative_energy(j) = cumulative;
  }
  r.numerical_rank = static_cast<int>(rank);
  r.message.clear();
  if (rank == 0) {  // degenerate data: say why
    double largest = 0.0, magnitude = 0.0;
    for (Index j = 0; j < n; ++j) {
      for (Index i = 0; i < m; ++i) {
        largest = std::max(largest, std::abs(xt(j, i) - r.mean(i)));
        magnitude = std::max(magnitude, std::abs(xt(j, i)));
      }
    }
    // Deviations within the centring's round-off (centring_floor) are none.
    const bool constant =
        largest == 0.0 || (options_.remove_mean && largest <= size_eps * magnitude);
    r.message =
        constant ? std::string(options_.remove_mean
                                   ? "degenerate data: numerical rank 0, every value equals "
                                     "its sensor's mean (to rounding)"
                                   : "degenerate data: numerical rank 0, every value is zero")
                 : "degenerate data: numerical rank 0, the largest deviation " + ToText(largest) +
                       " is too small for double precision (its square is subnormal or 0); "
                       "rescale the data";
  }
  return r;
}

void PodSolver::TimeModes(const PodResult& result, Eigen::Index count, Eigen::MatrixXd* v) {
  using Eigen::Index;
  Workspace& w = *workspace_;
  const Index m = result.sensors, n = result.samples;
  if (w.weighted) {
    ThrowInvalid("PodSolver::TimeModes", "an unweighted POD", "a solver with PodOptions.weighting");
  }
  if (count < 0 || count > result.modes()) {
    ThrowInvalid("PodSolver::TimeModes: count", "0.." + std::to_string(result.modes()),
                 std::to_string(count));
  }
  if (w.yt.rows() != n || w.yt.cols() != m || result.poms.rows() != m ||
      result.singular_values.size() != result.modes()) {
    ThrowInvalid("PodSolver::TimeModes", "the result of this solver's last Compute()",
                 "a result of " + Shape(m, n) + " and data of " + Shape(w.yt.cols(), w.yt.rows()));
  }
  DirectTimeModes(w.yt, result.poms, result.singular_values, count, &w.coefficients, v);
}

PodResult ComputePod(const Eigen::Ref<const Eigen::MatrixXd>& x, const PodOptions& options) {
  PodSolver solver(options);
  return solver.Compute(x);
}

PodResult ComputePod(const TimeSeries& series, const PodOptions& options) {
  PodSolver solver(options);
  return solver.Compute(series);
}

namespace {

// MAC into a caller's matrix (no allocation once it has the size).
void MacInto(const Eigen::Ref<const Eigen::MatrixXd>& a, const Eigen::Ref<const Eigen::MatrixXd>& b,
             Eigen::MatrixXd* mac) {
  if (a.rows() != b.rows()) {
    ThrowInvalid("ModalAssuranceCriterion", "mode shapes of the same length (rows)",
                 Shape(a.rows(), a.cols()) + " and " + Shape(b.rows(), b.cols()));
  }
  mac->resize(a.cols(), b.cols());
  mac->noalias() = a.transpose() * b;
  for (Eigen::Index j = 0; j < mac->cols(); ++j) {
    const double nb = b.col(j).squaredNorm();
    for (Eigen::Index i = 0; i < mac->rows(); ++i) {
      const double d = a.col(i).squaredNorm() * nb;
      const double dot = (*mac)(i, j);
      (*mac)(i, j) = d > 0.0 ? std::min(dot * dot / d, 1.0) : 0.0;
    }
  }
}

}  // namespace

Eigen::MatrixXd ModalAssuranceCriterion(const Eigen::Ref<const Eigen::MatrixXd>& a,
                                        const Eigen::Ref<const Eigen::MatrixXd>& b) {
  Eigen::MatrixXd mac;
  MacInto(a, b, &mac);
  return mac;
}

PodAlignment AlignToReference(const PodResult& reference, PodResult* result) {
  PodAlignment alignment;
  AlignToReference(reference, result, &alignment);
  return alignment;
}

void AlignToReference(const PodResult& reference, PodResult* result, PodAlignment* alignment) {
  PODID_CHECK(result != nullptr && alignment != nullptr);
  using Eigen::Index;
  const Index kr = reference.modes();
  const Index k = result->modes();
  if (reference.poms.rows() != result->poms.rows()) {
    ThrowInvalid("AlignToReference", "POMs of the same length M (rows)",
                 Shape(reference.poms.rows(), kr) + " and " + Shape(result->poms.rows(), k));
  }
  if (k < kr) {
    ThrowInvalid("AlignToReference",
                 "at least as many modes as the reference (" + std::to_string(kr) + ")",
                 std::to_string(k));
  }
  MacInto(reference.poms, result->poms, &alignment->mac);
  const Eigen::MatrixXd& mac = alignment->mac;

  // Greedy matching: the largest remaining MAC first. order[i] = the mode
  // matched to reference mode i; sign doubles as the "used" flags here.
  std::vector<int>& order = alignment->order;
  std::vector<int>& used = alignment->sign;
  order.assign(static_cast<std::size_t>(kr), -1);
  used.assign(static_cast<std::size_t>(k), 0);
  for (Index step = 0; step < kr; ++step) {
    double best = -1.0;
    Index bi = 0, bj = 0;
    for (Index i = 0; i < kr; ++i) {
      if (order[static_cast<std::size_t>(i)] >= 0) continue;
      for (Index j = 0; j < k; ++j) {
        if (used[static_cast<std::size_t>(j)]) continue;
        // Ties (e.g. zero modes, MAC 0) go to the lowest indices.
        if (mac(i, j) > best) {
          best = mac(i, j);
          bi = i;
          bj = j;
        }
      }
    }
    order[static_cast<std::size_t>(bi)] = static_cast<int>(bj);
    used[static_cast<std::size_t>(bj)] = 1;
  }
  for (Index j = 0; j < k; ++j) {
    if (!used[static_cast<std::size_t>(j)]) order.push_back(static_cast<int>(j));
  }

  PodResult& r = *result;
  const bool has_v = r.time_modes.cols() == k;
  // new column i = old column order[i]: each cycle of the permutation by
  // swaps of columns, in place (a copy of V was 1 % of an objective
  // evaluation); the usual identity order swaps nothing.
  std::vector<int>& done = alignment->sign;  // reused as "placed" flags, then the signs
  done.assign(static_cast<std::size_t>(k), 0);
  for (Index start = 0; start < k; ++start) {
    Index i = start;
    while (!done[static_cast<std::size_t>(i)]) {
      done[static_cast<std::size_t>(i)] = 1;
      const Index j = order[static_cast<std::size_t>(i)];
      if (j == start) break;
      r.poms.col(i).swap(r.poms.col(j));
      if (has_v) r.time_modes.col(i).swap(r.time_modes.col(j));
      std::swap(r.singular_values(i), r.singular_values(j));
      std::swap(r.proper_orthogonal_values(i), r.proper_orthogonal_values(j));
      std::swap(r.energy_fraction(i), r.energy_fraction(j));
      i = j;
    }
  }
  double cumulative = 0.0;
  for (Index i = 0; i < k; ++i) {
    int s = 1;
    if (i < kr && reference.poms.col(i).dot(r.poms.col(i)) < 0.0) {
      s = -1;
      r.poms.col(i) *= -1.0;
      if (has_v) r.time_modes.col(i) *= -1.0;
    }
    alignment->sign[static_cast<std::size_t>(i)] = s;
    cumulative += r.energy_fraction(i);
    r.cumulative_energy(i) = cumulative;
  }
}

Eigen::MatrixXd Reconstruct(const PodResult& result, int modes) {
  if (modes < 0 || modes > result.modes()) {
    ThrowInvalid("Reconstruct: modes", "0 <= modes <= " + std::to_string(result.modes()),
                 std::to_string(modes));
  }
  if (result.time_modes.cols() != result.modes() || result.time_modes.rows() != result.samples) {
    ThrowInvalid("Reconstruct", "a PodResult with time modes (compute_time_modes = true)",
                 "V of " + Shape(result.time_modes.rows(), result.time_modes.cols()));
  }
  Eigen::MatrixXd x = result.mean.replicate(1, result.samples);
  // U Sigma V^T: eq. 6 with a_k(t) = sigma_k V(t, k), truncated to `modes`.
  x.noalias() += result.poms.leftCols(modes) * result.singular_values.head(modes).asDiagonal() *
                 result.time_modes.leftCols(modes).transpose();
  return x;
}

double ReconstructionError(const PodResult& result,
                           const Eigen::Ref<const Eigen::MatrixXd>& x,
                           int modes) {
  if (x.rows() != result.sensors || x.cols() != result.samples) {
    ThrowInvalid("ReconstructionError: data",
                 "the decomposed shape " + Shape(result.sensors, result.samples),
                 Shape(x.rows(), x.cols()));
  }
  const double difference = (x - Reconstruct(result, modes)).norm();
  const double scale = x.norm();
  return scale > 0.0 ? difference / scale : difference;
}

}  // namespace podid
