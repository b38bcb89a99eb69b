// Typed parameters and the cached Simulator against the document path they
// replace: copy the case document, set the key, re-validate, Simulate().
#include "podid/core/simulator.hpp"

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "case_text.hpp"
#include "podid/core/case_file.hpp"
#include "podid/core/model_parameter.hpp"
#include "podid/core/simulate.hpp"
#include "reference_case.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

// Every typed kind at once: segments, a point mass, a spring, modal damping,
// a cubic element, a static initial deflection and a harmonic force.
const std::string kCase = R"([beam]
area = 0.196e-3
[[beam.segment]]
length = 0.3
elements = 3
youngs_modulus = 2.05e11
density = 7800.0
[[beam.segment]]
length = 0.293
elements = 3
youngs_modulus = 1.9e11
density = 7600.0
[[mass]]
node = 4
mass = 0.2
[[spring]]
node = 2
stiffness = 1.0e4
damping = 2.0
)" + testing::RayleighTable("[0.01, 0.02]") +
                          testing::CubicTable() + testing::InitialTable() + R"([force]
type = "harmonic"
node = 6
amplitude = 2.0
frequency = 30.0
)" + testing::TimeTable("0.05");

// The cached path runs the same operations on the same matrices (a rebuilt
// model is built by the same code; a nonlinear coefficient only changes the
// elements): equal up to round-off of a different evaluation order, if any.
constexpr double kRoundoffTolerance = 1e-12;

// Applies each (key, value) in turn to a Simulator of the case (a typed
// parameter) and to its document (copy-the-document path), and compares the
// two simulations after every change.
void ExpectChangesMatchTheDocumentPath(const std::string& text,
                                       const char* name,
                                       const std::vector<std::pair<std::string, double>>& changes) {
  CaseDocument document = CaseDocument::Parse(text, name);
  const CaseSpec base = document.ToSpec();
  Simulator simulator(base);
  for (const auto& [key, value] : changes) {
    const ModelParameter parameter = ModelParameter::Resolve(base, key);
    ASSERT_TRUE(parameter.typed()) << key;
    std::string why;
    ASSERT_TRUE(simulator.Set(parameter, value, &why)) << key << ": " << why;
    document.SetNumber(key, value);
    const SimulationResult expected = Simulate(document.ToSpec(), SimulateOptions{false});
    const SimulationResult actual = simulator.Run();
    ASSERT_TRUE(expected.summary.IsSolutionUsable()) << expected.summary.message;
    ASSERT_TRUE(actual.summary.IsSolutionUsable()) << actual.summary.message;
    ASSERT_EQ(actual.sensors.channel_names, expected.sensors.channel_names);
    const double scale = expected.sensors.values.cwiseAbs().maxCoeff();
    EXPECT_TRUE(testing::ExpectMatricesNear(actual.sensors.values / scale,
                                            expected.sensors.values / scale, kRoundoffTolerance))
        << "after " << key << " = " << value;
    EXPECT_EQ(actual.sensors.time_s, expected.sensors.time_s) << "after " << key;
  }
}

TEST(SimulatorTest, EveryTypedChangeMatchesTheDocumentPath) {
  const std::vector<std::pair<std::string, double>> changes = {
      {"nonlinearity.0.k3", 3.0e9},
      {"nonlinearity.0.k3", 8.0e9},
      {"damping.modal_ratios.0", 0.03},
      {"beam.segment.1.youngs_modulus", 2.2e11},
      {"beam.segment.0.density", 7000.0},
      {"mass.0.mass", 0.5},
      {"spring.0.stiffness", 3.0e4},
      {"spring.0.damping", 5.0},
      {"force.amplitude", -1.0},
      {"force.frequency", 45.0},
      {"initial.static_tip_force", 15.0},
      {"nonlinearity.0.k3", 5.0e9},
  };
  ExpectChangesMatchTheDocumentPath(kCase, "simulator_test", changes);
}

