#include "podid/ident/measured_record.hpp"

#include "podid/core/error.hpp"
#include "podid/core/io.hpp"
#include "podid/core/recording.hpp"

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
