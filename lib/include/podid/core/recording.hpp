#pragma once
// A case's recording ([data], docs/case-file.md): the measured record mapped
// onto the case's sensors, and the same conditioning for both sides of an
// identification. Units are SI.

#include <string>
#include <vector>

#include "podid/core/case_spec.hpp"
#include "podid/core/time_series.hpp"

namespace podid {

/// The measured record as the case's identification sees it: the [data]
/// conditioning (channels, window, detrend, filter, decimate) applied, and,
/// when [data] channels are given, the channels renamed to the case's sensor
/// names in order (a note per renamed channel goes to `notes`). Throws
/// std::invalid_argument naming the case file's data.channels when they do
/// not number the sensors (`where`, the data file, names conditioning errors).
TimeSeries ConditionMeasured(const CaseSpec& spec,
                             const TimeSeries& raw,
                             const std::string& where,
                             std::vector<std::string>* notes = nullptr);

/// The simulated sensors conditioned as ConditionMeasured() conditions the
/// measured record (the same window, detrend, filter and decimation; the
/// channels are already the sensors). Returns `sensors` itself when [data]
/// asks for nothing. This is what an objective calls on every simulation.
TimeSeries ConditionSimulated(const CaseSpec& spec, const TimeSeries& sensors);

}  // namespace podid
