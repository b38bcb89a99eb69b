// Several forces at once ([[force]]): the reader, the load, superposition on a
// linear beam against single-force runs, and the errors a user can make.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "case_text.hpp"
#include "podid/core/case_file.hpp"
#include "podid/core/load.hpp"
#include "podid/core/simulate.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

using testing::TempDir;

// The reference beam made linear (k3 = 0), from rest, no damping change.
const std::string kLinearBeam = testing::BeamTable() + testing::RayleighTable() +
                                testing::CubicTable("0.0") + testing::TimeTable("0.05") +
                                "[integrator]\nsubsteps = 3\n";

constexpr const char* kHarmonicAt3 = R"(type = "harmonic"
node = 3
amplitude = 4.0
frequency = 70.0
)";
constexpr const char* kSweepAt6 = R"(type = "sweep"
node = 6
amplitude = -2.5
start_frequency = 20.0
end_frequency = 200.0
)";
constexpr const char* kFileAt5 = R"(type = "file"
node = 5
file = "f.csv"
column = "volts"
gain = 3.0
offset = 0.5
)";

// A measured force of 1 ms samples: a band-limited tone in volts.
std::string ForceCsv() {
  std::string text = "t,volts\n";
  for (int i = 0; i <= 60; ++i) {
    const double t = i * 1e-3;
    text += std::to_string(t) + "," + std::to_string(std::sin(2 * 3.141592653589793 * 40 * t)) + "\n";
  }
  return text;
}

SimulationResult RunCase(const TempDir& dir, const std::string& name, const std::string& forces) {
  const std::string path = dir.Write(name, kLinearBeam + forces);
  const SimulationResult r = Simulate(CaseDocument::Load(path).ToSpec(), SimulateOptions{false});
  EXPECT_TRUE(r.summary.IsSolutionUsable()) << r.summary.message;
  return r;
}

TEST(MultiForceTest, ResponseToSeveralForcesIsTheSumOfSingleForceResponses) {
  // A linear structure from rest: x(F1 + F2 + F3) = x(F1) + x(F2) + x(F3).
  // Each step solves the same linear system (Newton on the condensed dof of
  // a k3 = 0 element converges to round-off in one iteration, tolerance
  // 1e-10 of the residual scale), so the sums agree to that tolerance times
  // the response: 1e-9 of the largest displacement leaves a margin of 10.
  constexpr double kSuperpositionTolerance = 1e-9;
  const TempDir dir;
  dir.Write("f.csv", ForceCsv());
  const SimulationResult all = RunCase(dir, "all.toml",
                                   std::string("[[force]]\n") + kHarmonicAt3 + "[[force]]\n" +
                                       kSweepAt6 + "[[force]]\n" + kFileAt5);
  const SimulationResult one = RunCase(dir, "one.toml", std::string("[force]\n") + kHarmonicAt3);
  const SimulationResult two = RunCase(dir, "two.toml", std::string("[[force]]\n") + kSweepAt6);
  const SimulationResult three = RunCase(dir, "three.toml", std::string("[force]\n") + kFileAt5);
  const Eigen::MatrixXd sum = one.sensors.values + two.sensors.values + three.sensors.values;
  const double scale = all.sensors.values.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.0);
  // Each force matters (none is negligible against the tolerance).
  for (const auto* single : {&one, &two, &three})
    EXPECT_GT(single->sensors.values.cwiseAbs().maxCoeff(), 1e-3 * scale);
  EXPECT_TRUE(testing::ExpectMatricesNear(all.sensors.values / scale, sum / scale, kSuperpositionTolerance));
}

TEST(MultiForceTest, LoadHasOneColumnPerForceWithItsOwnGainAndOffset) {
  constexpr double kRoundOff = 1e-12;  // the same formula evaluated twice
  const TempDir dir;
  dir.Write("f.csv", ForceCsv());
  const std::string path = dir.Write(
      "case.toml", kLinearBeam + "[[force]]\n" + kHarmonicAt3 + "[[force]]\ntype = \"none\"\n" +
                       "[[force]]\n" + kFileAt5);
  const CaseSpec spec = CaseDocument::Load(path).ToSpec();
  ASSERT_EQ(spec.forces.size(), 3u);
  EXPECT_EQ(spec.forces[2].history_N.gain, 3.0);
  EXPECT_EQ(spec.forces[2].history_N.offset, 0.5);
  const ExternalLoad load = BuildLoad(spec);
  ASSERT_EQ(load.columns(), 2);  // "none" adds nothing
  EXPECT_EQ(load.history.cols(), 250 * 3 + 1);  // the fine grid (substeps = 3)
  EXPECT_EQ(load.pattern.coeff(TransverseDof(3), 0), 1.0);
  EXPECT_EQ(load.pattern.coeff(TransverseDof(5), 1), 1.0);
  EXPECT_EQ(load.pattern.nonZeros(), 2);
  // On the data's grid (every third fine sample) the file force is gain x
  // volts + offset exactly at the file's samples (t = 1 ms = 5 steps).
  EXPECT_NEAR(load.history(1, 3 * 5), 3.0 * spec.forces[2].history_N.file_values[1] + 0.5,
              kRoundOff);
  EXPECT_NEAR(load.history(0, 7), 4.0 * std::sin(2 * 3.141592653589793 * 70.0 * 7 * 2e-4 / 3), kRoundOff);
}

