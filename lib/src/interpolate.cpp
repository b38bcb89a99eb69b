#include "podid/core/interpolate.hpp"

#include "fftw_util.hpp"
#include "podid/core/error.hpp"

namespace podid {
namespace {

/// Smallest length >= n with prime factors 2, 3, 5 only (fast FFT lengths).
Eigen::Index SmoothLength(Eigen::Index n) {
  for (Eigen::Index p = n;; ++p) {
    Eigen::Index m = p;
    for (const int f : {2, 3, 5})
      while (m % f == 0) m /= f;
    if (m == 1) return p;
  }
}

}  // namespace

Eigen::VectorXd InterpolateBandLimited(const Eigen::VectorXd& x, int factor) {
  PODID_CHECK(factor >= 1);
  const Eigen::Index n = x.size();
  if (factor == 1 || n == 0) return x;
  if (n == 1) return Eigen::VectorXd::Constant(1, x[0]);
  const Eigen::Index out = (n - 1) * factor + 1;
  // The line through the end samples, removed and added back.
  const double x0 = x[0], slope = (x[n - 1] - x[0]) / static_cast<double>(n - 1);
  const Eigen::Index p = SmoothLength(n);
  const Eigen::Index m = p * factor;
  if (m > internal::FftwRealPlan::kMaxLength) {
    ThrowInvalid("band-limited interpolation of a sampled force (integrator.substeps)",
                 "at most 2^31 - 1 fine points", ToText(m) + " (fewer substeps or a shorter record)");
  }
  auto in = internal::FftwAllocate<double>(static_cast<std::size_t>(p));
  auto spectrum = internal::FftwAllocate<fftw_complex>(static_cast<std::size_t>(p / 2 + 1));
  auto padded = internal::FftwAllocate<fftw_complex>(static_cast<std::size_t>(m / 2 + 1));
  auto fine = internal::FftwAllocate<double>(static_cast<std::size_t>(m));
  const auto forward = internal::FftwRealPlan::Forward(p, in.get(), spectrum.get());
  const auto inverse = internal::FftwRealPlan::Inverse(m, padded.get(), fine.get());
  for (Eigen::Index i = 0; i < n; ++i) in[i] = x[i] - (x0 + slope * static_cast<double>(i));
  for (Eigen::Index i = n; i < p; ++i) in[i] = 0.0;
  forward.Execute();
  // Bins 0 .. P/2 of the real sequence into bins 0 .. M/2 of the fine one
  // (the negative bins are implied by the c2r transform's Hermitian symmetry).
  for (Eigen::Index k = 0; k <= m / 2; ++k) padded[k][0] = padded[k][1] = 0.0;
  const Eigen::Index half = (p - 1) / 2;  // bins strictly below Nyquist
  for (Eigen::Index k = 0; k <= half; ++k) {
    padded[k][0] = spectrum[k][0];
    padded[k][1] = spectrum[k][1];
  }
  if (p % 2 == 0) {  // Nyquist: split between +- Nyquist so that the interpolant stays real
    padded[p / 2][0] = 0.5 * spectrum[p / 2][0];
    padded[p / 2][1] = 0.5 * spectrum[p / 2][1];
  }
  inverse.Execute();  // unnormalised: the samples need 1 / P
  Eigen::VectorXd y(out);
  const double scale = 1.0 / static_cast<double>(p);
  for (Eigen::Index j = 0; j < out; ++j) {
    y[j] = scale * fine[j] + x0 + slope * static_cast<double>(j) / static_cast<double>(factor);
  }
  return y;
}

}  // namespace podid
