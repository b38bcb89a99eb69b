#pragma once
// The measured record an ObjectiveFunction compares, prepared from the case's
// [data] (docs/case-file.md) in one place for podid identify / landscape and
// the Python module: one side conditioned and the other not gave objectives
// that were wrong without an error.

#include <string>
#include <vector>

#include "podid/core/case_file.hpp"
#include "podid/core/time_series.hpp"

namespace podid::ident {

/// `raw` as ObjectiveFunction compares it with the simulation:
/// - the [data] conditioning applied (ConditionMeasured: channels, window,
///   detrend, filter); every simulation is conditioned alike
///   (ConditionSimulated);
/// - the document's time.start set to the record's first stamp, so that the
///   simulation and its force files and channels run on the record's time
///   axis (a note goes to `notes` when it changes).
/// Decimation is refused: the simulation runs on the measured grid, which
/// decimation would coarsen. `where` names the record in messages. Throws
/// std::invalid_argument.
TimeSeries PrepareMeasured(CaseDocument& document,
                           const TimeSeries& raw,
                           const std::string& where,
                           std::vector<std::string>* notes = nullptr);

/// The case's [data] file, read with [data]'s reading options (variable, rate,
/// step) and prepared by PrepareMeasured. Throws std::invalid_argument when
/// [data] names no file, when the file cannot be read, or as PrepareMeasured.
TimeSeries ReadMeasured(CaseDocument& document, std::vector<std::string>* notes = nullptr);

}  // namespace podid::ident
