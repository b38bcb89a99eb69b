// PrepareMeasured / ReadMeasured (podid/ident/measured_record.hpp): the
// measured record podid identify and the Python module compare, prepared
// from the case's [data] in one place.
#include <gtest/gtest.h>

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "podid/core/case_file.hpp"
#include "podid/core/simulate.hpp"
#include "podid/ident/measured_record.hpp"
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
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("rec.csv: the record starts at t = 0.5"), std::string::npos) << notes[0];

  // A record already starting at time.start changes nothing and says nothing.
  CaseDocument again = CaseDocument::Load(podid::testing::ExamplePath("duffing/duffing.toml"));
  notes.clear();
  PrepareMeasured(again, f.raw, "rec.csv", &notes);
  EXPECT_TRUE(notes.empty());
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
