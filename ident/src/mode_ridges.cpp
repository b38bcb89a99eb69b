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

// How messages name mode `mode`'s band: the field and option that set it.
std::string BandSource(int mode, const ObjectiveOptions& options) {
  if (mode == 0) return "ridge.cwt.frequencies, --fmin/--fmax";
  const std::string k = ToText(mode + 1);
  if (mode < static_cast<int>(options.mode_bands.size()) && !options.mode_bands[mode].follow()) {
    return "mode_bands[" + ToText(mode) + "], --mode-band " + k;
  }
  return "around its spectral peak; mode_bands, --mode-band " + k;
}

// The filter conditions the measured and the simulated records alike: beyond
// its cutoff both hold only what its skirt lets through (gain 1/2 at the
// cutoff, about 1/(1 + 4^order) an octave beyond), so a ridge there compares the
// filter, not the structure. A band wholly beyond is a contradiction; a band
// partly beyond gets a note with the share cut, in octaves as the ridge's
// grid (voices per octave) counts it, unless less than one step of that grid
// (a followed band that grazes the cutoff). The order does not move the edge: a
// lower order lets more of the stopband through, which was asked away.
void CheckBandInPassband(int mode,
                         const wavelet::CwtOptions& cwt,
                         const FilterOptions& filter,
                         const ObjectiveOptions& options,
                         std::vector<std::string>* notes) {
  if (filter.type == FilterType::kNone) return;
  const double pass_low = filter.PassbandLow_Hz(), pass_high = filter.PassbandHigh_Hz();
  const double low = cwt.frequencies.min_frequency_Hz, high = cwt.frequencies.max_frequency_Hz;
  const std::string kind = ToString(filter.type);
  const std::string names = "order " + ToText(filter.order) + "; data.filter, --" + kind;
  const std::string band = ToText(low) + ".." + ToText(high) + " Hz";
  const std::string passband = filter.DescribePassband();
  if (high <= pass_low || low >= pass_high) {
    const bool above = low >= pass_high;
    ThrowInvalid("mode " + ToText(mode + 1) + "'s ridge band (" + BandSource(mode, options) + ")",
                 "a band reaching into the passband of the data's " + kind + " filter, " +
                     passband + " (" + names +
                     "; it conditions the measured and the simulated records alike)",
                 band + ", entirely " + (above ? "above" : "below") + " its cutoff " +
                     ToText(above ? pass_high : pass_low) + " Hz");
  }
  const double below_octaves = low < pass_low ? std::log2(pass_low / low) : 0.0;
  const double above_octaves = high > pass_high ? std::log2(high / pass_high) : 0.0;
  if (below_octaves + above_octaves >= 1.0 / cwt.frequencies.voices_per_octave) {
    const double octaves = std::log2(high / low);
    const std::string side =
        below_octaves > 0 && above_octaves > 0
            ? "outside the data's " + kind + " filter's passband " + passband
        : below_octaves > 0 ? "below the data's " + kind + " cutoff " + ToText(pass_low) + " Hz"
                            : "above the data's " + kind + " cutoff " + ToText(pass_high) + " Hz";
    notes->push_back(
        "mode " + ToText(mode + 1) + ": " + ToShortText(below_octaves + above_octaves) +
        " of the ridge band's " + ToShortText(octaves) + " octaves (" + band + "; " +
        BandSource(mode, options) + "), " +
        ToShortText(100 * (below_octaves + above_octaves) / octaves) + " %, lie " + side + " (" +
        names +
        "), where the filter leaves both records only its skirt: keep the band inside the "
        "passband, e.g. " +
        ToText(std::max(low, pass_low)) + ".." + ToText(std::min(high, pass_high)) + " Hz");
  }
}

