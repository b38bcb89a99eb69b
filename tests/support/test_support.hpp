#pragma once
// Shared test helpers. Every tolerance a test uses is a named constant with a
// comment saying why it has that size.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <sstream>
#include <string>

namespace podid::testing {

inline std::string DataPath(const std::string& name) {
  return std::string(PODID_TEST_DATA_DIR) + "/" + name;
}
inline std::string ExamplePath(const std::string& name) {
  return std::string(PODID_EXAMPLES_DIR) + "/" + name;
}

/// Passes when a and b have the same shape and max |a - b| <= tolerance;
/// otherwise prints the worst entry.
template <typename A, typename B>
::testing::AssertionResult ExpectMatricesNear(const Eigen::MatrixBase<A>& a,
                                              const Eigen::MatrixBase<B>& b, double tolerance) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) {
    return ::testing::AssertionFailure() << "shape mismatch: " << a.rows() << "x" << a.cols()
                                         << " vs " << b.rows() << "x" << b.cols();
  }
  double worst = 0.0;
  Eigen::Index wi = 0, wj = 0;
  for (Eigen::Index j = 0; j < a.cols(); ++j) {
    for (Eigen::Index i = 0; i < a.rows(); ++i) {
      const double d = std::abs(static_cast<double>(a(i, j)) - static_cast<double>(b(i, j)));
      if (!(d <= worst)) {  // also catches NaN
        worst = d;
        wi = i;
        wj = j;
        if (std::isnan(d)) break;
      }
    }
  }
  if (worst <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "worst entry (" << wi << ", " << wj << "): " << a(wi, wj) << " vs " << b(wi, wj)
         << ", |diff| = " << worst << " > tolerance " << tolerance;
}

/// Relative L2 error ||a - b|| / ||b|| (Frobenius norm for matrices).
template <typename A, typename B>
double RelativeError(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  return (a - b).norm() / b.norm();
}

/// EXPECT_THROW plus a check that the message contains `needle`.
#define PODID_EXPECT_THROW_WITH(statement, exception_type, needle)                       \
  do {                                                                                 \
    try {                                                                              \
      statement;                                                                       \
      ADD_FAILURE() << "expected " #exception_type " from: " #statement;               \
    } catch (const exception_type& e) {                                                \
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos)                 \
          << "message \"" << e.what() << "\" lacks \"" << (needle) << "\"";            \
    }                                                                                  \
  } while (false)

}  // namespace podid::testing
