// Case files: loading the reference case, --set overrides, SetNumber, and one
// test for each rejection of issue 2's "Case files and data".
#include "podid/core/case_file.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "case_text.hpp"
#include "podid/core/beam_model.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

using testing::ExamplePath;
using testing::TempDir;

// The reference case without comments, a blank line between its tables; the
// line numbers matter for the messages checked below: [beam] at line 1,
// [damping] 8, [[nonlinearity]] 12, [initial] 17, [time] 20, [sensors] 24,
// [noise] 27, [[identify.parameter]] 31; text appended starts at line 38.
const std::string kBase = testing::BeamTable() + "\n" + testing::RayleighTable() + "\n" +
                          testing::CubicTable() + "\n" + testing::InitialTable() + "\n" +
                          testing::TimeTable() + "\n" + testing::SensorsTable() + "\n" +
                          testing::NoiseTable() + "\n" + testing::IdentifyK3Table();

/// kBase with the first occurrence of `from` replaced by `to` (which must exist).
std::string Edit(const std::string& from, const std::string& to) {
  std::string text = kBase;
  const auto at = text.find(from);
  if (at == std::string::npos) throw std::logic_error("Edit: no '" + from + "' in kBase");
  return text.replace(at, from.size(), to);
}

CaseSpec SpecOf(const std::string& text) { return CaseDocument::Parse(text, "case.toml").ToSpec(); }

#define EXPECT_CASE_ERROR(text, needle) \
  PODID_EXPECT_THROW_WITH(SpecOf(text), std::invalid_argument, needle)