// A uniform beam (no segments) with Rayleigh damping given by alpha and beta,
// a polynomial element and a sweep: the remaining typed keys.
const std::string kUniformCase = testing::BeamTable() + R"([damping]
type = "rayleigh"
alpha = 2.0
beta = 1.0e-5
[[nonlinearity]]
type = "polynomial"
node = 6
k1 = 1.0e3
k2 = 1.0e6
k3 = 5.0e9
[force]
type = "sweep"
node = 6
amplitude = 5.0
start_frequency = 20.0
end_frequency = 60.0
)" + testing::TimeTable("0.05");

TEST(SimulatorTest, UniformBeamRayleighPolynomialAndSweepKeysMatchTheDocumentPath) {
  const std::vector<std::pair<std::string, double>> changes = {
      {"beam.youngs_modulus", 1.9e11},  {"beam.density", 7000.0},
      {"damping.alpha", 5.0},           {"damping.beta", 2.0e-5},
      {"nonlinearity.0.k1", 2.0e3},     {"nonlinearity.0.k2", -1.0e6},
      {"force.start_frequency", 25.0},  {"force.end_frequency", 80.0},
  };
  ExpectChangesMatchTheDocumentPath(kUniformCase, "simulator_test_uniform", changes);
}

TEST(SimulatorTest, RunInPlaceGivesRunsSensorsWithoutTheCopy) {
  // What the objective reads (the recording's top rows) is what Run() copies
  // out: the same simulation, so the same bits; and after a change of k3.
  Simulator simulator(testing::ReferenceCase({"sensors.quantity=\"acceleration\""}));
  const ModelParameter k3 = ModelParameter::Resolve(simulator.spec(), "nonlinearity.0.k3");
  for (const double value : {5e9, 4e9}) {
    std::string why;
    ASSERT_TRUE(simulator.Set(k3, value, &why)) << why;
    const SimulationResult copied = simulator.Run();
    ASSERT_TRUE(copied.summary.IsSolutionUsable()) << copied.summary.message;
    const SimulationSummary& summary = simulator.RunInPlace();
    ASSERT_TRUE(summary.IsSolutionUsable()) << summary.message;
    EXPECT_EQ(summary.rows_recorded, copied.summary.rows_recorded);
    EXPECT_TRUE(Eigen::MatrixXd(simulator.sensor_values()) == copied.sensors.values);
  }
}

// Several forces and base excitation: force.i.* and base.* are kLoad keys; a
// change of the mass (kModel) also changes the base's load -M r a_g.
const std::string kForcesAndBaseCase = testing::BeamTable() + R"([[mass]]
node = 4
mass = 0.2
)" + testing::RayleighTable("[0.01, 0.02]") +
                                       testing::CubicTable() +
                                       R"([[force]]
type = "harmonic"
node = 6
amplitude = 2.0
frequency = 30.0
[[force]]
type = "sweep"
node = 3
amplitude = 1.0
start_frequency = 10.0
end_frequency = 80.0
[base]
type = "harmonic"
amplitude = 5.0
frequency = 25.0
[sensors]
quantity = "acceleration"
)" + testing::TimeTable("0.05");

// Each key resolves to a parameter of the case with the given effect.
void ExpectEffects(const CaseSpec& spec,
                   const std::vector<std::pair<std::string, ParameterEffect>>& effects) {
  for (const auto& [key, effect] : effects) {
    EXPECT_EQ(ModelParameter::Resolve(spec, key).effect(), effect) << key;
  }
}

// Each key is refused by Resolve with a message that contains its needle.
void ExpectKeysRejected(const CaseSpec& spec,
                        const std::vector<std::pair<std::string, std::string>>& needles) {
  for (const auto& [key, needle] : needles) {
    SCOPED_TRACE(key);
    PODID_EXPECT_THROW_WITH(ModelParameter::Resolve(spec, key), std::invalid_argument, needle);
  }
}

