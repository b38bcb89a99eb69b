#pragma once
// The Silverbox record and examples/silverbox's case around it, shared by
// the benchmarks that run it (ident, simulate and wavelet_benchmark).
#include <benchmark/benchmark.h>

#include <fstream>
#include <optional>
#include <string>

#include "podid/core/case_file.hpp"

namespace podid {

/// ../shared/realdata/silverbox/SNLS80mV.mat (V1 the force, V2 the output).
inline std::string SilverboxMat() {
  return std::string(PODID_TEST_DATA_DIR) + "/../../../shared/realdata/silverbox/SNLS80mV.mat";
}

/// The record's step: 2^14 / 10^7 s (610.35 Hz; the file has no time vector).
inline const double kSilverboxStep_s = 16384.0 / 1e7;

/// Whether SilverboxMat() is there; if not, the benchmark is skipped.
inline bool HaveSilverbox(benchmark::State& state) {
  if (std::ifstream(SilverboxMat()).good()) return true;
  state.SkipWithError("no ../shared/realdata/silverbox/SNLS80mV.mat");
  return false;
}

/// examples/silverbox/silverbox.toml with data.file set to SilverboxMat();
/// nullopt, and the benchmark skipped, when the file is not there.
inline std::optional<CaseDocument> SilverboxCase(benchmark::State& state) {
  if (!HaveSilverbox(state)) return std::nullopt;
  CaseDocument document = CaseDocument::Load(std::string(PODID_EXAMPLES_DIR) + "/silverbox/silverbox.toml");
  document.Set("data.file", "\"" + SilverboxMat() + "\"");
  return document;
}

}  // namespace podid