TEST(CaseFile, LoadsTheReferenceCaseExactly) {
  const CaseSpec spec = CaseDocument::Load(ExamplePath("beam.toml")).ToSpec();
  EXPECT_EQ(spec.source, ExamplePath("beam.toml"));
  // Values are the file's decimal literals: parsed exactly, compared exactly.
  EXPECT_EQ(spec.beam.length_m, 0.593);
  EXPECT_EQ(spec.beam.elements, 6);
  EXPECT_EQ(spec.beam.youngs_modulus_Pa, 2.05e11);
  EXPECT_EQ(spec.beam.density_kg_per_m3, 7800.0);
  EXPECT_EQ(spec.beam.area_m2, 0.196e-3);
  EXPECT_EQ(spec.beam.second_moment_m4, 0.196e-3 * 0.196e-3 / 12.0);
  EXPECT_EQ(spec.damping.type, DampingType::kRayleigh);
  EXPECT_TRUE(spec.damping.from_modal_ratios);
  EXPECT_EQ(spec.damping.modal_ratios[0], 0.01);
  EXPECT_EQ(spec.damping.modal_ratios[1], 0.01);
  EXPECT_EQ(spec.damping.modes[0], 1);
  EXPECT_EQ(spec.damping.modes[1], 2);
  ASSERT_EQ(spec.nonlinearities.size(), 1u);
  EXPECT_EQ(spec.nonlinearities[0].type, NonlinearType::kCubic);
  EXPECT_EQ(spec.nonlinearities[0].node, 6);
  EXPECT_EQ(spec.nonlinearities[0].k3_N_per_m3, 5.0e9);
  EXPECT_EQ(spec.initial.type, InitialType::kStaticForce);
  EXPECT_EQ(spec.initial.static_force_N, 20.0);
  EXPECT_EQ(spec.initial.static_force_node, 6);
  EXPECT_EQ(spec.force.history_N.type, ForceType::kNone);
  EXPECT_EQ(spec.time.duration_s, 0.1);
  EXPECT_EQ(spec.time.step_s, 2.0e-4);
  EXPECT_EQ(spec.time.samples(), 501);
  EXPECT_EQ(spec.sensors.dof, SensorDof::kW);
  EXPECT_EQ(spec.sensors.nodes, (std::vector<int>{1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(spec.sensors.ChannelNames(),
            (std::vector<std::string>{"w1", "w2", "w3", "w4", "w5", "w6"}));
  EXPECT_EQ(spec.noise.relative, 0.0);
  EXPECT_EQ(spec.noise.seed, 1u);
  EXPECT_EQ(spec.integrator.type, IntegratorType::kModifiedNewmark);
  EXPECT_EQ(spec.integrator.gamma, 0.5);
  EXPECT_EQ(spec.integrator.beta, 0.25);
  EXPECT_EQ(spec.integrator.tolerance, 1e-10);
  EXPECT_EQ(spec.integrator.max_iterations, 50);
  ASSERT_EQ(spec.parameters.size(), 1u);
  EXPECT_EQ(spec.parameters[0].name, "knl");
  EXPECT_EQ(spec.parameters[0].key, "nonlinearity.0.k3");
  EXPECT_EQ(spec.parameters[0].scale, 1.0e8);
  EXPECT_EQ(spec.parameters[0].start, 40.0);
  EXPECT_EQ(spec.parameters[0].lower, 0.0);
  EXPECT_EQ(spec.parameters[0].upper, 200.0);
  EXPECT_EQ(spec.dofs(), 12);
}

TEST(CaseFile, EveryOptionalSection) {
  const std::string text = R"([beam]
length = 1
elements = 4
youngs_modulus = 2e11
density = 7800
width = 0.02
height = 0.01
[damping]
type = "rayleigh"
alpha = 0.5
[[nonlinearity]]
type = "polynomial"
node = 2
k2 = -1e6
k3 = 3e9
[[nonlinearity]]
type = "gap"
gap = 1e-3
stiffness = 1e6
[[nonlinearity]]
type = "friction"
node = 3
mu = 0.3
normal_force = 10
velocity_scale = 1e-3
[initial]
velocity = [0, 0, 0, 0, 0, 0, 1, 0]
[force]
type = "sweep"
node = 1
amplitude = 2
start_frequency = 5
end_frequency = 50
[time]
duration = 1
step = 1e-3
[sensors]
dof = "theta"
nodes = [4, 2]
[noise]
relative = 0.01
seed = 0
[integrator]
type = "newmark"
gamma = 0.6
beta = 0.3025
tolerance = 1e-8
max_iterations = 20
)";
  const CaseSpec spec = SpecOf(text);
  EXPECT_EQ(spec.beam.area_m2, 0.02 * 0.01);
  EXPECT_EQ(spec.beam.second_moment_m4, 0.02 * std::pow(0.01, 3) / 12.0);
  EXPECT_FALSE(spec.damping.from_modal_ratios);
  EXPECT_EQ(spec.damping.alpha_per_s, 0.5);
  EXPECT_EQ(spec.damping.beta_s, 0.0);
  ASSERT_EQ(spec.nonlinearities.size(), 3u);
  EXPECT_EQ(spec.nonlinearities[0].type, NonlinearType::kPolynomial);
  EXPECT_EQ(spec.nonlinearities[0].k1_N_per_m, 0.0);
  EXPECT_EQ(spec.nonlinearities[0].k2_N_per_m2, -1e6);
  EXPECT_EQ(spec.nonlinearities[1].type, NonlinearType::kGap);
  EXPECT_EQ(spec.nonlinearities[1].node, 4);  // default: the free end
  EXPECT_EQ(spec.nonlinearities[1].gap_m, 1e-3);
  EXPECT_EQ(spec.nonlinearities[1].contact_stiffness_N_per_m, 1e6);
  EXPECT_EQ(spec.nonlinearities[2].friction_coefficient, 0.3);
  EXPECT_EQ(spec.nonlinearities[2].normal_force_N, 10.0);
  EXPECT_EQ(spec.nonlinearities[2].regularisation_velocity_m_per_s, 1e-3);
  EXPECT_EQ(spec.initial.type, InitialType::kExplicit);
  EXPECT_EQ(spec.initial.displacement.size(), 8);
  EXPECT_EQ(spec.initial.displacement.norm(), 0.0);
  EXPECT_EQ(spec.initial.velocity(TransverseDof(4)), 1.0);
  EXPECT_EQ(spec.force.history_N.type, ForceType::kSweep);
  EXPECT_EQ(spec.force.node, 1);
  EXPECT_EQ(spec.force.history_N.end_frequency_Hz, 50.0);
  EXPECT_EQ(spec.sensors.ChannelNames(), (std::vector<std::string>{"theta4", "theta2"}));
  EXPECT_EQ(spec.noise.seed, 0u);
  EXPECT_EQ(spec.integrator.type, IntegratorType::kNewmark);
  EXPECT_EQ(spec.integrator.max_iterations, 20);
  EXPECT_TRUE(spec.parameters.empty());
}

TEST(CaseFile, MinimalCaseTakesDefaults) {
  const CaseSpec spec = SpecOf(
      "[beam]\nlength=1\nelements=2\nyoungs_modulus=1\ndensity=1\narea=1\n"
      "[time]\nduration=1\nstep=0.3\n");
  EXPECT_EQ(spec.damping.type, DampingType::kNone);
  EXPECT_TRUE(spec.nonlinearities.empty());
  EXPECT_EQ(spec.initial.type, InitialType::kRest);
  EXPECT_EQ(spec.force.history_N.type, ForceType::kNone);
  EXPECT_EQ(spec.time.samples(), 4);  // round(1 / 0.3) + 1
  EXPECT_EQ(spec.sensors.nodes, (std::vector<int>{1, 2}));
  EXPECT_EQ(spec.noise.relative, 0.0);
  EXPECT_EQ(spec.noise.seed, 1u);
}

TEST(CaseFile, ForceFromCsvRelativeToTheCaseFile) {
  const TempDir dir;
  std::filesystem::create_directory(dir.File("data"));
  dir.Write("data/force.csv", "t,f\n0,0\n0.5,1\n1,4\n");
  const std::string harmonic = kBase +
                               "[force]\ntype = \"file\"\nfile = "
                               "\"data/force.csv\"\ncolumn = \"f\"\nnode = 3\n";
  const std::string path = dir.Write("case.toml", harmonic);
  const CaseSpec spec = CaseDocument::Load(path).ToSpec();
  EXPECT_EQ(spec.force.history_N.type, ForceType::kFile);
  EXPECT_EQ(spec.force.node, 3);
  EXPECT_EQ(spec.force.history_N.file, "data/force.csv");
  EXPECT_EQ(spec.force.history_N.file_time_s, Eigen::Vector3d(0, 0.5, 1));
  EXPECT_EQ(spec.force.history_N.file_values, Eigen::Vector3d(0, 1, 4));

  // A column that the file lacks, and a file that does not exist.
  CaseDocument doc = CaseDocument::Load(path);
  doc.Set("force.column", "\"g\"");
  PODID_EXPECT_THROW_WITH(doc.ToSpec(), std::invalid_argument,
                          "--set force.column=\"g\": force.column: expected a column of");
  doc = CaseDocument::Load(path);
  doc.Set("force.file", "\"nope.csv\"");
  PODID_EXPECT_THROW_WITH(doc.ToSpec(), std::invalid_argument, "force.file: ");
  PODID_EXPECT_THROW_WITH(doc.ToSpec(), std::invalid_argument, "nope.csv");
}

// --- --set and SetNumber ----------------------------------------------------

TEST(CaseFileSet, OverridesKeysFromTheCommandLine) {
  CaseDocument doc = CaseDocument::Parse(kBase, "case.toml");
  ApplySetArguments(
      doc,
      {"nonlinearity.0.k3=2.5e9", "time.duration=1.0", "damping.modal_ratios.1=0.02",
       "sensors.nodes=[6, 3]", "integrator.type=newmark", "integrator.tolerance=1e-6",
       "force.type=\"harmonic\"", "force.amplitude=1", "force.frequency=30", "beam.elements = 8"});
  const CaseSpec spec = doc.ToSpec();
  EXPECT_EQ(spec.nonlinearities[0].k3_N_per_m3, 2.5e9);
  EXPECT_EQ(spec.time.duration_s, 1.0);
  EXPECT_EQ(spec.damping.modal_ratios[1], 0.02);
  EXPECT_EQ(spec.sensors.nodes, (std::vector<int>{6, 3}));
  EXPECT_EQ(spec.integrator.type, IntegratorType::kNewmark);
  EXPECT_EQ(spec.integrator.tolerance, 1e-6);
  EXPECT_EQ(spec.force.history_N.type, ForceType::kHarmonic);
  EXPECT_EQ(spec.force.node, 8);
  EXPECT_EQ(spec.beam.elements, 8);
}

TEST(CaseFileSet, AppendsAnArrayElementAtTheNextIndex) {
  CaseDocument doc = CaseDocument::Parse(kBase, "case.toml");
  doc.Set("nonlinearity.1.type", "gap");
  doc.Set("nonlinearity.1.gap", "0.001");
  doc.Set("nonlinearity.1.stiffness", "1e7");
  doc.Set("nonlinearity.1.node", "3");
  const CaseSpec spec = doc.ToSpec();
  ASSERT_EQ(spec.nonlinearities.size(), 2u);
  EXPECT_EQ(spec.nonlinearities[1].type, NonlinearType::kGap);
  EXPECT_EQ(spec.nonlinearities[1].node, 3);
  // An appended element that is incomplete is reported at its --set.
  doc.Set("nonlinearity.2.type", "friction");
  PODID_EXPECT_THROW_WITH(doc.ToSpec(), std::invalid_argument,
                          "nonlinearity.2.mu: expected a number >= 0, got nothing");
}

// A --set that CaseDocument::Set refuses: key, value, a part of the message.
struct SetRejection {
  std::string_view key, value, needle;
};

// Applies each --set in turn to one document of kBase; each must be refused.
void ExpectSetsRejected(const std::vector<SetRejection>& rejections) {
  CaseDocument doc = CaseDocument::Parse(kBase, "case.toml");
  for (const auto& [key, value, needle] : rejections) {
    SCOPED_TRACE(std::string(key) + "=" + std::string(value));
    PODID_EXPECT_THROW_WITH(doc.Set(key, value), std::invalid_argument, std::string(needle));
  }
}

TEST(CaseFileSet, RejectsKeysOutsideTheSchema) {
  ExpectSetsRejected({
      {"beam.lenght", "1", "--set beam.lenght=1: expected a key of the case-file schema"},
      {"nonlinearity.k3", "1", "the unknown key \"nonlinearity.k3\""},
      {"beam..length", "1", "expected a dotted key"},
      {"", "1", "expected a dotted key"},
      {"nonlinearity.5.k3", "1",
       "--set nonlinearity.5.k3=1: expected an index <= 1 into nonlinearity"},
      {"damping.modal_ratios.7", "0.1", "expected an index <= 2 into damping.modal_ratios"},
  });
}

TEST(CaseFileSet, RejectsValuesThatAreNotToml) {
  ExpectSetsRejected({
      {"beam.length", "1.2.3", "--set beam.length=1.2.3: expected a TOML value"},
      {"beam.length", "", "expected a TOML value"},
      {"time.step", "1\nx = 2", "expected a TOML value"},
  });
}

TEST(CaseFileSet, WrongValueIsReportedAtTheSet) {
  CaseDocument doc = CaseDocument::Parse(kBase, "case.toml");
  doc.Set("beam.elements", "0");
  PODID_EXPECT_THROW_WITH(doc.ToSpec(), std::invalid_argument,
                          "--set beam.elements=0: beam.elements: expected an integer in [1, "
                          "1000], got 0");
  doc = CaseDocument::Parse(kBase, "case.toml");
  doc.Set("time.step", "\"fast\"");
  PODID_EXPECT_THROW_WITH(doc.ToSpec(), std::invalid_argument,
                          "--set time.step=\"fast\": time.step: expected a number > 0 (s), got "
                          "\"fast\"");
  // A bare word is a string only where the schema wants a string.
  PODID_EXPECT_THROW_WITH(doc.Set("time.step", "fast"), std::invalid_argument,
                          "expected a TOML value");
}

TEST(CaseFileSet, ParseSetArguments) {
  const auto pairs = ParseSetArguments({"a.b=1", " time.step = 2e-4 ", "x=y=z"});
  ASSERT_EQ(pairs.size(), 3u);
  EXPECT_EQ(pairs[0], (std::pair<std::string, std::string>{"a.b", "1"}));
  EXPECT_EQ(pairs[1], (std::pair<std::string, std::string>{"time.step", "2e-4"}));
  EXPECT_EQ(pairs[2], (std::pair<std::string, std::string>{"x", "y=z"}));
  PODID_EXPECT_THROW_WITH(ParseSetArguments({"time.step"}), std::invalid_argument,
                          "--set time.step: expected key=value");
  PODID_EXPECT_THROW_WITH(ParseSetArguments({"=3"}), std::invalid_argument, "expected key=value");
}

TEST(CaseFileSet, SetNumberAndGetNumber) {
  CaseDocument doc = CaseDocument::Parse(kBase, "case.toml");
  EXPECT_EQ(doc.GetNumber("nonlinearity.0.k3"), 5.0e9);
  EXPECT_EQ(doc.GetNumber("beam.elements"), 6.0);
  EXPECT_EQ(doc.GetNumber("damping.modal_ratios.1"), 0.01);
  doc.SetNumber("nonlinearity.0.k3", 4.2e9);
  doc.SetNumber("damping.modal_ratios.0", 0.03);
  doc.SetNumber("integrator.tolerance", 1e-9);  // absent from the file: created
  EXPECT_TRUE(doc.Has("integrator.tolerance"));
  EXPECT_FALSE(doc.Has("integrator.gamma"));
  const CaseSpec spec = doc.ToSpec();
  EXPECT_EQ(spec.nonlinearities[0].k3_N_per_m3, 4.2e9);
  EXPECT_EQ(spec.damping.modal_ratios[0], 0.03);
  EXPECT_EQ(spec.integrator.tolerance, 1e-9);
  // Integer and string keys are not numeric parameters.
  EXPECT_TRUE(CaseDocument::IsNumericKey("initial.displacement.3"));
  EXPECT_FALSE(CaseDocument::IsNumericKey("beam.elements"));
  EXPECT_FALSE(CaseDocument::IsNumericKey("force.type"));
  EXPECT_FALSE(CaseDocument::IsNumericKey("beam"));
  PODID_EXPECT_THROW_WITH(doc.SetNumber("beam.elements", 7), std::invalid_argument,
                          "expected a real-valued key");
  PODID_EXPECT_THROW_WITH(doc.GetNumber("force.amplitude"), std::invalid_argument,
                          "force.amplitude: expected a number, got nothing");
  PODID_EXPECT_THROW_WITH(doc.GetNumber("sensors.dof"), std::invalid_argument,
                          "case.toml:25: sensors.dof: expected a number, got \"w\"");
  // A value made invalid by SetNumber is reported as such.
  doc.SetNumber("beam.length", -1.0);
  PODID_EXPECT_THROW_WITH(doc.ToSpec(), std::invalid_argument,
                          "(beam.length set by the program): beam.length: expected a number > 0 "
                          "(m), got -1");
}

TEST(CaseFileSet, CopiesAreIndependentAndUsableFromThreads) {
  const CaseDocument base = CaseDocument::Parse(kBase, "case.toml");
  constexpr int kThreads = 4;
  constexpr int kEvaluations = 200;
  std::vector<int> wrong(kThreads, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t]() {
      for (int i = 0; i < kEvaluations; ++i) {
        CaseDocument copy = base;
        const double k3 = 1e9 * (t + 1) + i;
        copy.SetNumber("nonlinearity.0.k3", k3);
        if (copy.ToSpec().nonlinearities[0].k3_N_per_m3 != k3) ++wrong[t];
      }
    });
  }
  for (auto& thread : threads) thread.join();
  for (int t = 0; t < kThreads; ++t) EXPECT_EQ(wrong[t], 0) << "thread " << t;
  EXPECT_EQ(base.GetNumber("nonlinearity.0.k3"), 5.0e9);
  // Copies keep the file's line numbers for their messages.
  CaseDocument copy = base;
  copy.Set("noise.seed", "1");
  CaseDocument copy2 = copy;
  copy2.Set("beam.density", "1");  // unrelated
  EXPECT_EQ(copy2.GetNumber("beam.density"), 1.0);
  CaseDocument bad = CaseDocument::Parse(Edit("elements = 6", "elements = 0"), "case.toml");
  const CaseDocument bad_copy = bad;
  PODID_EXPECT_THROW_WITH(bad_copy.ToSpec(), std::invalid_argument, "case.toml:3: beam.elements");
}