TEST(SimulatorTest, ForceArrayAndBaseKeysMatchTheDocumentPath) {
  const std::vector<std::pair<std::string, double>> changes = {
      {"force.0.amplitude", -1.0}, {"force.1.end_frequency", 120.0}, {"base.amplitude", 9.0},
      {"base.frequency", 40.0},    {"mass.0.mass", 0.6},             {"force.0.frequency", 45.0},
  };
  ExpectChangesMatchTheDocumentPath(kForcesAndBaseCase, "simulator_test", changes);
  const CaseSpec spec = CaseDocument::Parse(kForcesAndBaseCase, "simulator_test").ToSpec();
  ExpectEffects(spec, {{"force.1.amplitude", ParameterEffect::kLoad},
                       {"base.amplitude", ParameterEffect::kLoad}});
  const std::vector<std::pair<std::string, std::string>> refused = {
      {"force.2.amplitude", "an index of the case's [[force]] tables (0..1)"},
      {"force.amplitude", "the case has [[force]] tables: force.<i>.amplitude"},
      {"force.0.gain", "a value the case's force.type does not have"},
      {"base.start_frequency", "a value the case's base.type does not have"},
  };
  ExpectKeysRejected(spec, refused);
  // The objective's path (RunInPlace, no copy) sees the absolute accelerations too.
  Simulator simulator(spec);
  const SimulationResult copied = simulator.Run();
  ASSERT_TRUE(simulator.RunInPlace().IsSolutionUsable());
  EXPECT_TRUE(Eigen::MatrixXd(simulator.sensor_values()) == copied.sensors.values);
  CaseDocument relative_doc = CaseDocument::Parse(kForcesAndBaseCase, "simulator_test");
  ApplySetArguments(relative_doc, {"sensors.reference=relative"});
  const SimulationResult relative = Simulate(relative_doc.ToSpec(), SimulateOptions{false});
  EXPECT_FALSE(relative.sensors.values == copied.sensors.values);
}

TEST(ModelParameterTest, ResolvesEachKeyOnceWithWhatItInvalidates) {
  const CaseSpec spec = CaseDocument::Parse(kCase, "simulator_test").ToSpec();
  const std::vector<std::pair<std::string, ParameterEffect>> effects = {
      {"nonlinearity.0.k3", ParameterEffect::kNonlinear},
      {"damping.modal_ratios.1", ParameterEffect::kDamping},
      {"mass.0.mass", ParameterEffect::kModel},
      {"force.amplitude", ParameterEffect::kLoad},
      {"initial.static_tip_force", ParameterEffect::kInitialState},
      // A real-valued key without a typed binding goes through the document.
      {"beam.segment.0.length", ParameterEffect::kDocument},
  };
  ExpectEffects(spec, effects);
  // Keys the case cannot take.
  const std::vector<std::pair<std::string, std::string>> refused = {
      {"nonlinearity.2.k3",
       "parameter key nonlinearity.2.k3: expected an index of the case's "
       "[[nonlinearity]] tables (0..0), got 2"},
      {"nonlinearity.0.k1", "a coefficient the element's type does not have"},
      {"damping.alpha", "damping given by modal_ratios"},
      {"beam.elements", "parameter key: expected a real-valued case-file key"},
      {"force.start_frequency", "force.start_frequency"},
  };
  ExpectKeysRejected(spec, refused);
}

TEST(ModelParameterTest, ValuesOutOfRangeAreRejectedWithTheReasonAndLeaveTheCase) {
  const CaseSpec base = CaseDocument::Parse(kCase, "simulator_test").ToSpec();
  Simulator simulator(base);
  std::string why;
  const ModelParameter zeta = ModelParameter::Resolve(base, "damping.modal_ratios.0");
  EXPECT_FALSE(simulator.Set(zeta, -0.5, &why));
  EXPECT_EQ(why, "damping.modal_ratios.0: expected a damping ratio in [0, 1), got -0.5");
  const ModelParameter modulus = ModelParameter::Resolve(base, "beam.segment.0.youngs_modulus");
  EXPECT_FALSE(simulator.Set(modulus, 0.0, &why));
  EXPECT_EQ(why, "beam.segment.0.youngs_modulus: expected a finite value > 0, got 0");
  EXPECT_EQ(simulator.spec().damping.modal_ratios[0], 0.01);
  EXPECT_EQ(simulator.spec().beam.segments[0].youngs_modulus_Pa, 2.05e11);
}

}  // namespace
}  // namespace podid
