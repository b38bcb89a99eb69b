// CheckMeasuredQuantity (podid/core/quantity_check.hpp): records of the
// reference beam simulated as acceleration, velocity and displacement.
#include "podid/core/quantity_check.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "podid/core/simulate.hpp"
#include "reference_case.hpp"

namespace podid {
namespace {

using podid::testing::ReferenceCase;

TimeSeries Record(const std::string& quantity) {
  // 1 s of the reference beam's free decay: 5001 samples, modes 1-3 in band.
  return Simulate(ReferenceCase({"sensors.quantity=" + quantity, "time.duration=1.0"})).sensors;
}

// Acceleration and displacement of the same motion differ by w^2 exactly for
// the continuous signals; Newmark's accelerations and the finite record's
// leakage bend the ratio a little: 0.2 leaves the decision (|k| < 0.5, or the
// nearest integer) far from its thresholds.
constexpr double kExponentTolerance = 0.2;

TEST(QuantityCheckTest, AccelerationDeclaredAsDisplacement) {
  const QuantityCheck q = CheckMeasuredQuantity(Record("acceleration"), Record("displacement"),
                                                SensorQuantity::kDisplacement);
  ASSERT_TRUE(q.determined);
  EXPECT_NEAR(q.exponent, 2.0, kExponentTolerance) << q.low_Hz << ".." << q.high_Hz;
  EXPECT_TRUE(q.mismatch);
  EXPECT_EQ(q.likely, SensorQuantity::kAcceleration);
  EXPECT_NE(q.message.find("the record looks like acceleration while [sensors] quantity = "
                           "\"displacement\""),
            std::string::npos)
      << q.message;
}

TEST(QuantityCheckTest, DisplacementDeclaredAsAccelerationAndVelocity) {
  const QuantityCheck q = CheckMeasuredQuantity(Record("displacement"), Record("acceleration"),
                                                SensorQuantity::kAcceleration);
  ASSERT_TRUE(q.determined);
  EXPECT_NEAR(q.exponent, -2.0, kExponentTolerance);
  EXPECT_EQ(q.likely, SensorQuantity::kDisplacement);
  const QuantityCheck v = CheckMeasuredQuantity(Record("velocity"), Record("displacement"),
                                                SensorQuantity::kDisplacement);
  EXPECT_NEAR(v.exponent, 1.0, kExponentTolerance);
  EXPECT_EQ(v.likely, SensorQuantity::kVelocity);
}

TEST(QuantityCheckTest, SameQuantityIsNotReported) {
  const TimeSeries a = Record("acceleration");
  TimeSeries other = Simulate(ReferenceCase({"sensors.quantity=acceleration", "time.duration=1.0",
                                             "nonlinearity.0.k3=4.0e9"}))
                         .sensors;  // another knl: same quantity, other amplitudes
  const QuantityCheck q = CheckMeasuredQuantity(a, other, SensorQuantity::kAcceleration);
  ASSERT_TRUE(q.determined);
  EXPECT_LT(std::abs(q.exponent), 0.5);
  EXPECT_FALSE(q.mismatch);
  EXPECT_TRUE(q.message.empty());
}

TEST(QuantityCheckTest, TooFewSamplesIsUndetermined) {
  TimeSeries s;
  s.time_s = Eigen::VectorXd::LinSpaced(10, 0.0, 0.9);
  s.values = Eigen::MatrixXd::Random(10, 1);
  s.channel_names = {"x"};
  EXPECT_FALSE(CheckMeasuredQuantity(s, s, SensorQuantity::kDisplacement).determined);
}

}  // namespace
}  // namespace podid

namespace podid {
namespace {

TimeSeries WithWhiteNoise(TimeSeries s, double relative_std, unsigned seed) {
  std::mt19937_64 engine(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (Eigen::Index c = 0; c < s.channels(); ++c) {
    const double rms = std::sqrt(s.values.col(c).squaredNorm() / s.samples());
    for (Eigen::Index n = 0; n < s.samples(); ++n) s.values(n, c) += relative_std * rms * normal(engine);
  }
  return s;
}

TEST(QuantityCheckTest, NoisyRecordOfTheDeclaredQuantityIsNotReported) {
  // White measurement noise lifts the weak higher modes' peaks of the measured
  // spectrum, not the simulated one's: without the noise floor taken out the
  // ratio grew as f^0.8 at the shared record's noise and a "looks like
  // velocity" warning was raised against a displacement record.
  const TimeSeries clean = Record("displacement");
  for (double level : {0.02, 0.1, 0.3}) {
    const QuantityCheck q =
        CheckMeasuredQuantity(WithWhiteNoise(clean, level, 5), clean, SensorQuantity::kDisplacement);
    EXPECT_FALSE(q.mismatch) << level << ": " << q.message << " (exponent " << q.exponent << ")";
  }
  // The same noise on accelerations declared as displacements is still found.
  const QuantityCheck a = CheckMeasuredQuantity(WithWhiteNoise(Record("acceleration"), 0.1, 6), clean,
                                                SensorQuantity::kDisplacement);
  EXPECT_TRUE(a.mismatch) << a.exponent;
  EXPECT_EQ(a.likely, SensorQuantity::kAcceleration);
}

}  // namespace
}  // namespace podid