// --- rejections: one row per invalid edit of kBase --------------------------

// kBase with the first `from` replaced by `to` (or with `to` appended where
// `from` is empty) must be refused with a message that contains `needle`;
// `test` names the CaseFileRejects test that checks the row.
struct Rejection {
  std::string_view test, from, to, needle;
};

constexpr Rejection kRejections[] = {
    {"InvalidToml", "length = 0.593", "length = ", "case.toml:2:"},
    {"InvalidToml", "length = 0.593", "length = ", "expected valid TOML"},
    {"InvalidToml", "elements = 6", "elements = 6\nlength = 1", "case.toml:4:"},  // duplicate key
    {"UnknownKeys", "length = 0.593", "lenght = 0.593",
     "case.toml:2: beam.lenght: expected a key of the case-file schema (here: length, elements, "
     "youngs_modulus, density, area, width, height, left, right, segment, second_moment), got an "
     "unknown key"},
    {"UnknownKeys", "[noise]", "[noisy]", "case.toml:27: noisy: expected a key"},
    {"UnknownKeys", "k3 = 5.0e9", "k3 = 5.0e9\nk4 = 1",
     "case.toml:16: nonlinearity.0.k4: expected a key"},
    {"UnknownKeys", "upper = 200.0", "upper = 200.0\ncolour = 1",
     "identify.parameter.0.colour: expected a key"},
    {"UnknownKeys", "[[identify.parameter]]", "[identify]\nmethod = 1\n[[identify.parameter]]",
     "case.toml:32: identify.method: expected a key of the case-file schema (here: parameter)"},
    {"WrongTypes", "elements = 6", "elements = \"six\"",
     "case.toml:3: beam.elements: expected an integer in [1, 1000], got \"six\""},
    {"WrongTypes", "elements = 6", "elements = 6.0",
     "case.toml:3: beam.elements: expected an integer in [1, 1000], got 6"},
    {"WrongTypes", "length = 0.593", "length = true",
     "case.toml:2: beam.length: expected a number > 0 (m), got true"},
    {"WrongTypes", "modal_ratios = [0.01, 0.01]", "modal_ratios = 0.01",
     "case.toml:10: damping.modal_ratios: expected an array of 2 numbers, got 0.01"},
    {"WrongTypes", "modal_ratios = [0.01, 0.01]", "modal_ratios = [0.01, \"a\"]",
     "damping.modal_ratios.1: expected a number in [0, 1), got \"a\""},
    {"WrongTypes", "dof = \"w\"", "dof = 1",
     "case.toml:25: sensors.dof: expected one of \"w\", \"theta\", got 1"},
    {"WrongTypes", "[beam]", "beam = 1\n[beem]", "case.toml:1: beam: expected a table, got 1"},
    {"WrongTypes", "[[nonlinearity]]", "[nonlinearity]",
     "case.toml:12: nonlinearity: expected an array of tables [[nonlinearity]], got a table"},
    {"WrongTypes", "key = \"nonlinearity.0.k3\"", "key = 3",
     "identify.parameter.0.key: expected a non-empty string, got 3"},
    {"Beam", "length = 0.593", "length = -0.593",
     "case.toml:2: beam.length: expected a number > 0 (m), got -0.593"},
    {"Beam", "elements = 6", "elements = 0",
     "case.toml:3: beam.elements: expected an integer in [1, 1000], got 0"},
    {"Beam", "youngs_modulus = 2.05e11", "youngs_modulus = 0",
     "beam.youngs_modulus: expected a number > 0 (Pa), got 0"},
    {"Beam", "density = 7800.0", "density = nan",
     "beam.density: expected a number > 0 (kg/m^3), got nan"},
    {"Beam", "area = 0.196e-3", "area = inf", "beam.area: expected a number > 0"},
    {"Beam", "length = 0.593", "# no length",
     "case.toml:1: beam.length: expected a number > 0 (m), got nothing (the key is required)"},
    {"Beam", "area = 0.196e-3", "width = 0.01",
     "case.toml:1: beam: expected beam.area (square section) or beam.width and beam.height, got "
     "only beam.width"},
    {"Beam", "area = 0.196e-3", "area = 0.196e-3\nheight = 0.01",
     "case.toml:7: beam.height: expected either beam.area (square section) or beam.width and "
     "beam.height, got both"},
    {"Beam", "[beam]", "[beem]", "case.toml:1: beem: expected a key"},
    {"Damping", "type = \"rayleigh\"", "type = \"viscous\"",
     "case.toml:9: damping.type: expected one of \"rayleigh\", \"none\", got \"viscous\""},
    {"Damping", "modal_ratios = [0.01, 0.01]", "modal_ratios = [0.01, 1.0]",
     "case.toml:10: damping.modal_ratios.1: expected a number in [0, 1), got 1"},
    {"Damping", "modal_ratios = [0.01, 0.01]", "modal_ratios = [0.01]",
     "damping.modal_ratios: expected an array of 2 numbers, got an array of 1"},
    {"Damping", "modal_ratios = [0.01, 0.01]", "modal_ratios = [0.01, 0.01]\nmodes = [2, 2]",
     "case.toml:11: damping.modes: expected two different mode numbers, got [2, 2]"},
    {"Damping", "modal_ratios = [0.01, 0.01]", "modal_ratios = [0.01, 0.01]\nmodes = [1, 13]",
     "damping.modes.1: expected an integer in [1, 12], got 13"},
    {"Damping", "modal_ratios = [0.01, 0.01]", "modal_ratios = [0.01, 0.01]\nalpha = 1",
     "damping.alpha: expected either damping.modal_ratios or damping.alpha/beta, got both"},
    {"Damping", "modal_ratios = [0.01, 0.01]", "beta = -1e-5",
     "damping.beta: expected a number >= 0 (s), got -1e-05"},
    {"Damping", "modal_ratios = [0.01, 0.01]", "",
     "case.toml:8: damping: expected damping.modal_ratios = [z1, z2] or damping.alpha/beta for "
     "type \"rayleigh\", got neither"},
    {"Nonlinearity", "node = 6", "node = 7",
     "case.toml:14: nonlinearity.0.node: expected an integer in [1, 6], got 7"},
    {"Nonlinearity", "node = 6", "node = 0",
     "nonlinearity.0.node: expected an integer in [1, 6], got 0"},
    {"Nonlinearity", "type = \"cubic\"", "type = \"quintic\"",
     "case.toml:13: nonlinearity.0.type: expected one of \"cubic\", \"polynomial\", \"gap\", "
     "\"friction\", got \"quintic\""},
    {"Nonlinearity", "k3 = 5.0e9", "k3 = 5.0e9\ngap = 0.1",
     "case.toml:16: nonlinearity.0.gap: expected only the keys type, node, nodes, dof, dofs, k3 "
     "for type \"cubic\", got gap = 0.1"},
    {"Nonlinearity", "k3 = 5.0e9", "",
     "case.toml:12: nonlinearity.0.k3: expected a finite number (N/m^3), got nothing"},
    {"Nonlinearity", "type = \"cubic\"\nnode = 6\nk3 = 5.0e9",
     "type = \"gap\"\ngap = -1e-3\nstiffness = 1e6",
     "case.toml:14: nonlinearity.0.gap: expected a number >= 0 (m), got -0.001"},
    {"Nonlinearity", "type = \"cubic\"\nnode = 6\nk3 = 5.0e9",
     "type = \"gap\"\ngap = 1e-3\nstiffness = 0",
     "nonlinearity.0.stiffness: expected a number > 0 (N/m), got 0"},
    {"Nonlinearity", "type = \"cubic\"\nnode = 6\nk3 = 5.0e9",
     "type = \"friction\"\nmu = 0.3\nnormal_force = 10\nvelocity_scale = 0",
     "nonlinearity.0.velocity_scale: expected a number > 0 (m/s), got 0"},
    {"Nonlinearity", "type = \"cubic\"\nnode = 6\nk3 = 5.0e9",
     "type = \"friction\"\nmu = -0.3\nnormal_force = 10\nvelocity_scale = 1",
     "nonlinearity.0.mu: expected a number >= 0, got -0.3"},
    {"Initial", "static_tip_force = 20.0", "static_tip_force = 20.0\nnode = 9",
     "case.toml:19: initial.node: expected an integer in [1, 6], got 9"},
    {"Initial", "static_tip_force = 20.0", "static_tip_force = 20.0\nvelocity = [1]",
     "initial.velocity: expected either initial.static_tip_force or initial.displacement/velocity, "
     "got both"},
    {"Initial", "static_tip_force = 20.0", "displacement = [1, 2, 3]",
     "case.toml:18: initial.displacement: expected an array of 12 numbers, got an array of 3"},
    {"Initial", "static_tip_force = 20.0", "node = 2",
     "initial.node: expected initial.node only with initial.static_tip_force (or static_force), "
     "got 2"},
    {"Initial", "static_tip_force = 20.0", "static_tip_force = \"big\"",
     "initial.static_tip_force: expected a finite number (N), got \"big\""},
    {"Force", "", "[force]\ntype = \"impulse\"\n",
     "case.toml:39: force.type: expected one of \"none\", \"harmonic\", \"sweep\", \"file\", "
     "\"channel\", got \"impulse\""},
    {"Force", "", "[force]\namplitude = 1\n",
     "case.toml:38: force.type: expected one of \"none\", \"harmonic\", \"sweep\", \"file\", "
     "\"channel\", got nothing"},
    {"Force", "", "[force]\ntype = \"harmonic\"\namplitude = 1\n",
     "case.toml:38: force.frequency: expected a number > 0 (Hz), got nothing"},
    {"Force", "", "[force]\ntype = \"harmonic\"\namplitude = 1\nfrequency = 30\nnode = 0\n",
     "case.toml:42: force.node: expected an integer in [1, 6], got 0"},
    {"Force", "",
     "[force]\ntype = \"sweep\"\namplitude = 1\nstart_frequency = 0\nend_frequency = 5\n",
     "case.toml:41: force.start_frequency: expected a number > 0 (Hz), got 0"},
    {"Force", "", "[force]\ntype = \"file\"\ncolumn = \"f\"\n",
     "force.file: expected a non-empty string, got nothing"},
    {"Time", "step = 2.0e-4", "step = 0",
     "case.toml:22: time.step: expected a number > 0 (s), got 0"},
    {"Time", "step = 2.0e-4", "step = -2.0e-4",
     "case.toml:22: time.step: expected a number > 0 (s), got -2e-04"},
    {"Time", "step = 2.0e-4", "step = 0.2",
     "case.toml:22: time.step: expected a step <= time.duration = 0.1 s, got 0.2"},
    {"Time", "duration = 0.1", "duration = 0",
     "case.toml:21: time.duration: expected a number > 0 (s), got 0"},
    {"Time", "step = 2.0e-4", "step = 1e-12", "time.step: expected at most 1e9 steps"},
    {"Time", "step = 2.0e-4", "",
     "case.toml:20: time.step: expected a number > 0 (s), got nothing"},
    // A subnormal step or rate has an infinite reciprocal (IsSamplingStep).
    {"Data", "", "[data]\nstep = 1e-320\n",
     "data.step: expected a step whose rate 1 / step is finite (s), got 1e-320"},
    {"Data", "", "[data]\nrate = 1e-320\n",
     "data.rate: expected a rate whose step 1 / rate is finite (Hz), got 1e-320"},
    {"Data", "", "[data]\nstep = 0.0\n", "data.step: expected a number > 0 (s), got 0"},
    {"SensorsNoiseIntegrator", "dof = \"w\"", "dof = \"u\"",
     "case.toml:25: sensors.dof: expected one of \"w\", \"theta\", got \"u\""},
    {"SensorsNoiseIntegrator", "dof = \"w\"", "nodes = [1, 7]",
     "case.toml:25: sensors.nodes.1: expected an integer in [1, 6], got 7"},
    {"SensorsNoiseIntegrator", "dof = \"w\"", "nodes = [1, 2, 1]",
     "sensors.nodes: expected distinct node numbers, got node 1 twice"},
    {"SensorsNoiseIntegrator", "dof = \"w\"", "nodes = []",
     "sensors.nodes: expected a non-empty array of integers, got an array of 0"},
    {"SensorsNoiseIntegrator", "relative = 0.0", "relative = -0.01",
     "case.toml:28: noise.relative: expected a number >= 0, got -0.01"},
    {"SensorsNoiseIntegrator", "seed = 1", "seed = -1",
     "case.toml:29: noise.seed: expected an integer >= 0, got -1"},
    {"SensorsNoiseIntegrator", "", "[integrator]\ngamma = 0.4\n",
     "case.toml:39: integrator.gamma: expected a number in [0.5, 1], got 0.4"},
    {"SensorsNoiseIntegrator", "", "[integrator]\nbeta = 0\n",
     "integrator.beta: expected a number in (0, 0.5], got 0"},
    {"SensorsNoiseIntegrator", "", "[integrator]\ntolerance = 0\n",
     "integrator.tolerance: expected a number in (0, 1), got 0"},
    {"SensorsNoiseIntegrator", "", "[integrator]\ntolerance = 1\n",
     "integrator.tolerance: expected a number in (0, 1), got 1"},
    {"SensorsNoiseIntegrator", "", "[integrator]\nsubsteps = 1001\n",
     "integrator.substeps: expected an integer in [1, 1000], got 1001"},
    {"SensorsNoiseIntegrator", "", "[integrator]\nmax_iterations = 0\n",
     "integrator.max_iterations: expected an integer in [1, 1000000], got 0"},
    {"SensorsNoiseIntegrator", "", "[integrator]\ntype = \"rk4\"\n",
     "integrator.type: expected one of \"modified\", \"newmark\", got \"rk4\""},
    {"IdentifyParameters", "key = \"nonlinearity.0.k3\"", "key = \"beam.elements\"",
     "case.toml:33: identify.parameter.0.key: expected a real-valued key of this case"},
    {"IdentifyParameters", "key = \"nonlinearity.0.k3\"", "key = \"nonlinearity.0.k5\"",
     "identify.parameter.0.key: expected a real-valued key"},
    {"IdentifyParameters", "key = \"nonlinearity.0.k3\"", "key = \"nonlinearity.1.k3\"",
     "got \"nonlinearity.1.k3\""},
    {"IdentifyParameters", "scale = 1.0e8", "scale = 0",
     "case.toml:34: identify.parameter.0.scale: expected a number != 0, got 0"},
    {"IdentifyParameters", "lower = 0.0", "lower = 300.0",
     "case.toml:37: identify.parameter.0.upper: expected a number > lower = 300, got 200"},
    {"IdentifyParameters", "start = 40.0", "start = 400.0",
     "case.toml:35: identify.parameter.0.start: expected a number in [0, 200] (between lower and "
     "upper), got 400"},
    {"IdentifyParameters", "name = \"knl\"", "name = \"\"",
     "identify.parameter.0.name: expected a non-empty string, got \"\""},
    // Names reach CSV headers, JSON keys and the terminal: an escape sequence
    // (here one that clears the screen), NUL or a comma is refused, shown escaped.
    {"IdentifyParameters", "name = \"knl\"", "name = \"k\\u001b[2J\"",
     "case.toml:32: identify.parameter.0.name: expected a name of at most 256 bytes without "
     "control characters, ',' or '\"', got \"k\\u001b[2J\""},
    {"IdentifyParameters", "name = \"knl\"", "name = \"k,nl\"", "got \"k,nl\""},
    {"SensorsNoiseIntegrator", "dof = \"w\"\n",
     "dof = \"w\"\nnodes = [1, 2]\nnames = [\"a\", \"b\\u0000c\"]\n",
     "sensors.names.1: expected a name of at most 256 bytes without control characters, ',' or "
     "'\"', got \"b\\u0000c\""},
    {"IdentifyParameters", "",
     "[[identify.parameter]]\nname = \"knl\"\nkey = \"damping.modal_ratios.0\"\nstart = 1\n"
     "lower = 0\nupper = 2\n",
     "case.toml:39: identify.parameter.1.name: expected a name no other identify.parameter has, "
     "got \"knl\" again"},
    {"IdentifyParameters", "key = \"nonlinearity.0.k3\"", "key = \"nonlinearity.0.gap\"",
     "case.toml:33: identify.parameter.0.key: expected a key this case can take at scale * start "
     "(setting it gives: case.toml (nonlinearity.0.gap set by the program): nonlinearity.0.gap: "
     "expected only the keys type, node, nodes, dof, dofs, k3 for type \"cubic\", got gap = "
     "4e+09), got \"nonlinearity.0.gap\""},
};

