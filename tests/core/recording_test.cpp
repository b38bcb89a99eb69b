// [data] and measured forces (podid/core/recording.hpp, case_spec.hpp):
// a force read from a channel of the data file, its gain, records that do not
// start at t = 0, and the conditioning of measured and simulated records.
#include "podid/core/recording.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "podid/core/io.hpp"
#include "podid/core/model_parameter.hpp"
#include "podid/core/simulate.hpp"
#include "podid/core/simulator.hpp"
#include "reference_case.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

using podid::testing::ExpectMatricesNear;
using podid::testing::ReferenceCase;
using podid::testing::TempDir;

// A force history on 0 .. 0.4 s at the reference case's step (2e-4 s): a
// 30 Hz tone of 5 N, in a CSV whose time starts at `start_s`, with a second
// column "g" of the same force in volts for a gain of 4 N/V.
std::string WriteForce(const TempDir& dir, const std::string& name, double start_s) {
  TimeSeries f;
  const int n = 2001;
  f.time_s.resize(n);
  f.values.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    const double t = i * 2e-4;
    f.time_s[i] = start_s + t;
    f.values(i, 0) = 5.0 * std::sin(2 * std::numbers::pi * 30.0 * t);
    f.values(i, 1) = f.values(i, 0) / 4.0;
    f.values(i, 2) = std::sin(2 * std::numbers::pi * 7.0 * t);
  }
  f.channel_names = {"f", "volts", "a"};
  const std::string path = dir.File(name);
  WriteCsv(path, f);
  return path;
}

// Same inputs in the same order through the same code: identical doubles.
constexpr double kSamePath = 0.0;
// The same force sampled at the same instants, whose times are computed as
// start + i h in two ways: interpolation weights differ by round-off only.
constexpr double kRoundOff_m = 1e-15;

