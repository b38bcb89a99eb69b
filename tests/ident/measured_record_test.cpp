// PrepareMeasured / ReadMeasured (podid/ident/measured_record.hpp): the
// measured record podid identify and the Python module compare, prepared
// from the case's [data] in one place.
#include "podid/ident/measured_record.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "podid/core/case_file.hpp"
#include "podid/core/io.hpp"
#include "podid/core/simulate.hpp"
#include "test_support.hpp"

namespace podid::ident {
namespace {

// The one-dof Duffing oscillator (examples/duffing/), 2 s at 1e-4 s from
// t = 0, and a window [0.5, 1.5] s of it.
struct Fixture {
  CaseDocument document = CaseDocument::Load(podid::testing::ExamplePath("duffing/duffing.toml"));
  TimeSeries raw;
  Fixture() {
    SimulateOptions options;
    options.add_noise = false;
    raw = Simulate(document.ToSpec(), options).sensors;
    document.Set("data.window", "[0.5, 1.5]");
  }
};

std::string MessageOf(const std::function<void()>& run) {
  try {
    run();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no exception";
}

TEST(MeasuredRecord, TheWindowIsAppliedAndTheSimulationStartsAtItsFirstSample) {
  Fixture f;
  std::vector<std::string> notes;
  const TimeSeries data = PrepareMeasured(f.document, f.raw, "rec.csv", &notes);
  // The window keeps samples 5000..15000 of the raw record (t = n 1e-4 s),
  // compared index by index with the raw record.
  ASSERT_EQ(data.samples(), 10001);
  EXPECT_EQ(data.values.row(0), f.raw.values.row(5000));
  EXPECT_EQ(data.values.row(10000), f.raw.values.row(15000));
  EXPECT_EQ(f.document.GetNumber("time.start"), data.time_s[0]);
  EXPECT_NEAR(data.time_s[0], 0.5, 1e-12);  // the grid's round-off at 5000 steps
  // The time.start note, then the explicit [initial] state's (see
  // TheStartStateAfterALateWindowGetsANote).
  ASSERT_EQ(notes.size(), 2u);
  EXPECT_NE(notes[0].find("rec.csv: the record starts at t = 0.5"), std::string::npos) << notes[0];

  // A record already starting at time.start changes nothing and says nothing.
  CaseDocument again = CaseDocument::Load(podid::testing::ExamplePath("duffing/duffing.toml"));
  notes.clear();
  PrepareMeasured(again, f.raw, "rec.csv", &notes);
  EXPECT_TRUE(notes.empty());
}

// Notes matching `text`.
std::size_t Count(const std::vector<std::string>& notes, const std::string& text) {
  std::size_t n = 0;
  for (const std::string& note : notes) n += note.find(text) != std::string::npos;
  return n;
}

TEST(MeasuredRecord, TheStartStateAfterALateWindowGetsANote) {
  // Duffing's [initial] displacement 0.1 m is its record's state at t = 0:
  // the window [0.5, 1.5] starts the simulation there from it, which the
  // note says; the record from t = 0 gives none.
  Fixture f;
  std::vector<std::string> notes;
  PrepareMeasured(f.document, f.raw, "rec.csv", &notes);
  EXPECT_EQ(Count(notes, "rec.csv: the window starts at t = 0.5"), 1u);
  EXPECT_EQ(Count(notes,
                  "[initial]'s displacement and velocity, which must be the state at t = "
                  "0.5"),
            1u);
  CaseDocument whole = CaseDocument::Load(podid::testing::ExamplePath("duffing/duffing.toml"));
  notes.clear();
  PrepareMeasured(whole, f.raw, "rec.csv", &notes);
  EXPECT_EQ(Count(notes, "[initial]"), 0u);

  // The reference beam released from a static deflection: the same for the
  // release, on its 1 s record windowed from 0.3 s.
  CaseDocument beam = CaseDocument::Load(podid::testing::ExamplePath("beam.toml"));
  const TimeSeries record = ReadCsv(podid::testing::ExamplePath("measured_knl50_T1.0.csv"));
  notes.clear();
  PrepareMeasured(beam, record, "beam.csv", &notes);
  EXPECT_EQ(Count(notes, "[initial]"), 0u);
  beam.Set("data.window", "[0.3, 1.0]");
  notes.clear();
  PrepareMeasured(beam, record, "beam.csv", &notes);
  EXPECT_EQ(Count(notes, "from [initial], the static deflection under 20 N released at t = 0.3 s"),
            1u);
}

TEST(MeasuredRecord, ARecordThatStartsMovingIsNotedForACaseAtRest) {
  // Duffing without [initial] starts at rest. Its free decay from 0.1 m
  // starts at its peak (100 %); a tone sin(2 pi 5 t) from t = 0 starts at 0,
  // a record at rest (no note), but windowed from 0.05 s (a quarter period,
  // its peak) it does not. Accelerometers and detrended records are not
  // judged (their value at rest is not 0), nor a start within 5 noise std.
  const std::string text =
      "[model]\ntype = \"matrices\"\nmass = \"m.mtx\"\nstiffness = \"k.mtx\"\n"
      "damping = \"c.mtx\"\nlabels = [\"x\"]\n[time]\nduration = 2.0\nstep = 1.0e-4\n";
  const std::string folder = podid::testing::ExamplePath("duffing");
  Fixture f;
  std::vector<std::string> notes;
  CaseDocument rest = CaseDocument::Parse(text, "rest.toml", folder);
  PrepareMeasured(rest, f.raw, "decay.csv", &notes);
  EXPECT_EQ(Count(notes,
                  "decay.csv: the simulation starts at rest ([initial] gives no state) at "
                  "t = 0 s, but the measured x is there 100 % of its peak |x|"),
            1u)
      << (notes.empty() ? "" : notes[0]);

  TimeSeries tone = f.raw;
  tone.values.col(0) = (2 * std::numbers::pi * 5.0 * tone.time_s.array()).sin().matrix();
  notes.clear();
  rest = CaseDocument::Parse(text, "rest.toml", folder);
  PrepareMeasured(rest, tone, "tone.csv", &notes);
  EXPECT_TRUE(notes.empty());
  rest.Set("data.window", "[0.05, 1.5]");
  notes.clear();
  PrepareMeasured(rest, tone, "tone.csv", &notes);
  EXPECT_EQ(Count(notes, "is there 100 % of its peak"), 1u);
  // A sensor that records only noise (uniform in +-0.5, std 0.29) starts
  // at 0.45, 90 % of its peak but within 5 noise std: no note.
  TimeSeries noise = f.raw;
  unsigned state = 12345u;
  for (Eigen::Index i = 0; i < noise.samples(); ++i) {
    state = state * 1664525u + 1013904223u;
    noise.values(i, 0) = static_cast<double>(state >> 8) / static_cast<double>(1u << 24) - 0.5;
  }
  noise.values(0, 0) = 0.45;
  notes.clear();
  CaseDocument quiet = CaseDocument::Parse(text, "rest.toml", folder);
  PrepareMeasured(quiet, noise, "noise.csv", &notes);
  EXPECT_TRUE(notes.empty()) << notes[0];
  rest.Set("data.detrend", "\"constant\"");
  notes.clear();
  PrepareMeasured(rest, tone, "tone.csv", &notes);
  EXPECT_EQ(Count(notes, "of its peak"), 0u);
}

TEST(MeasuredRecord, DecimationAndAMissingFileAreRefusedByName) {
  Fixture f;
  f.document.Set("data.decimate", "2");
  EXPECT_NE(MessageOf([&] { PrepareMeasured(f.document, f.raw, "rec.csv"); })
                .find("data.decimate: expected 1 for identify and landscape"),
            std::string::npos);
  // Refused before the file is read: this one does not exist.
  f.document.Set("data.file", "\"/nonexistent/record.csv\"");
  EXPECT_NE(MessageOf([&] { ReadMeasured(f.document); }).find("data.decimate"), std::string::npos);

  CaseDocument no_file = CaseDocument::Load(podid::testing::ExamplePath("duffing/duffing.toml"));
  EXPECT_NE(MessageOf([&] { ReadMeasured(no_file); }).find("data.file: expected a measured file, got none"),
            std::string::npos);
}

}  // namespace
}  // namespace podid::ident
