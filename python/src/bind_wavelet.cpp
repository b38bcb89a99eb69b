// podid.cwt(x, step_s, ...), podid.ridges(...), podid.instantaneous_frequency(...),
// podid.synchrosqueeze(...), podid.inverse_cwt(scalogram): the Morlet or Morse CWT, its
// ridges, the IF, the synchrosqueezed transform and the inverse CWT of a 1-D
// array (docs/wavelet.md).
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "podid/core/error.hpp"
#include "podid/wavelet/cwt.hpp"
#include "podid/wavelet/plans.hpp"
#include "podid/wavelet/ridge.hpp"
#include "podid/wavelet/synthesis.hpp"

namespace py = pybind11;

namespace podid::python {

std::string PythonNames(std::string message) {
  // Longest first: a shorter name is part of a longer one.
  static constexpr std::pair<std::string_view, std::string_view> kNames[] = {
      {"Cwt: frequencies.max_frequency_Hz", "fmax"},
      {"Cwt: frequencies.min_frequency_Hz", "fmin"},
      {"FrequencyGrid.min_frequency_Hz", "fmin"},
      {"FrequencyGrid.max_frequency_Hz", "fmax"},
      {"FrequencyGrid.voices_per_octave", "voices"},
      {"FrequencyGrid.bins", "bins"},
      {"FrequencyGrid: ", "voices, fmin, fmax: "},  // the log grid's count and ratio
      {"MorletWavelet.omega0", "omega0"},
      {"MorletWavelet.gamma", "gamma"},
      {"MorletWavelet.beta", "beta"},
      {"RidgeOptions.penalty_s", "penalty_s"},
      {"SynchrosqueezeOptions.relative_threshold", "threshold"},
      {"PodOptions.max_modes", "modes"},
      {"RidgeOptions.ridges", "count"},
      {"ridge method", "method"},
      {"frequency estimator", "estimator"},
      {"scale convention", "scale_convention"},
      {"CwtOptions.coi_factor", "coi_factor"},
      {"CwtOptions.threads", "threads"},
      {"CwtOptions::memory_budget_bytes", "max_memory_MB"},
      {"min_frequency_Hz", "fmin"},
      {"max_frequency_Hz", "fmax"},
      {" (or admissibility_correction = true)", ""},  // not a keyword of this module
  };
  for (const auto& [field, argument] : kNames)
    message = ReplaceAll(std::move(message), field, argument);
  return message;
}

namespace {

// Runs `compute`, its std::invalid_argument (a ValueError) in Python's names;
// the transform's checks of its input ("Cwt: signal") name `signal`.
template <typename F>
auto WithPythonNames(F&& compute, const char* signal = "x") {
  try {
    return compute();
  } catch (const std::invalid_argument& e) {
    std::string what = ReplaceAll(e.what(), "Cwt: signal", signal);
    throw std::invalid_argument(PythonNames(ReplaceAll(std::move(what), "Cwt: step_s", "step_s")));
  }
}

}  // namespace

wavelet::MorletWavelet MakeWavelet(const WaveletArguments& w) {
  wavelet::MorletWavelet psi;
  psi.omega0 = w.omega0;
  psi.gamma = w.gamma;
  psi.beta = w.beta;
  WithPythonNames([&] {
    psi.family = wavelet::ParseWaveletFamily(w.family);
    psi.normalisation = wavelet::ParseNormalisation(w.normalisation);
    psi.convention = wavelet::ParseScaleConvention(w.convention);
    return 0;
  });
  std::string why;
  if (!psi.IsValid(&why)) throw std::invalid_argument(PythonNames(why));
  return psi;
}

namespace {

wavelet::CwtOptions MakeCwtOptions(double fmin_Hz,
                                   double fmax_Hz,
                                   const IntObject& voices,
                                   const OptionalIntObject& bins,
                                   const WaveletArguments& w,
                                   const std::string& padding,
                                   double coi_factor,
                                   const IntObject& threads) {
  wavelet::CwtOptions options;
  // bins: the CLI's --bins, a linear grid instead of the log one.
  options.frequencies =
      !bins.is_none()
          ? wavelet::FrequencyGrid::Linear(fmin_Hz, fmax_Hz,
                                           IntArgument(bins, "bins",
                                                       ToText(wavelet::kMinLinearBins) + ".." +
                                                           ToText(wavelet::kMaxFrequencies)))
          : wavelet::FrequencyGrid::Log(
                fmin_Hz, fmax_Hz,
                IntArgument(voices, "voices", "1.." + ToText(wavelet::kMaxVoicesPerOctave)));
  options.wavelet = MakeWavelet(w);
  WithPythonNames([&] {
    options.padding = wavelet::ParsePadding(padding);
    return 0;
  });
  options.coi_factor = coi_factor;
  options.threads = IntArgument(threads, "threads", "1.." + ToText(wavelet::kMaxCwtThreads));
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument(PythonNames(why));
  return options;
}

// The CLI's --band-limited and --max-memory: the transform's bytes as a
// share of max_memory_MB, W's 16 bytes a coefficient out of the `cell_bytes`
// each takes (24 with the synchrosqueezed transform's reassignment field).
void ApplyOutputLimits(bool band_limited,
                       double max_memory_MB,
                       double cell_bytes,
                       wavelet::CwtOptions* options) {
  options->band_limited = band_limited;
  if (!(max_memory_MB >= wavelet::kMinMemoryLimit_MB &&
        max_memory_MB <= wavelet::kMaxMemoryLimit_MB)) {
    throw std::invalid_argument("max_memory_MB: expected " + ToText(wavelet::kMinMemoryLimit_MB) +
                                ".." + ToText(wavelet::kMaxMemoryLimit_MB) + " (MB), got " +
                                ToText(max_memory_MB));
  }
  options->memory_budget_bytes = max_memory_MB * 1048576.0 * 16.0 / cell_bytes;
}

// Keyword arguments shared by the functions (the CLI's names). The wavelet's
// and bins (a linear grid) come last: the earlier arguments keep their positions.
#define PODID_WAVELET_KWARGS                                                     \
  py::arg("wavelet") = "morlet", py::arg("gamma") = 3.0, py::arg("beta") = 20.0, \
  py::arg("normalisation") = "amplitude", py::arg("scale_convention") = "ridge", \
  py::arg("bins") = py::none()
#define PODID_WAVELET_PARAMETERS                                                          \
  const std::string &family, double gamma, double beta, const std::string &normalisation, \
      const std::string &convention, const OptionalIntObject &bins
#define PODID_WAVELET_ARGUMENTS \
  WaveletArguments { family, omega0, gamma, beta, normalisation, convention }
// The lambdas' parameters for PODID_CWT_KWARGS (or PODID_OBJECTIVE_KWARGS), and
// the options they give.
#define PODID_CWT_PARAMETERS                                                                    \
  double fmin, double fmax, const IntObject &voices, double omega0, const std::string &padding, \
      double coi_factor, const IntObject &threads, PODID_WAVELET_PARAMETERS
#define PODID_CWT_OPTIONS \
  MakeCwtOptions(fmin, fmax, voices, bins, PODID_WAVELET_ARGUMENTS, padding, coi_factor, threads)
// The CLI's defaults (podid cwt): zero padding, cone factor 2 (docs/wavelet.md).
#define PODID_CWT_KWARGS                                                             \
  py::arg("fmin") = 10.0, py::arg("fmax") = 120.0, py::arg("voices") = 32,           \
  py::arg("omega0") = 6.0, py::arg("padding") = "zero", py::arg("coi_factor") = 2.0, \
  py::arg("threads") = 1, PODID_WAVELET_KWARGS
// What the transform keeps (the CLI's --band-limited, --max-memory): after every
// other keyword, so that positions stay.
#define PODID_OUTPUT_KWARGS py::arg("band_limited") = false, py::arg("max_memory_MB") = 2048.0
// The wavelet objective's (RidgeFrequencyOptions): reflect padding, cone factor 1.
#define PODID_OBJECTIVE_KWARGS                                                          \
  py::arg("fmin") = 10.0, py::arg("fmax") = 120.0, py::arg("voices") = 32,              \
  py::arg("omega0") = 6.0, py::arg("padding") = "reflect", py::arg("coi_factor") = 1.0, \
  py::arg("threads") = 1, PODID_WAVELET_KWARGS

}  // namespace

void BindWavelet(py::module_& m) {
  py::class_<wavelet::Scalogram>(m, "Scalogram",
                                 "W(t, f) of one signal (rows: times, columns: frequencies).")
      .def_readonly("frequencies_Hz", &wavelet::Scalogram::frequencies_Hz)
      .def_readonly("scales_s", &wavelet::Scalogram::scales_s)
      .def_readonly("time_s", &wavelet::Scalogram::time_s)
      .def_readonly("coefficients", &wavelet::Scalogram::coefficients,
                    "complex (times x frequencies), in units of coefficient_scale")
      .def_readonly("magnitude", &wavelet::Scalogram::magnitude,
                    "|W| in single precision (times x frequencies, float32), in units of "
                    "coefficient_scale, when cwt(output=\"magnitude\"); then coefficients is "
                    "empty. Else empty")
      .def_readonly("coefficients_float", &wavelet::Scalogram::coefficients_float,
                    "W rounded to single precision (times x frequencies, complex64), in units "
                    "of coefficient_scale, when cwt(output=\"complex-float\"); then "
                    "coefficients is empty. Else empty")
      .def_readonly("coefficient_scale", &wavelet::Scalogram::coefficient_scale)
      .def_readonly("coi_frequency_Hz", &wavelet::Scalogram::coi_frequency_Hz,
                    "lowest frequency inside the cone of influence at each time")
      .def_readonly("decimation", &wavelet::Scalogram::decimation);

  py::class_<wavelet::RidgeTrack>(m, "RidgeTrack", "A ridge: instantaneous frequency and amplitude.")
      .def_readonly("time_s", &wavelet::RidgeTrack::time_s)
      .def_readonly("frequency_Hz", &wavelet::RidgeTrack::frequency_Hz)
      .def_readonly("grid_frequency_Hz", &wavelet::RidgeTrack::grid_frequency_Hz)
      .def_readonly("amplitude", &wavelet::RidgeTrack::amplitude)
      .def_property_readonly("inside_coi", [](const wavelet::RidgeTrack& t) {
        return Eigen::Array<bool, Eigen::Dynamic, 1>(t.inside_coi);
      });

  m.def(
      "cwt",
      [](const ArrayObject& signal, double step_s, PODID_CWT_PARAMETERS,
         const BoolObject& band_limited, double max_memory_MB, const std::string& output) {
        const RealVector x(signal, "x");
        wavelet::CwtOptions options = PODID_CWT_OPTIONS;
        // The whole budget for the transform: the library counts 16, 8 or 4 bytes a
        // coefficient by the output asked for.
        ApplyOutputLimits(BoolArgument(band_limited, "band_limited"), max_memory_MB, 16.0,
                          &options);
        options.output = wavelet::ParseCwtOutput(output);
        py::gil_scoped_release release;
        return WithPythonNames([&] { return wavelet::Cwt(x.values, step_s, options); });
      },
      py::arg("x"), py::arg("step_s"), PODID_CWT_KWARGS, PODID_OUTPUT_KWARGS,
      py::arg("output") = "complex",
      "CWT of x (1-D, sampled every step_s) on a log grid fmin..fmax Hz (voices per octave; "
      "bins=N: N linearly spaced frequencies): Morlet (omega0) or, "
      "with wavelet=\"morse\", generalised Morse (gamma, beta); normalisation \"amplitude\" "
      "(L1) or \"energy\" (L2); scale_convention \"ridge\" or \"peak\" (MATLAB, PyWavelets). "
      "band_limited: only every D-th time, D as large as the band allows (the scalogram's "
      "decimation); max_memory_MB: refuse a transform needing more (a ValueError); "
      "output=\"magnitude\": only |W|, in single precision (Scalogram.magnitude, 4 bytes a "
      "coefficient against 16); output=\"complex-float\": W computed in double precision and "
      "rounded to complex64 (Scalogram.coefficients_float, 8 bytes).");

  m.def(
      "ridges",
      [](const ArrayObject& signal, double step_s, const IntObject& count, PODID_CWT_PARAMETERS,
         const std::string& method, double penalty_s, const std::string& estimator,
         const BoolObject& band_limited, double max_memory_MB) {
        const RealVector x(signal, "x");
        wavelet::CwtOptions options = PODID_CWT_OPTIONS;
        ApplyOutputLimits(BoolArgument(band_limited, "band_limited"), max_memory_MB, 16.0,
                          &options);
        wavelet::RidgeOptions ridge;
        ridge.ridges = IntArgument(count, "count", "1.." + ToText(wavelet::kMaxRidges));
        ridge.penalty_s = penalty_s;
        WithPythonNames([&] {
          ridge.method = wavelet::ParseRidgeMethod(method);
          ridge.estimator = wavelet::ParseFrequencyEstimator(estimator);
          return 0;
        });
        std::string why;
        if (!ridge.IsValid(&why)) throw std::invalid_argument(PythonNames(why));
        py::gil_scoped_release release;
        // The ridges' checks too (penalty_s against the grid and step).
        return WithPythonNames([&] {
          wavelet::CwtTransform transform(options);
          wavelet::Scalogram scalogram;
          transform.Compute(x.values, step_s, &scalogram);
          std::vector<wavelet::RidgeTrack> tracks;
          for (const Eigen::VectorXi& path : wavelet::FindRidges(scalogram, ridge)) {
            tracks.push_back(wavelet::TrackRidge(scalogram, path, ridge, &transform));
          }
          return tracks;
        });
      },
      py::arg("x"), py::arg("step_s"), py::arg("count") = 1, PODID_CWT_KWARGS,
      py::arg("method") = "penalised", py::arg("penalty_s") = 0.05, py::arg("estimator") = "phase",
      PODID_OUTPUT_KWARGS,
      "The `count` strongest ridges of x's CWT, strongest first: method \"penalised\" (dynamic "
      "programming, a one-e-fold jump costing penalty_s) or \"max\"; the IF from the "
      "\"phase\" derivative (follows content beyond the grid) or the ridge's \"scale\" "
      "(refined between grid frequencies, always on the grid). band_limited, max_memory_MB: as "
      "for cwt.");

  py::class_<wavelet::SynchrosqueezedTransform>(m, "SynchrosqueezedTransform",
                                                "T(t, f) and the reassignment it was built from.")
      .def_readonly("sst", &wavelet::SynchrosqueezedTransform::sst,
                    "a Scalogram whose coefficients are T (times x frequencies, complex)")
      .def_readonly(
          "reassigned_frequency_Hz", &wavelet::SynchrosqueezedTransform::reassigned_frequency_Hz,
          "(times x frequencies) each CWT coefficient's IF; NaN where |W| is at most the "
          "threshold or the IF is not positive. A coefficient whose IF lies more than half a "
          "bin outside the grid is not moved")
      .def(
          "ridges",
          [](const wavelet::SynchrosqueezedTransform& sst, const IntObject& count) {
            wavelet::RidgeOptions ridge;
            ridge.ridges = IntArgument(count, "count", "1.." + ToText(wavelet::kMaxRidges));
            std::string why;
            if (!ridge.IsValid(&why)) throw std::invalid_argument(PythonNames(why));
            py::gil_scoped_release release;
            return WithPythonNames([&] { return wavelet::SynchrosqueezedRidges(sst, ridge); });
          },
          py::arg("count") = 1,
          "The `count` strongest penalised ridges of |T|, strongest first, each IF at the "
          "reassignment's fixed point (not quantised to the grid).");

  m.def(
      "synchrosqueeze",
      [](const ArrayObject& signal, double step_s, double threshold, PODID_CWT_PARAMETERS,
         const BoolObject& band_limited, double max_memory_MB) {
        const RealVector x(signal, "x");
        wavelet::CwtOptions options = PODID_CWT_OPTIONS;
        // T replaces W in place; the reassigned frequencies take 8 bytes more a coefficient.
        ApplyOutputLimits(BoolArgument(band_limited, "band_limited"), max_memory_MB, 24.0,
                          &options);
        wavelet::SynchrosqueezeOptions squeeze;
        squeeze.relative_threshold = threshold;
        std::string why;
        if (!squeeze.IsValid(&why)) throw std::invalid_argument(PythonNames(why));
        py::gil_scoped_release release;
        wavelet::CwtTransform transform(options);
        wavelet::SynchrosqueezedTransform out;
        try {
          WithPythonNames([&] {
            transform.Compute(x.values, step_s, &out.sst);
            return 0;
          });
        } catch (const std::invalid_argument& e) {
          const std::string what = e.what();
          if (what.find("(max_memory_MB)") == std::string::npos) throw;
          throw std::invalid_argument(what + " [max_memory_MB " + ToText(max_memory_MB) +
                                      " x 16 / 24: W's share of the 24 bytes a coefficient "
                                      "takes with its reassigned frequency]");
        }
        WithPythonNames([&] {
          wavelet::SynchrosqueezeInPlace(transform, squeeze, &out);  // T over W: no second matrix
          return 0;
        });
        return out;
      },
      py::arg("x"), py::arg("step_s"), py::arg("threshold") = 1e-6, PODID_CWT_KWARGS,
      PODID_OUTPUT_KWARGS,
      "Synchrosqueezed CWT of x (Daubechies, Lu & Wu 2011): each coefficient with |W| "
      "above threshold x max |W| moved to the grid frequency of its IF. band_limited, "
      "max_memory_MB: as for cwt (24 bytes a coefficient: T and the reassigned frequency).");

  m.def(
      "inverse_cwt",
      [](const wavelet::Scalogram& scalogram) {
        py::gil_scoped_release release;
        return wavelet::InverseCwt(scalogram);
      },
      py::arg("scalogram"),
      "The in-band part of the signal a podid.cwt scalogram came from, at its output times "
      "(a wavelet band-pass: the inverse CWT). It takes W: a synchrosqueezed sst's T already "
      "carries the log-scale step and comes back scaled by it (ln 2 / voices).");

  m.def(
      "plan",
      [](const IntObject& samples_, double step_s, PODID_CWT_PARAMETERS,
         const std::string& effort) {
        // The library checks the range (at least 4, at most 2^27).
        const Eigen::Index samples =
            Int64Argument(samples_, "samples", "4 to 2^27 = 134217728 samples");
        wavelet::CwtOptions options = PODID_CWT_OPTIONS;
        if (effort != "measure" && effort != "patient") {
          throw std::invalid_argument("effort: expected one of measure, patient, got \"" + effort +
                                      "\"");
        }
        // Both paths, as `podid plan` plans them: the full-rate transform
        // (cwt, ridges, synchrosqueeze) and the band-limited one
        // (instantaneous_frequency, the wavelet objective).
        wavelet::FftLengths lengths;
        WithPythonNames(
            [&] {
              for (bool band_limited : {false, true}) {
                options.band_limited = band_limited;
                wavelet::MergeFftLengths(wavelet::CwtFftLengths(options, samples, step_s),
                                         &lengths);
              }
              return 0;
            },
            "samples");
        wavelet::PlanSummary summary;
        {
          py::gil_scoped_release release;
          summary = wavelet::MeasureFftPlans(lengths, effort == "patient"
                                                          ? wavelet::PlanEffort::kPatient
                                                          : wavelet::PlanEffort::kMeasure);
        }
        py::dict planned;
        planned["real_forward"] = lengths.real_forward;
        planned["complex_forward"] = lengths.complex_forward;
        planned["complex_backward"] = lengths.complex_backward;
        planned["batched_backward"] = lengths.interleaved_backward;
        py::dict out;
        out["lengths"] = planned;
        out["measured"] = summary.measured;
        out["known"] = summary.known;
        out["seconds"] = summary.seconds;
        out["wisdom_path"] = summary.wisdom_path;
        out["saved"] = summary.saved;
        out["message"] = summary.message;
        out["ignored"] = summary.ignored;
        return out;
      },
      py::arg("samples"), py::arg("step_s"), PODID_CWT_KWARGS, py::arg("effort") = "measure",
      "Measure the FFT plans of a record of `samples` samples every step_s with these cwt keywords "
      "(the full-rate and the band-limited transform), as `podid plan` does, into the wisdom cache "
      "$XDG_CACHE_HOME/podid (else ~/.cache/podid); later calls and processes find them. A dict: "
      "'lengths', 'measured' (now), 'known' (already measured), 'seconds', 'wisdom_path', "
      "'saved', 'message' (why not saved), 'ignored' (a cache file that was not read). effort: "
      "\"measure\" (FFTW_MEASURE) or \"patient\" (FFTW_PATIENT, minutes at 10^5 samples).");

  m.def(
      "instantaneous_frequency",
      [](const ArrayObject& signal, double step_s, PODID_CWT_PARAMETERS, double max_memory_MB) {
        const RealVector x(signal, "x");
        wavelet::RidgeFrequencyOptions options;
        const bool band_limited = options.cwt.band_limited;
        options.cwt = PODID_CWT_OPTIONS;
        ApplyOutputLimits(band_limited, max_memory_MB, 16.0, &options.cwt);
        py::gil_scoped_release release;
        try {
          return WithPythonNames(
              [&] { return wavelet::RidgeFrequency(x.values, step_s, options); });
        } catch (const std::invalid_argument& e) {
          // Always band-limited: the library's advice names a keyword this function lacks.
          throw std::invalid_argument(ReplaceAll(e.what(), "fewer frequencies or band_limited",
                                                 "fewer frequencies or a larger max_memory_MB"));
        }
      },
      py::arg("x"), py::arg("step_s"), PODID_OBJECTIVE_KWARGS, py::arg("max_memory_MB") = 2048.0,
      "The IF of x along its main ridge, as the wavelet objective computes it (band-limited, "
      "decimated output times, streamed in blocks: about 1 byte a coefficient; max_memory_MB as "
      "for cwt).");
}

}  // namespace podid::python
