#include "podid/ident/measured_record.hpp"

#include <cmath>

#include "podid/core/error.hpp"
#include "podid/core/io.hpp"
#include "podid/core/recording.hpp"
#include "podid/pod/noise.hpp"

namespace podid::ident {

namespace {

void CheckNotDecimated(const CaseDocument& document, const CaseSpec& spec) {
  if (spec.data.conditioning.decimate != 1) {
    ThrowInvalid(document.source_name() + ": data.decimate",
                 "1 for identify and landscape (the simulation runs on the measured grid; "
                 "decimate the file beforehand, or use podid pod)",
                 ToText(spec.data.conditioning.decimate));
  }
}

// A first sample beyond this share of its channel's peak |x| is a structure
// already moving (a record windowed at a random phase of an oscillation
// reaches it with probability 0.84 on one channel), if it is also beyond
// kMovingNoiseSigmas x the channel's white-noise std (DifferenceNoiseVariance):
// a sensor near a clamp, its peak within a few noise std, stays quiet
// (probability 6e-7 per channel).
constexpr double kMovingShare = 0.25;
constexpr double kMovingNoiseSigmas = 5.0;

// The simulation starts at the record's first sample from [initial]: a case
// at rest differs from a record that starts moving until the transient has
// decayed (a free decay: throughout), and a static release or an explicit
// state given for the record's start no longer holds after a late window.
void NoteStartState(const CaseSpec& spec,
                    const TimeSeries& raw,
                    const TimeSeries& data,
                    const std::string& where,
                    std::vector<std::string>* notes) {
  if (notes == nullptr) return;
  const double t0 = data.time_s[0];
  const bool late = raw.time_s.size() > 0 && t0 > raw.time_s[0];
  const auto window = [&] {
    return "the window starts at t = " + ToText(t0) +
           " s, after the record's first sample at t = " + ToText(raw.time_s[0]) + " s";
  };
  switch (spec.initial.type) {
    case InitialType::kRest: {
      // A displacement or velocity at rest is 0; an acceleration is not (the
      // force at t0), nor a detrended record.
      if (spec.sensors.quantity == SensorQuantity::kAcceleration ||
          spec.data.conditioning.detrend != Detrend::kNone) {
        return;
      }
      Eigen::Index worst = -1;
      double worst_share = kMovingShare;
      for (Eigen::Index c = 0; c < data.values.cols(); ++c) {
        const double first = std::abs(data.values(0, c));
        const double peak = data.values.col(c).cwiseAbs().maxCoeff();
        if (!(first > worst_share * peak)) continue;
        // The noise of this channel only (no copy of a long record's matrix).
        const double noise_std =
            data.samples() >= 8
                ? std::sqrt(DifferenceNoiseVariance(data.values.col(c).transpose())[0])
                : 0.0;
        if (first > kMovingNoiseSigmas * noise_std) worst = c, worst_share = first / peak;
      }
      if (worst < 0) return;
      const std::string& name = data.channel_names[static_cast<std::size_t>(worst)];
      notes->push_back(where +
                       ": the simulation starts at rest ([initial] gives no state) at t = " +
                       ToText(t0) + " s, but the measured " + name + " is there " +
                       ToText(std::round(100 * worst_share)) + " % of its peak |" + name +
                       "|: the simulated start differs from the record's until its transient has "
                       "decayed (a free decay, never); start the window where the structure is at "
                       "rest (--window, [data] window), or give [initial] displacement and "
                       "velocity");
      return;
    }
    case InitialType::kStaticForce:
      if (!late) return;
      notes->push_back(where + ": " + window() +
                       ": the simulation starts there from [initial], the static deflection "
                       "under " +
                       ToText(spec.initial.static_force_N) + " N released at t = " + ToText(t0) +
                       " s; if it was released at the record's start, window from there "
                       "(--window, [data] window) or give [initial] displacement and velocity at " +
                       ToText(t0) + " s");
      return;
    case InitialType::kExplicit:
      if (!late) return;
      notes->push_back(where + ": " + window() +
                       ": the simulation starts there from [initial]'s displacement and "
                       "velocity, which must be the state at t = " +
                       ToText(t0) + " s, not at the record's start");
      return;
  }
}

// PrepareMeasured with the document's spec already built: ToSpec validates
// the whole case and reads its force files, once is enough.
TimeSeries Prepare(CaseDocument& document,
                   const CaseSpec& spec,
                   const TimeSeries& raw,
                   const std::string& where,
                   std::vector<std::string>* notes) {
  CheckNotDecimated(document, spec);
  TimeSeries data = ConditionMeasured(spec, raw, where, notes);
  if (data.time_s.size() == 0) ThrowInvalid(where, "a record with samples", "none");
  const double t0 = data.time_s[0];
  if (t0 != spec.time.start_s) {
    if (notes != nullptr) {
      notes->push_back(where + ": the record starts at t = " + ToText(t0) +
                       " s: the simulation starts there (time.start = " + ToText(t0) +
                       " s), force files and channels are read at the record's time");
    }
    document.SetNumber("time.start", t0);
  }
  NoteStartState(spec, raw, data, where, notes);
  return data;
}

}  // namespace

TimeSeries PrepareMeasured(CaseDocument& document,
                           const TimeSeries& raw,
                           const std::string& where,
                           std::vector<std::string>* notes) {
  return Prepare(document, document.ToSpec(), raw, where, notes);
}

TimeSeries ReadMeasured(CaseDocument& document, std::vector<std::string>* notes) {
  const CaseSpec spec = document.ToSpec();
  CheckNotDecimated(document, spec);  // before reading a long file for nothing
  const DataSpec& data = spec.data;
  if (data.file.empty()) {
    ThrowInvalid(document.source_name() + ": data.file", "a measured file", "none");
  }
  DataReadOptions read;
  read.variable = data.variable;
  read.rate_Hz = data.rate_Hz;
  read.step_s = data.step_s;
  return Prepare(document, spec, ReadTimeSeries(data.file, read, notes), data.file, notes);
}

}  // namespace podid::ident
