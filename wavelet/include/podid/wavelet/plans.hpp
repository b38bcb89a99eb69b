#pragma once
// FFT planning without a per-process penalty.
//
// FFTW makes a plan per transform length. Measuring the fastest plan
// (FFTW_MEASURE) costs far more than one transform (about 0.1 s at 10^4
// points, seconds at 10^6), so a one-shot `podid cwt` used to spend most of
// its time planning. podid therefore keeps FFTW's wisdom (the measured plans)
// on disk and otherwise plans with FFTW_ESTIMATE (microseconds):
//
//   cache file   $XDG_CACHE_HOME/podid/fftw3-wisdom (an absolute XDG_CACHE_HOME),
//                else $HOME/.cache/podid/fftw3-wisdom; no cache if neither is set.
//   reading      once per process and cache path, before the first plan, by podid
//                itself (FFTW's reader hangs on a FIFO and aborts on some malformed
//                entries): a missing file, one that is not a regular file, unreadable,
//                over 16 MiB, not in the shape FFTW exports, or foreign (another FFTW
//                version or build) is ignored, and replaced at the next writing.
//   effort       FFTW_MEASURE by default; MeasureFftPlans (`podid plan --effort patient`)
//                can search harder (FFTW_PATIENT). A transform uses the most rigorous
//                plan the wisdom holds for its length.
//   writing      only after measuring (MeasureFftPlans, `podid plan`, or a transform
//                with FftPlanning::kMeasure): the cache folder is created (0700) on
//                first use, the file is merged with what is already there, written
//                to a unique temporary file in the same folder and renamed over the
//                old one, so concurrent processes never see a partial file (the last
//                writer wins; the lost wisdom is only a slower plan). A folder that
//                cannot be written is reported in the summary, never fatal.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "podid/wavelet/cwt.hpp"

namespace podid::wavelet {

/// The cache file's path, "" when neither XDG_CACHE_HOME (absolute) nor HOME is set.
std::string FftWisdomPath();

/// The FFT lengths a CwtTransform with `options` uses for `samples` input
/// samples at step_s: CwtTransform(options).Lengths(samples, step_s).
FftLengths CwtFftLengths(const CwtOptions& options, Eigen::Index samples, double step_s);

/// Adds `more`'s lengths to *lengths: afterwards each list is sorted and
/// holds each length once (the lengths of several records or paths, planned
/// once each).
void MergeFftLengths(const FftLengths& more, FftLengths* lengths);

struct PlanSummary {
  int measured = 0;      ///< plans measured now
  int known = 0;         ///< plans already measured (wisdom in the cache or this process)
  double seconds = 0.0;  ///< wall time spent measuring
  std::string wisdom_path;
  bool saved = false;   ///< the cache file was written
  std::string message;  ///< why the cache was not written ("" when saved or nothing new)
  std::string
      ignored;  ///< why the cache file was ignored ("path: reason"; "" when read or missing)
};

/// How hard MeasureFftPlans searches: FFTW's planner flags. Transforms take
/// the most rigorous plan the wisdom holds for a length.
enum class PlanEffort {
  kMeasure,  ///< FFTW_MEASURE: seconds (14 s for the plans of fCWT's 10^5-sample case)
  kPatient,  ///< FFTW_PATIENT: minutes at 10^5 samples, for transforms up to about 1.07x faster
};

/// Measures every listed plan that has no wisdom of at least `effort` yet and
/// saves the wisdom to FftWisdomPath(). Lengths are checked (1 .. 2^27); bad
/// ones throw std::invalid_argument before anything is measured.
PlanSummary MeasureFftPlans(const FftLengths& lengths, PlanEffort effort = PlanEffort::kMeasure);

}  // namespace podid::wavelet