TEST(RecordingTest, ForceChannelMatchesForceFile) {
  TempDir dir;
  const std::string file = WriteForce(dir, "force.csv", 0.0);
  const CaseSpec by_file = ReferenceCase(
      {"force.type=file", "force.file=\"" + file + "\"", "force.column=f", "force.node=3"});
  const CaseSpec by_channel = ReferenceCase(
      {"data.file=\"" + file + "\"", "force.type=channel", "force.channel=f", "force.node=3"});
  EXPECT_EQ(by_channel.force.history_N.type, ForceType::kChannel);
  const SimulationResult a = Simulate(by_file), b = Simulate(by_channel);
  ASSERT_TRUE(a.summary.IsSolutionUsable() && b.summary.IsSolutionUsable());
  EXPECT_TRUE(ExpectMatricesNear(a.sensors.values, b.sensors.values, kSamePath));
  // Without a force the response differs (the force is really applied).
  const SimulationResult free = Simulate(ReferenceCase());
  EXPECT_GT((free.sensors.values - a.sensors.values).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(RecordingTest, GainConvertsVoltsToNewtons) {
  TempDir dir;
  const std::string file = WriteForce(dir, "force.csv", 0.0);
  const std::vector<std::string> linear = {"nonlinearity.0.k3=0.0", "initial.static_tip_force=0.0",
                                           "data.file=\"" + file + "\"", "force.type=channel",
                                           "force.node=3"};
  auto with = [&](const std::string& channel, const std::string& gain) {
    std::vector<std::string> sets = linear;
    sets.push_back("force.channel=" + channel);
    sets.push_back("force.gain=" + gain);
    return Simulate(ReferenceCase(sets)).sensors.values;
  };
  const Eigen::MatrixXd newtons = with("f", "1.0");
  const double scale = newtons.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.0);
  // volts x 4 N/V is the same force; the model is linear, so gain 3 triples it.
  // Relative 1e-12: one multiplication by 4 (exact) or 3 per force sample and
  // a linear solve per step.
  constexpr double kLinearRelative = 1e-12;
  EXPECT_TRUE(ExpectMatricesNear(with("volts", "4.0"), newtons, kLinearRelative * scale));
  EXPECT_TRUE(
      ExpectMatricesNear(with("f", "3.0"), (3.0 * newtons).eval(), kLinearRelative * scale));
  // A force file takes the gain too.
  std::vector<std::string> sets = {"nonlinearity.0.k3=0.0", "initial.static_tip_force=0.0",
                                   "force.type=file",       "force.file=\"" + file + "\"",
                                   "force.column=volts",    "force.gain=4.0",
                                   "force.node=3"};
  EXPECT_TRUE(ExpectMatricesNear(Simulate(ReferenceCase(sets)).sensors.values, newtons,
                                 kLinearRelative * scale));
}

TEST(RecordingTest, RecordStartingLaterReadsTheForceAtItsOwnTime) {
  TempDir dir;
  // The same force stamped from 0 and from 0.25 s; the simulation starting
  // at 0.25 s must see, at its first sample, the force stamped 0.25 s.
  const std::string at0 = WriteForce(dir, "f0.csv", 0.0);
  const std::string at025 = WriteForce(dir, "f025.csv", 0.25);
  const SimulationResult a = Simulate(ReferenceCase(
      {"force.type=file", "force.file=\"" + at0 + "\"", "force.column=f", "force.node=3"}));
  const SimulationResult b =
      Simulate(ReferenceCase({"force.type=file", "force.file=\"" + at025 + "\"", "force.column=f",
                              "force.node=3", "time.start=0.25"}));
  EXPECT_DOUBLE_EQ(b.sensors.time_s[0], 0.25);
  EXPECT_NEAR(b.sensors.time_s[b.sensors.samples() - 1], 0.35, 1e-12);
  EXPECT_TRUE(ExpectMatricesNear(a.sensors.values, b.sensors.values, kRoundOff_m));
}

TEST(RecordingTest, MeasuredChannelsMapOntoSensorsAndConditioningIsShared) {
  const CaseSpec spec =
      ReferenceCase({"data.channels=[\"c6\", \"c5\", \"c4\", \"c3\", \"c2\", \"c1\"]",
                     "data.filter=lowpass", "data.cutoff=500.0", "data.detrend=linear"});
  const SimulationResult sim = Simulate(spec);
  TimeSeries raw = sim.sensors;  // the file's channels, named otherwise and reversed
  raw.channel_names = {"c1", "c2", "c3", "c4", "c5", "c6"};
  raw.values = sim.sensors.values.rowwise().reverse();
  std::vector<std::string> notes;
  const TimeSeries measured = ConditionMeasured(spec, raw, "rec.csv", &notes);
  EXPECT_EQ(measured.channel_names, spec.sensors.ChannelNames());
  ASSERT_EQ(notes.size(), 6u);
  EXPECT_EQ(notes[0], "rec.csv: channel c6 is sensor w1");
  // Conditioning is linear and channel-wise: the measured channels, mapped
  // back, equal the conditioned simulation.
  EXPECT_TRUE(
      ExpectMatricesNear(measured.values, ConditionSimulated(spec, sim.sensors).values, kSamePath));
  ConditioningOptions expected;
  expected.filter = {FilterType::kLowpass, 4, 0.0, 500.0};
  expected.detrend = Detrend::kLinear;
  EXPECT_TRUE(ExpectMatricesNear(ConditionSimulated(spec, sim.sensors).values,
                                 ConditionRecord(sim.sensors, expected, "x").values, kSamePath));
}

std::string Message(const std::vector<std::string>& sets) {
  try {
    (void)ReferenceCase(sets);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no exception";
}

TEST(RecordingTest, DataTableErrorsNameTheKey) {
  EXPECT_EQ(Message({"data.filter=lowpass"}),
            podid::testing::ExamplePath("beam.toml") +
                ": data.cutoff: expected a number > 0 (Hz), got nothing (the key is required)");
  EXPECT_EQ(Message({"data.decimate=1001"}),
            "--set data.decimate=1001: data.decimate: expected an integer in [1, 1000], got 1001");
  EXPECT_EQ(Message({"data.filter=bandpass", "data.band=[50.0, 10.0]"}),
            "--set data.band=[50.0, 10.0]: data.band: expected [low, high] with low < high (Hz), "
            "got [50, 10]");
  EXPECT_EQ(
      Message({"data.filter=lowpass", "data.cutoff=10.0", "data.filter_order=17"}),
      "--set data.filter_order=17: data.filter_order: expected an integer in [1, 16], got 17");
  EXPECT_EQ(Message({"data.window=[1.0, 0.5]"}),
            "--set data.window=[1.0, 0.5]: data.window: expected [start, end] with start < end "
            "(s), got [1, 0.5]");
  EXPECT_EQ(Message({"force.type=channel", "force.channel=f"}),
            "--set force.channel=f: force.channel: expected a [data] file to read it from "
            "(data.file, or the measured file given on the command line), got no data.file");
  TempDir dir;
  const std::string file = WriteForce(dir, "force.csv", 0.0);
  EXPECT_EQ(Message({"data.file=\"" + file + "\"", "force.type=channel", "force.channel=zz"}),
            "--set force.channel=zz: force.channel: expected a channel of " + file +
                " (f, volts, a), got \"zz\"");
}

TEST(RecordingTest, ForceGainAndOffsetAreLoadParametersMatchingTheDocumentPath) {
  TempDir dir;
  const std::string file = WriteForce(dir, "force.csv", 0.0);
  CaseDocument document = CaseDocument::Load(podid::testing::ExamplePath("beam.toml"));
  ApplySetArguments(document, {"data.file=\"" + file + "\"", "force.type=channel",
                               "force.channel=volts", "force.node=3", "force.offset=0.5"});
  const CaseSpec base = document.ToSpec();
  EXPECT_EQ(base.force.history_N.offset, 0.5);
  Simulator simulator(base);
  // The cached load is rebuilt with the new gain and offset; the document
  // path re-reads the channel. Same operations on the same samples, the
  // nonlinear solve included: equal to round-off relative to the response.
  constexpr double kRoundoffRelative = 1e-12;
  for (const auto& [key, value] :
       std::vector<std::pair<std::string, double>>{{"force.gain", 4.0}, {"force.offset", -1.5},
                                                   {"force.gain", -2.0}}) {
    const ModelParameter parameter = ModelParameter::Resolve(base, key);
    EXPECT_EQ(parameter.effect(), ParameterEffect::kLoad) << key;
    std::string why;
    ASSERT_TRUE(simulator.Set(parameter, value, &why)) << why;
    document.SetNumber(key, value);
    const SimulationResult expected = Simulate(document.ToSpec(), SimulateOptions{false});
    const SimulationResult actual = simulator.Run();
    ASSERT_TRUE(expected.summary.IsSolutionUsable() && actual.summary.IsSolutionUsable());
    const double scale = expected.sensors.values.cwiseAbs().maxCoeff();
    EXPECT_TRUE(ExpectMatricesNear(actual.sensors.values, expected.sensors.values,
                                   kRoundoffRelative * scale))
        << "after " << key << " = " << value;
  }
  // A harmonic force has neither.
  PODID_EXPECT_THROW_WITH(ModelParameter::Resolve(ReferenceCase({"force.type=harmonic",
                                                                 "force.amplitude=1.0",
                                                                 "force.frequency=10.0"}),
                                                  "force.offset"),
                          std::invalid_argument, "a value the case's force.type does not have");
}

// A one-dof oscillator m x'' + c x' + k x = F, F = gain x u + offset with a
// measured u = 0: the offset alone is a step force b applied at t = 0, whose
// response from rest is x(t) = b / k (1 - e^(-zeta w t) (cos(wd t) +
// zeta / sqrt(1 - zeta^2) sin(wd t))).
TEST(RecordingTest, ForceOffsetIsAStepForceWithTheAnalyticResponse) {
  TempDir dir;
  dir.Write("m.mtx", "%%MatrixMarket matrix coordinate real general\n1 1 1\n1 1 1.0\n");
  dir.Write("k.mtx", "%%MatrixMarket matrix coordinate real general\n1 1 1\n1 1 986.96044010893581\n");
  dir.Write("c.mtx", "%%MatrixMarket matrix coordinate real general\n1 1 1\n1 1 0.4\n");
  std::string csv = "t,u\n";
  for (int i = 0; i <= 5000; ++i) csv += std::to_string(i * 1e-4) + ",0\n";
  const std::string data = dir.Write("u.csv", csv);
  const std::string path = dir.Write("sdof.toml", R"([model]
type = "matrices"
mass = "m.mtx"
stiffness = "k.mtx"
damping = "c.mtx"
[force]
type = "channel"
channel = "u"
dof = 1
gain = 3.0
offset = 2.0
[data]
file = "u.csv"
[time]
duration = 0.5
step = 1.0e-4
[sensors]
dofs = [1]
)");
  (void)data;
  const SimulationResult sim = Simulate(CaseDocument::Load(path).ToSpec());
  ASSERT_TRUE(sim.summary.IsSolutionUsable()) << sim.summary.message;
  const double k = 986.96044010893581, c = 0.4, b = 2.0;
  const double w = std::sqrt(k), zeta = c / (2 * w), wd = w * std::sqrt(1 - zeta * zeta);
  Eigen::MatrixXd expected(sim.sensors.samples(), 1);
  for (int i = 0; i < sim.sensors.samples(); ++i) {
    const double t = sim.sensors.time_s[i];
    expected(i, 0) = b / k * (1 - std::exp(-zeta * w * t) *
                                      (std::cos(wd * t) + zeta / std::sqrt(1 - zeta * zeta) *
                                                              std::sin(wd * t)));
  }
  // Trapezoidal Newmark's period error (w dt)^2 / 12 = 8.2e-7 over 2.5
  // periods is a phase error of 1.3e-5 rad, i.e. 1.3e-5 x (b / k) at most;
  // 1e-4 x (b / k) leaves margin, and a missing or doubled offset (an error
  // of b / k) fails.
  constexpr double kNewmarkPhaseRelative = 1e-4;
  EXPECT_TRUE(ExpectMatricesNear(sim.sensors.values, expected, kNewmarkPhaseRelative * b / k));
}

}  // namespace
}  // namespace podid