// Checks the rows of kRejections that belong to `test`.
void ExpectRejections(std::string_view test) {
  int checked = 0;
  for (const Rejection& row : kRejections) {
    if (row.test != test) continue;
    ++checked;
    const std::string from(row.from), to(row.to);
    SCOPED_TRACE("\"" + from + "\" -> \"" + to + "\"");
    EXPECT_CASE_ERROR(from.empty() ? kBase + to : Edit(from, to), std::string(row.needle));
  }
  EXPECT_GT(checked, 0) << "no row of kRejections for " << test;
}

// --- rejections: syntax, unknown keys, wrong types ---------------------------

TEST(CaseFileRejects, InvalidToml) { ExpectRejections("InvalidToml"); }

TEST(CaseFileRejects, MissingFile) {
  PODID_EXPECT_THROW_WITH(CaseDocument::Load("/nonexistent/case.toml"), std::invalid_argument,
                          "/nonexistent/case.toml: expected a readable case file");
}

TEST(CaseFileRejects, UnknownKeys) { ExpectRejections("UnknownKeys"); }

TEST(CaseFileRejects, WrongTypes) { ExpectRejections("WrongTypes"); }

// --- rejections: out-of-range values -------------------------------------------

TEST(CaseFileRejects, Beam) {
  ExpectRejections("Beam");
  EXPECT_CASE_ERROR(
      "[time]\nduration=1\nstep=0.1\n",
      "case.toml: beam: expected a [beam] table, got nothing (the table is required)");
}

