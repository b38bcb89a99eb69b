#include "mode_ridges.hpp"

#include <algorithm>
#include <cmath>

#include "podid/core/error.hpp"
#include "podid/wavelet/spectrum.hpp"

namespace podid::ident::internal {
namespace {

// The highest ridge frequency allowed, as a fraction of Nyquist: the
// band-limited transform needs the wavelet's band (about +-1/omega0 of the
// centre for Morlet) below Nyquist.
constexpr double kMaxBandFractionOfNyquist = 0.95;
// A lower mode's peak excludes +-1/4 octave (+-19 %): wider than the
// amplitude-dependent frequency shift of the first mode on the shared record
// (36 -> 33 Hz), narrower than the spacing of a beam's modes (x 6 and x 2.8).
constexpr double kExcludeOctaves = 0.25;

// Mode `mode`'s ridge options; appends the mode's spectral peak to *peaks_Hz
// (mode 1: inside the user's band) so that later modes look elsewhere: a
// higher POD time mode of a nonlinear response carries the first mode's
// frequency too (on the shared 1 s record, the clean V_2's periodogram peaks
// at 34 Hz below 120 Hz, though 88 % of its energy is at the second mode's 207 Hz).
wavelet::RidgeFrequencyOptions BandOf(int mode, int modes, const PodResult& pod, double step_s,
                                      const ObjectiveOptions& options, std::vector<double>* peaks_Hz,
                                      std::vector<std::string>* notes) {
  wavelet::RidgeFrequencyOptions ridge = options.ridge;
  auto& grid = ridge.cwt.frequencies;
  if (mode == 0) {
    // Mode 1's peak only serves to keep the later modes' bands off it.
    if (modes > 1) peaks_Hz->push_back(wavelet::SpectralPeak_Hz(pod.time_modes.col(0), step_s, grid.min_frequency_Hz,
                                                 grid.max_frequency_Hz));
    return ridge;
  }
  const double nyquist_Hz = 0.5 / step_s;
  const double top_Hz = kMaxBandFractionOfNyquist * nyquist_Hz;
  if (mode < static_cast<int>(options.mode_bands.size()) && !options.mode_bands[mode].follow()) {
    grid.min_frequency_Hz = options.mode_bands[mode].min_Hz;
    grid.max_frequency_Hz = options.mode_bands[mode].max_Hz;
    peaks_Hz->push_back(std::sqrt(grid.min_frequency_Hz * grid.max_frequency_Hz));
    return ridge;
  }
  const double peak_Hz = wavelet::SpectralPeak_Hz(pod.time_modes.col(mode), step_s, 0.0, top_Hz, *peaks_Hz,
                                                  kExcludeOctaves);
  peaks_Hz->push_back(peak_Hz);
  if (!std::isfinite(peak_Hz) || !(peak_Hz > 0)) {
    ThrowInvalid("mode " + ToText(mode + 1) + " of the measured data", "a time mode with a spectral peak",
                 "none (give its band with mode_bands / --mode-band)");
  }
  // The user's band's width in octaves, centred on the peak.
  const double half_octaves = 0.5 * std::log2(grid.max_frequency_Hz / grid.min_frequency_Hz);
  double low = peak_Hz * std::exp2(-half_octaves), high = peak_Hz * std::exp2(half_octaves);
  if (high > top_Hz) {
    high = top_Hz;
    low = std::min(low, high / 2.0);  // keep at least an octave below the top
  }
  grid.min_frequency_Hz = low;
  grid.max_frequency_Hz = high;
  notes->push_back("mode " + ToText(mode + 1) + ": ridge band " + ToText(low) + ".." + ToText(high) +
                   " Hz around its spectral peak at " + ToText(peak_Hz) + " Hz");
  return ridge;
}

}  // namespace

ModeRidges PrepareModeRidges(const PodResult& pod, const Eigen::VectorXd& noise_variance, double step_s,
                             int modes, const ObjectiveOptions& options) {
  ModeRidges out;
  const Eigen::Index samples = pod.time_modes.rows();
  const double duration_s = (samples - 1) * step_s;
  std::vector<double> peaks_Hz;
  for (int k = 0; k < modes; ++k) {
    out.options.push_back(BandOf(k, modes, pod, step_s, options, &peaks_Hz, &out.notes));
    const wavelet::CwtOptions& cwt = out.options.back().cwt;
    // The record must hold the cone of influence at the lowest frequency, at
    // both ends: 2 * coi_factor * the wavelet's e-folding time (sqrt(2) s for
    // Morlet, longer for Morse gamma 3 beta 20).
    const double s_min = cwt.wavelet.FrequencyToScale_s(cwt.frequencies.min_frequency_Hz);
    const double needed = 2.0 * cwt.coi_factor * cwt.wavelet.ConeOfInfluenceTime_s(s_min);
    if (duration_s <= needed) {
      ThrowInvalid("measured data", "a record longer than " + ToText(needed) +
                       " s for the wavelet objective's lowest frequency " +
                       ToText(cwt.frequencies.min_frequency_Hz) + " Hz" +
                       (k > 0 ? " of mode " + ToText(k + 1) : std::string()) +
                       " (its cone of influence; raise --fmin or give a longer record)",
                   ToText(duration_s) + " s");
    }
    wavelet::RidgeFrequencyEstimator estimator(out.options.back());
    wavelet::RidgeTrack track = estimator.Estimate(pod.time_modes.col(k), step_s);
    if (noise_variance.size() == pod.poms.rows() && options.ridge_min_snr > 0) {
      // Time mode k is X^T u_k / sigma_k: white noise of variance v_i on
      // sensor i puts variance q = sum_i u_ik^2 v_i / sigma_k^2 on each of its
      // samples, hence an rms |W| of sqrt(q) x the filter's energy.
      const double sigma = pod.singular_values[k];
      const double q = pod.poms.col(k).array().square().matrix().dot(noise_variance) / (sigma * sigma);
      const Eigen::VectorXd unit = wavelet::WhiteNoiseMagnitude(cwt, samples, step_s);
      const Eigen::Index usable_before = track.InsideCoiCount();
      for (Eigen::Index j = 0; j < track.size(); ++j) {
        if (!track.inside_coi[j]) continue;
        const double noise = std::sqrt(q) * unit[track.frequency_index[j]];
        if (!(track.amplitude[j] >= options.ridge_min_snr * noise)) track.inside_coi[j] = false;
      }
      const Eigen::Index screened = usable_before - track.InsideCoiCount();
      if (screened > 0) {
        out.notes.push_back("mode " + ToText(k + 1) + ": " + ToText(screened) + " of " +
                            ToText(usable_before) + " ridge samples inside the cone are below " +
                            ToText(options.ridge_min_snr) +
                            " x the measurement noise and are not compared");
      }
    }
    if (track.InsideCoiCount() == 0) {
      ThrowInvalid("measured data", "a ridge of mode " + ToText(k + 1) +
                       " inside the cone of influence and above the measurement noise",
                   "none (a record too short for the band, or a mode buried in noise: compare fewer modes)");
    }
    out.measured.push_back(std::move(track));
  }
  return out;
}

}  // namespace podid::ident::internal
