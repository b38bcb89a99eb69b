#include "podid/core/interpolate.hpp"

#include <complex>
#include <unsupported/Eigen/FFT>
#include <vector>

#include "podid/core/error.hpp"

namespace podid {
namespace {

/// Smallest length >= n with prime factors 2, 3, 5 only: kissfft (Eigen's
/// FFT) costs O(n p) for a prime factor p.
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
  std::vector<std::complex<double>> in(static_cast<std::size_t>(p), 0.0), spectrum;
  for (Eigen::Index i = 0; i < n; ++i) in[i] = x[i] - (x0 + slope * static_cast<double>(i));
  Eigen::FFT<double> fft;
  fft.fwd(spectrum, in);
  const Eigen::Index m = p * factor;
  std::vector<std::complex<double>> padded(static_cast<std::size_t>(m), 0.0), fine;
  const Eigen::Index half = (p - 1) / 2;  // bins strictly below Nyquist
  padded[0] = spectrum[0];
  for (Eigen::Index k = 1; k <= half; ++k) {
    padded[k] = spectrum[k];
    padded[m - k] = spectrum[p - k];
  }
  if (p % 2 == 0) {  // Nyquist: split so that the interpolant stays real
    padded[p / 2] = 0.5 * spectrum[p / 2];
    padded[m - p / 2] = 0.5 * spectrum[p / 2];
  }
  fft.inv(fine, padded);  // scaled by 1 / m; the samples need 1 / p
  Eigen::VectorXd y(out);
  for (Eigen::Index j = 0; j < out; ++j) {
    y[j] = static_cast<double>(factor) * fine[j].real() +
           x0 + slope * static_cast<double>(j) / static_cast<double>(factor);
  }
  return y;
}

}  // namespace podid