// Issue 10 item 6: values the schema accepts but whose model overflows or
// underflows used to trip PODID_CHECKs in beam_model.cpp (abort, exit 134).
TEST(CaseFileRejects, BeamValuesWhoseModelIsNotFinite) {
  const auto build = [](const std::string& from, const std::string& to) {
    return BeamModel::Build(SpecOf(Edit(from, to)));
  };
  PODID_EXPECT_THROW_WITH(build("youngs_modulus = 2.05e11", "youngs_modulus = 1e-320"),
                          std::invalid_argument,
                          "beam.youngs_modulus: expected a modulus > 0 Pa between 2.3e-308 and "
                          "1.7e308 (a normal double), got 9.99");
  PODID_EXPECT_THROW_WITH(build("density = 7800.0", "density = 1e-320"), std::invalid_argument,
                          "beam.density: expected a density > 0 kg/m^3 between 2.3e-308");
  PODID_EXPECT_THROW_WITH(build("area = 0.196e-3", "area = 1e300"), std::invalid_argument,
                          "beam section (from beam.area or width, height): expected a second "
                          "moment of area > 0 m^4 between 2.3e-308 and 1.7e308 (a normal "
                          "double), got inf");
  PODID_EXPECT_THROW_WITH(build("length = 0.593", "length = 1e-100"), std::invalid_argument,
                          "beam.length, beam.elements, beam.youngs_modulus, beam.density, "
                          "beam.area (or width, height): expected a frequency scale");
  PODID_EXPECT_THROW_WITH(build("length = 0.593", "length = 1e300"), std::invalid_argument,
                          "expected an element stiffness E I / l^3 > 0 N/m between 2.3e-308 and "
                          "1.7e308 (a normal double), got 0");
  PODID_EXPECT_THROW_WITH(build("area = 0.196e-3", "area = 1e150"), std::invalid_argument,
                          "expected a bending stiffness E I > 0 N m^2");
  PODID_EXPECT_THROW_WITH(build("density = 7800.0", "density = 1e-300"), std::invalid_argument,
                          "expected a frequency scale E I / (rho A l^4) > 0 s^-2");
  // Extreme but representable values still build a finite model with modes.
  const BeamModel wide = build("length = 0.593", "length = 1e30");
  EXPECT_TRUE(wide.DenseStiffness().allFinite());
  EXPECT_TRUE(wide.DenseMass().allFinite());
  const ModalAnalysis modes = wide.Modes();
  EXPECT_GT(modes.frequencies_Hz[0], 0.0);
  EXPECT_TRUE(modes.frequencies_Hz.allFinite());
}

