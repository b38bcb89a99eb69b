// Two statistical-quality situations of the wavelet (IF) term that passed
// silently (ident/src/mode_ridges.cpp): a measured ridge compared over a
// handful of samples gets a note with its count, and a ridge band outside the
// passband of the filter both records go through is refused (partly outside:
// a note). The shipped examples give neither.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "podid/core/error.hpp"
#include "podid/core/io.hpp"
#include "podid/ident/measured_record.hpp"
#include "podid/ident/objective.hpp"
#include "reference_case.hpp"

namespace podid::ident {
namespace {

using testing::ExamplePath;
using testing::ReferenceDocument;

ObjectiveOptions Wavelet(int modes = 1, double fmin_Hz = 10.0, double fmax_Hz = 120.0) {
  ObjectiveOptions options;
  options.SetWeights(ObjectiveWeights::Preset("wavelet"));
  options.modes = modes;
  options.ridge.cwt.frequencies.min_frequency_Hz = fmin_Hz;
  options.ridge.cwt.frequencies.max_frequency_Hz = fmax_Hz;
  return options;
}

// The objective on an example record conditioned by the case's [data] keys
// `sets` (as podid identify passes --lowpass and the like).
ObjectiveFunction Build(const std::string& record,
                        const ObjectiveOptions& options,
                        const std::vector<std::string>& sets = {}) {
  CaseDocument document = ReferenceDocument(sets);
  const TimeSeries measured = PrepareMeasured(document, ReadCsv(ExamplePath(record)), record);
  return ObjectiveFunction(document, measured, options);
}

std::vector<std::string> NotesMatching(const ObjectiveFunction& objective,
                                       const std::string& text) {
  std::vector<std::string> found;
  for (const std::string& note : objective.notes()) {
    if (note.find(text) != std::string::npos) found.push_back(note);
  }
  return found;
}

const char* kFewSamples = "samples are compared";
const char* kBandCut = "of the ridge band's";

// The message of the std::invalid_argument `build` throws ("" if none).
template <typename F>
std::string Refusal(F build) {
  try {
    build();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(RidgeQualityTest, TheShippedExamplesGiveNoNote) {
  // Mode 1 of the 1 s record: 289 samples compared (Morlet), 23.5 wavelet
  // durations; Morse 283, 17.8; mode 2: 431, 26.9 (Morse 229, 22.1).
  struct Run {
    int modes;
    wavelet::WaveletFamily family;
  };
  for (const Run run :
       {Run{1, wavelet::WaveletFamily::kMorlet}, Run{2, wavelet::WaveletFamily::kMorlet},
        Run{3, wavelet::WaveletFamily::kMorlet}, Run{1, wavelet::WaveletFamily::kMorse}}) {
    ObjectiveOptions options = Wavelet(run.modes);
    options.ridge.cwt.wavelet.family = run.family;
    const ObjectiveFunction objective = Build("measured_knl50_T1.0.csv", options);
    EXPECT_TRUE(NotesMatching(objective, kFewSamples).empty()) << run.modes << " modes";
    EXPECT_TRUE(NotesMatching(objective, kBandCut).empty()) << run.modes << " modes";
    EXPECT_GE(objective.measured_ridges()[0].InsideCoiCount(), 200);
  }
  // The 0.1 s record's objectives without the IF term have no ridge to judge.
  ObjectiveOptions full;
  full.SetWeights(ObjectiveWeights::Preset("full"));
  EXPECT_TRUE(NotesMatching(Build("measured_knl50_T0.1.csv", full), kFewSamples).empty());
}

TEST(RidgeQualityTest, AHandfulOfRidgeSamplesIsNoted) {
  // The 0.1 s record is shorter than the cone at 10 Hz; from 30 Hz it is
  // long enough, but only its middle is inside the cone at the ridge's 40 Hz:
  // 17 samples, one wavelet duration.
  const ObjectiveFunction objective = Build("measured_knl50_T0.1.csv", Wavelet(1, 30.0, 120.0));
  const std::vector<std::string> notes = NotesMatching(objective, kFewSamples);
  ASSERT_EQ(notes.size(), 1u);
  const Eigen::Index compared = objective.measured_ridges()[0].InsideCoiCount();
  const Eigen::Index total = objective.measured_ridges()[0].size();
  EXPECT_GT(compared, 0);
  EXPECT_LT(compared, 20);
  EXPECT_NE(notes[0].find("mode 1: only " + ToText(compared) + " of the ridge's " + ToText(total) +
                          " samples are compared"),
            std::string::npos)
      << notes[0];
  EXPECT_NE(notes[0].find("s of the 0.1 s record"), std::string::npos) << notes[0];
  EXPECT_NE(notes[0].find("a longer record, a shorter wavelet (--omega0 below 6, 5 at least)"),
            std::string::npos)
      << notes[0];
}

TEST(RidgeQualityTest, NoRidgeSampleComparedIsRefused) {
  // Mode 2 of the 1 s record is nowhere 30 times above the noise.
  ObjectiveOptions options = Wavelet(2);
  options.ridge_min_snr = 30.0;
  const std::string refusal = Refusal([&] { Build("measured_knl50_T1.0.csv", options); });
  EXPECT_NE(
      refusal.find(
          "measured data: expected a ridge of mode 2 inside the cone of influence and above the "
          "measurement noise, got none of its "),
      std::string::npos)
      << refusal;
  EXPECT_NE(
      refusal.find(
          "inside the cone, all below 30 x the noise: lower --ridge-snr, or compare fewer modes)"),
      std::string::npos)
      << refusal;
}

TEST(RidgeQualityTest, ABandOutsideTheFiltersPassbandIsRefused) {
  const std::vector<std::string> lowpass = {"data.filter=\"lowpass\"", "data.cutoff=50"};
  EXPECT_EQ(Refusal([&] { Build("measured_knl50_T1.0.csv", Wavelet(1, 100.0, 200.0), lowpass); }),
            "mode 1's ridge band (ridge.cwt.frequencies, --fmin/--fmax): expected a band reaching "
            "into the "
            "passband of the data's lowpass filter, below 50 Hz (order 4; data.filter, --lowpass; "
            "it conditions "
            "the measured and the simulated records alike), got 100..200 Hz, entirely above its "
            "cutoff 50 Hz");
  // The edge counts as beyond: a band from the cutoff up holds nothing passed.
  EXPECT_NE(Refusal([&] { Build("measured_knl50_T1.0.csv", Wavelet(1, 50.0, 200.0), lowpass); }),
            "");
  const std::vector<std::string> highpass = {"data.filter=\"highpass\"", "data.cutoff=150",
                                             "data.filter_order=2"};
  EXPECT_EQ(
      Refusal([&] { Build("measured_knl50_T1.0.csv", Wavelet(), highpass); }),
      "mode 1's ridge band (ridge.cwt.frequencies, --fmin/--fmax): expected a band reaching into "
      "the "
      "passband of the data's highpass filter, above 150 Hz (order 2; data.filter, --highpass; it "
      "conditions the measured and the simulated records alike), got 10..120 Hz, entirely below "
      "its "
      "cutoff 150 Hz");
  // Mode 2's given band, beyond a band-pass that keeps mode 1.
  ObjectiveOptions two = Wavelet(2);
  two.mode_bands = {{}, {150.0, 400.0}};
  const std::string refusal = Refusal([&] {
    Build("measured_knl50_T1.0.csv", two, {"data.filter=\"bandpass\"", "data.band=[5, 100]"});
  });
  EXPECT_NE(
      refusal.find(
          "mode 2's ridge band (mode_bands[1], --mode-band 2): expected a band reaching into the "
          "passband of the data's bandpass filter, 5..100 Hz"),
      std::string::npos)
      << refusal;
  EXPECT_NE(refusal.find("got 150..400 Hz, entirely above its cutoff 100 Hz"), std::string::npos)
      << refusal;
}

TEST(RidgeQualityTest, ABandPartlyOutsideThePassbandIsNoted) {
  // log2(120 / 80) = 0.585 of log2(120 / 10) = 3.585 octaves: 16.3 %.
  const ObjectiveFunction objective =
      Build("measured_knl50_T1.0.csv", Wavelet(), {"data.filter=\"lowpass\"", "data.cutoff=80"});
  const std::vector<std::string> notes = NotesMatching(objective, kBandCut);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0],
            "mode 1: 0.585 of the ridge band's 3.58 octaves (10..120 Hz; "
            "ridge.cwt.frequencies, "
            "--fmin/--fmax), 16.3 %, lie above the data's lowpass cutoff 80 Hz (order 4; "
            "data.filter, "
            "--lowpass), where the filter leaves both records only its skirt: keep the band inside "
            "the passband, "
            "e.g. 10..80 Hz");
  // A band inside the passband: quiet.
  const ObjectiveFunction inside = Build("measured_knl50_T1.0.csv", Wavelet(1, 10.0, 80.0),
                                         {"data.filter=\"lowpass\"", "data.cutoff=80"});
  EXPECT_TRUE(NotesMatching(inside, kBandCut).empty());
}

}  // namespace
}  // namespace podid::ident