// The IFs of output times closer than the wavelet's duration (its e-folding
// time 2 sigma_t s at the ridge's frequency) come from overlapping stretches
// of the record, so the time compared over that duration is about the number
// of independent IF values the term holds, whatever the decimation (a wider
// band only samples the same stretch more densely). A short record, a wide
// cone or a mode mostly below the noise leaves a handful: the fit's IF term
// then rests on them. Says so, with what would give more.
void NoteFewRidgeSamples(int mode,
                         const wavelet::RidgeTrack& track,
                         Eigen::Index inside_cone,
                         int decimation,
                         double step_s,
                         double record_s,
                         const wavelet::CwtOptions& cwt,
                         const ObjectiveOptions& options,
                         std::vector<std::string>* notes) {
  const Eigen::Index compared = track.InsideCoiCount();
  if (compared == 0) return;  // refused by the caller
  std::vector<double> frequencies;
  for (Eigen::Index j = 0; j < track.size(); ++j) {
    if (track.inside_coi[j]) frequencies.push_back(track.grid_frequency_Hz[j]);
  }
  auto middle = frequencies.begin() + static_cast<std::ptrdiff_t>(frequencies.size() / 2);
  std::nth_element(frequencies.begin(), middle, frequencies.end());
  const double ridge_Hz = *middle;
  const double wavelet_s =
      cwt.wavelet.ConeOfInfluenceTime_s(cwt.wavelet.FrequencyToScale_s(ridge_Hz));
  const double compared_s = static_cast<double>(compared) * decimation * step_s;
  const double durations = compared_s / wavelet_s;
  if (durations >= kMinRidgeWaveletDurations) return;
  std::string remedies = "a longer record";
  if (cwt.wavelet.family == wavelet::WaveletFamily::kMorse) {
    remedies += ", a shorter wavelet (--wavelet morlet, or a smaller --beta)";
  } else if (cwt.wavelet.omega0 > wavelet::kMinOmega0) {
    remedies += ", a shorter wavelet (--omega0 below " + ToText(cwt.wavelet.omega0) + ", " +
                ToText(wavelet::kMinOmega0) + " at least)";
  }
  if (compared < inside_cone) {
    remedies += ", a lower --ridge-snr (" + ToText(inside_cone - compared) + " of the " +
                ToText(inside_cone) + " samples inside the cone are below " +
                ToText(options.ridge_min_snr) + " x the noise)";
  }
  notes->push_back(
      "mode " + ToText(mode + 1) + ": only " + ToText(compared) + " of the ridge's " +
      ToText(track.size()) +
      " samples are compared (samples_compared: inside the cone of influence and above the "
      "noise), " +
      ToShortText(compared_s) + " s of the " + ToShortText(record_s) +
      " s record: " + ToShortText(durations) + " wavelet durations at the ridge's " +
      ToShortText(ridge_Hz) + " Hz (" + ToShortText(wavelet_s) +
      " s each, over which its IFs are correlated), fewer than " +
      ToText(kMinRidgeWaveletDurations) +
      ", so the IF term rests on a handful of independent values; for a sounder fit give " +
      remedies);
}

}  // namespace

ModeRidges PrepareModeRidges(const PodResult& pod,
                             const Eigen::VectorXd& noise_variance,
                             double step_s,
                             int modes,
                             const ObjectiveOptions& options,
                             const FilterOptions& filter) {
  ModeRidges out;
  const Eigen::Index samples = pod.time_modes.rows();
  const double duration_s = (samples - 1) * step_s;
  std::vector<double> peaks_Hz;
  for (int k = 0; k < modes; ++k) {
    out.options.push_back(BandOf(k, modes, pod, step_s, options, &peaks_Hz, &out.notes));
    const wavelet::CwtOptions& cwt = out.options.back().cwt;
    CheckBandInPassband(k, cwt, filter, options, &out.notes);
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
    const Eigen::Index inside_cone = track.InsideCoiCount();
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
      ThrowInvalid(
          "measured data",
          "a ridge of mode " + ToText(k + 1) +
              " inside the cone of influence and above the measurement noise",
          "none of its " + ToText(track.size()) + " samples (" + ToText(inside_cone) +
              " inside the cone" +
              (inside_cone > 0 ? ", all below " + ToText(options.ridge_min_snr) +
                                     " x the noise: lower --ridge-snr, or compare fewer modes)"
                               : ": give a longer record)"));
    }
    NoteFewRidgeSamples(k, track, inside_cone, estimator.scalogram().decimation, step_s, duration_s,
                        cwt, options, &out.notes);
    out.measured.push_back(std::move(track));
  }
  return out;
}

}  // namespace podid::ident::internal
