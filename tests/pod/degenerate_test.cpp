// Degenerate data (issue 10 item 9): POD of values whose squares underflow, or
// of constant sensors, has numerical rank 0 and says so, instead of reporting
// rank 0 as an ordinary result.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "podid/pod/pod.hpp"

namespace podid {
namespace {

// Two sensors, 200 samples of two tones with scale `amplitude`.
Eigen::MatrixXd Tones(double amplitude) {
  Eigen::MatrixXd x(2, 200);
  for (int j = 0; j < 200; ++j) {
    x(0, j) = amplitude * std::sin(0.05 * j);
    x(1, j) = 2 * amplitude * std::cos(0.03 * j);
  }
  return x;
}

// The Gram methods (auto picks kDirect here) form sums of squares, which
// underflow to 0 below ~1e-154; kSvd scales internally and still finds rank 2.
TEST(PodDegenerate, ValuesWhoseSquaresUnderflowAreDegenerate) {
  for (const PodMethod method : {PodMethod::kAuto, PodMethod::kDirect, PodMethod::kSnapshot}) {
    PodOptions options;
    options.method = method;
    const PodResult r = ComputePod(Tones(1e-304), options);
    EXPECT_EQ(r.numerical_rank, 0) << ToString(method);
    EXPECT_TRUE(r.IsDegenerate());
    EXPECT_NE(r.message.find("degenerate data: numerical rank 0, the largest deviation 2"),
              std::string::npos)
        << r.message;
    EXPECT_NE(r.message.find("rescale the data"), std::string::npos) << r.message;
  }
}

// Between ~1e-154 and ~1e-162 the Gram's products are subnormal: sigma came
// out of kAuto (kDirect) 50 % wrong at 1e-162, with no message. Those data
// are degenerate too; kSvd scales Y itself and still finds rank 2.
TEST(PodDegenerate, ValuesWhoseGramProductsAreSubnormalAreDegenerate) {
  for (const double amplitude : {1e-156, 1e-162}) {
    for (const PodMethod method : {PodMethod::kAuto, PodMethod::kDirect, PodMethod::kSnapshot}) {
      PodOptions options;
      options.method = method;
      const PodResult r = ComputePod(Tones(amplitude), options);
      EXPECT_TRUE(r.IsDegenerate()) << ToString(method) << " " << amplitude;
      EXPECT_NE(r.message.find("(its square is subnormal or 0); rescale the data"),
                std::string::npos)
          << r.message;
    }
    PodOptions svd;
    svd.method = PodMethod::kSvd;
    EXPECT_EQ(ComputePod(Tones(amplitude), svd).numerical_rank, 2) << amplitude;
  }
}

TEST(PodDegenerate, ConstantSensorsAreDegenerate) {
  Eigen::MatrixXd x = Eigen::MatrixXd::Constant(3, 50, 4.5);
  PodResult r = ComputePod(x);
  EXPECT_TRUE(r.IsDegenerate());
  EXPECT_EQ(
      r.message,
      "degenerate data: numerical rank 0, every value equals its sensor's mean (to rounding)");
  PodOptions raw;
  raw.remove_mean = false;
  x.setZero();
  r = ComputePod(x, raw);
  EXPECT_EQ(r.message, "degenerate data: numerical rank 0, every value is zero");
}

// 0.1 and 0.3 are not doubles: their means differ from them by round-off,
// which gave a "mode" of sigma 4.5e-14 holding 100 % of the energy. Every
// method now sees no mode; a real variation 1e-10 of the offset is one.
TEST(PodDegenerate, ConstantsThatAreNotDoublesAreDegenerate) {
  Eigen::MatrixXd x(2, 1000);
  x.row(0).setConstant(0.1);
  x.row(1).setConstant(0.3);
  for (const PodMethod method :
       {PodMethod::kAuto, PodMethod::kDirect, PodMethod::kSnapshot, PodMethod::kSvd}) {
    PodOptions options;
    options.method = method;
    const PodResult r = ComputePod(x, options);
    EXPECT_TRUE(r.IsDegenerate()) << ToString(method) << ": sigma_1 " << r.singular_values(0);
    EXPECT_NE(r.message.find("every value equals its sensor's mean (to rounding)"),
              std::string::npos)
        << r.message;
  }
  for (int j = 0; j < 1000; j += 2) x(0, j) += 1e-11;
  EXPECT_EQ(ComputePod(x).numerical_rank, 1);
}

TEST(PodDegenerate, OrdinaryDataHaveNoMessage) {
  // The same tones at amplitude 1 (and 1e-150, whose squares are normal) have rank 2.
  for (const double amplitude : {1.0, 1e-150}) {
    const PodResult r = ComputePod(Tones(amplitude));
    EXPECT_EQ(r.numerical_rank, 2) << amplitude;
    EXPECT_FALSE(r.IsDegenerate());
    EXPECT_TRUE(r.message.empty()) << r.message;
  }
}

}  // namespace
}  // namespace podid