// Issue 10 item 8: a billion steps passed the 1e9-step bound and ended in a
// bare std::bad_alloc; the record (samples x sensors) is bounded at 2^27 values.
TEST(CaseFileRejects, RecordLargerThanTheMemoryBound) {
  EXPECT_CASE_ERROR(Edit("step = 2.0e-4", "step = 1e-10"),
                    "case.toml:22: time.step: expected at most 134217728 recorded values "
                    "((duration / step + 1) x sensor channels), got 6000000006 values");
  // 2^27 / 6 channels = 22369621 samples: a step of 0.1 / 2e7 still fits.
  EXPECT_NO_THROW(SpecOf(Edit("step = 2.0e-4", "step = 5e-9")));
}

TEST(CaseFileRejects, Damping) {
  ExpectRejections("Damping");
  // type = "none" ignores the table's other keys (--set damping.type=none).
  EXPECT_EQ(SpecOf(Edit("type = \"rayleigh\"", "type = \"none\"")).damping.type,
            DampingType::kNone);
}

TEST(CaseFileRejects, Nonlinearity) { ExpectRejections("Nonlinearity"); }

TEST(CaseFileRejects, Initial) { ExpectRejections("Initial"); }

TEST(CaseFileRejects, Force) {
  ExpectRejections("Force");
  EXPECT_EQ(SpecOf(kBase + "[force]\ntype = \"none\"\namplitude = 1\n").force.history_N.type,
            ForceType::kNone);
}

TEST(CaseFileRejects, Time) { ExpectRejections("Time"); }

TEST(CaseFileRejects, Data) { ExpectRejections("Data"); }

TEST(CaseFileRejects, SensorsNoiseIntegrator) { ExpectRejections("SensorsNoiseIntegrator"); }

TEST(CaseFileRejects, IdentifyParameters) {
  ExpectRejections("IdentifyParameters");
  // A key absent from the file but in the schema may be identified.
  const CaseSpec spec = SpecOf(kBase +
                               "[[identify.parameter]]\nname = \"zeta2\"\n"
                               "key = \"damping.modal_ratios.1\"\nstart = 1\n"
                               "lower = 0\nupper = 2\nscale = 0.01\n");
  EXPECT_EQ(spec.parameters.size(), 2u);
}

}  // namespace
}  // namespace podid