CaseSpec Spec(const std::string& text) { return CaseDocument::Parse(text, "forces.toml").ToSpec(); }

TEST(MultiForceTest, ErrorsNameTheForceAndWhatWasExpected) {
  const std::string beam = kLinearBeam;
  // A node out of range in the second table.
  PODID_EXPECT_THROW_WITH(
      Spec(beam + "[[force]]\n" + kHarmonicAt3 + "[[force]]\ntype = \"harmonic\"\nnode = 9\namplitude = 1\n"
                  "frequency = 5\n"),
      std::invalid_argument, "force.1.node: expected an integer in [1, 6]");
  // A key of another type.
  PODID_EXPECT_THROW_WITH(Spec(beam + "[[force]]\n" + kHarmonicAt3 + "gain = 2\n"), std::invalid_argument,
                          "force.0.gain: expected only the keys type, node, dof, amplitude, frequency");
  // More than kMaxForces tables.
  std::string many = beam;
  for (int i = 0; i <= kMaxForces; ++i) many += std::string("[[force]]\n") + kHarmonicAt3;
  PODID_EXPECT_THROW_WITH(Spec(many), std::invalid_argument, "force: expected at most 64 [[force]] tables, got 65");
  // [force] and [[force]] together are not TOML.
  EXPECT_THROW(Spec(beam + "[force]\n" + kHarmonicAt3 + "[[force]]\n" + kSweepAt6), std::invalid_argument);
  // A channel that the [data] file does not have.
  const TempDir dir;
  dir.Write("data.csv", "t,a,b\n0,0,0\n0.1,1,1\n");
  const std::string path = dir.Write(
      "case.toml", beam + "[data]\nfile = \"data.csv\"\n[[force]]\n" + kHarmonicAt3 +
                       "[[force]]\ntype = \"channel\"\nchannel = \"c\"\nnode = 2\n");
  PODID_EXPECT_THROW_WITH(CaseDocument::Load(path).ToSpec(), std::invalid_argument,
                          "force.1.channel: expected a channel of");
}

TEST(MultiForceTest, SetAddressesForcesByIndex) {
  CaseDocument doc = CaseDocument::Parse(kLinearBeam + "[[force]]\n" + kHarmonicAt3, "f.toml");
  ApplySetArguments(doc, {"force.1.type=sweep", "force.1.node=2", "force.1.amplitude=1",
                          "force.1.start_frequency=5", "force.1.end_frequency=50", "force.0.amplitude=7"});
  const CaseSpec spec = doc.ToSpec();
  ASSERT_EQ(spec.forces.size(), 2u);
  EXPECT_EQ(spec.forces[0].history_N.amplitude, 7.0);
  EXPECT_EQ(spec.forces[1].history_N.type, ForceType::kSweep);
  EXPECT_EQ(spec.forces[1].node, 2);
  // --set on a case without forces creates the array.
  CaseDocument fresh = CaseDocument::Parse(kLinearBeam, "f.toml");
  ApplySetArguments(fresh, {"force.0.type=harmonic", "force.0.amplitude=1", "force.0.frequency=3"});
  EXPECT_EQ(fresh.ToSpec().forces.size(), 1u);
}

TEST(MultiForceTest, FuzzSeedWithForcesAndBaseIsAValidCase) {
  // The case fuzzer's seed for these keys must reach the load and sensor
  // code, not stop at a typo: its TOML part (before "---") is a valid case.
  std::ifstream in(testing::ExamplePath("../fuzz/corpus/case/forces_base.toml"), std::ios::binary);
  ASSERT_TRUE(in);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const CaseSpec spec = Spec(text.substr(0, text.find("\n---\n")));
  EXPECT_EQ(spec.forces.size(), 3u);
  EXPECT_EQ(spec.base.history_m_per_s2.type, ForceType::kHarmonic);
  EXPECT_EQ(spec.parameters.size(), 2u);
  EXPECT_TRUE(Simulate(spec).summary.IsSolutionUsable());
}

}  // namespace
}  // namespace podid
