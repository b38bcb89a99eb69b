#include "podid/ident/objective_uncertainty.hpp"

#include <cmath>
#include <exception>
#include <random>
#include <vector>

#include "podid/core/error.hpp"
#include "podid/wavelet/ridge.hpp"

namespace podid::ident {
namespace {

// The objective's features of a response (objective_uncertainty.hpp).
class FeatureMap {
 public:
  FeatureMap(const ObjectiveFunction& objective, int weighting)
      : objective_(objective), weights_(objective.options().weightings.at(weighting).weights),
        pod_(std::make_unique<PodSolver>(objective.ResponsePodOptions())) {}

  // `response`: simulated sensors as SimulateAt returns them, already
  // conditioned as Evaluate conditions them (a second pass filtered twice).
  bool Compute(const TimeSeries& response, Eigen::VectorXd* out, std::string* why) {
    const ObjectiveOptions& o = objective_.options();
    const PodResult& m = objective_.measured_pod();
    const int k = objective_.compared_modes();
    PodResult pod = pod_->Compute(response);
    if (pod.IsDegenerate()) {
      *why = "a degenerate response: " + pod.message;
      return false;
    }
    AlignToReference(m, &pod);
    std::vector<double> f;
    const Eigen::Index sensors = pod.poms.rows(), samples = pod.time_modes.rows();
    if (weights_.u != 0) {
      const double w = std::sqrt(weights_.u);
      for (int c = 0; c < k; ++c)
        for (Eigen::Index i = 0; i < sensors; ++i) f.push_back(w * pod.poms(i, c));
    }
    if (weights_.s != 0) {
      const double w = std::sqrt(weights_.s);
      for (int c = 0; c < k; ++c) {
        f.push_back(w * pod.singular_values[c] / (o.relative_sigma ? m.singular_values[c] : 1.0));
      }
    }
    if (weights_.v != 0) {
      const double w = std::sqrt(weights_.v);
      for (int c = 0; c < k; ++c)
        for (Eigen::Index n = 0; n < samples; ++n) f.push_back(w * pod.time_modes(n, c));
    }
    if (weights_.f != 0) {
      if (ridges_.empty()) {
        for (int c = 0; c < k; ++c) {
          ridges_.push_back(std::make_unique<wavelet::RidgeFrequencyEstimator>(objective_.mode_ridge_options(c)));
        }
      }
      for (int c = 0; c < k; ++c) {
        const wavelet::RidgeTrack& meas = objective_.measured_ridges().at(c);
        const wavelet::RidgeTrack& sim = ridges_[c]->Estimate(pod.time_modes.col(c), response.step_s());
        if (sim.size() != meas.size()) {
          *why = "a ridge of another length than the measured one";
          return false;
        }
        const double w = std::sqrt(weights_.f * ridges_[c]->scalogram().decimation);
        for (Eigen::Index j = 0; j < meas.size(); ++j) {
          if (!meas.inside_coi[j]) continue;
          const double ratio = sim.frequency_Hz[j] / meas.frequency_Hz[j];
          f.push_back(w * (std::isfinite(ratio) ? ratio : 0.0));
        }
      }
    }
    *out = Eigen::Map<const Eigen::VectorXd>(f.data(), static_cast<Eigen::Index>(f.size()));
    return true;
  }

 private:
  const ObjectiveFunction& objective_;
  ObjectiveWeights weights_;
  std::unique_ptr<PodSolver> pod_;
  std::vector<std::unique_ptr<wavelet::RidgeFrequencyEstimator>> ridges_;
};

// Callbacks must not throw (uncertainty.hpp): anything becomes a reason.
template <typename F>
bool NoThrow(std::string* why, F&& f) {
  try {
    return f();
  } catch (const std::exception& e) {
    *why = e.what();
  } catch (...) {
    *why = "unknown exception";
  }
  return false;
}

}  // namespace

ParameterUncertainty ObjectiveUncertainty(const ObjectiveFunction& objective, const Eigen::VectorXd& values,
                                          int weighting, const UncertaintyOptions& options,
                                          std::uint64_t seed) {
  const int p = objective.parameter_count();
  if (values.size() != p) ThrowInvalid("uncertainty: values", ToText(p) + " values", ToText(values.size()));
  if (weighting < 0 || weighting >= objective.weighting_count()) {
    ThrowInvalid("uncertainty: weighting", "0.." + ToText(objective.weighting_count() - 1), ToText(weighting));
  }
  Eigen::VectorXd lower(p), upper(p);
  for (int i = 0; i < p; ++i) {
    lower[i] = objective.parameters()[i].lower;
    upper[i] = objective.parameters()[i].upper;
  }
  FeatureMap map(objective, weighting);
  // One cached simulator for the fit and its 2p perturbations: a typed
  // parameter rebuilds only what it invalidates (a file force is not
  // interpolated again for each one).
  EvaluationWorkspace workspace;
  const FeatureFunction features = [&](const Eigen::VectorXd& theta, Eigen::VectorXd* f, std::string* why) {
    return NoThrow(why, [&] {
      const SimulationResult sim = objective.SimulateAt(theta, &workspace);
      if (!sim.summary.IsSolutionUsable()) {
        *why = sim.summary.message;
        return false;
      }
      return map.Compute(sim.sensors, f, why);
    });
  };

  // The fitted response and the residual's variance per channel.
  ParameterUncertainty failed;
  std::string why;
  SimulationResult fit;
  Eigen::VectorXd fit_features;
  const bool ok = NoThrow(&why, [&] {
    fit = objective.SimulateAt(values, &workspace);
    if (!fit.summary.IsSolutionUsable()) {
      why = fit.summary.message;
      return false;
    }
    return map.Compute(fit.sensors, &fit_features, &why);
  });
  if (!ok) {
    failed.message = "the response at the parameters: " + why;
    return failed;
  }
  const Eigen::MatrixXd& y = fit.sensors.values;
  const Eigen::MatrixXd& measured = objective.measured().values;
  if (y.rows() != measured.rows() || y.cols() != measured.cols()) {
    failed.message = "the simulated record does not cover the measured one";
    return failed;
  }
  const Eigen::RowVectorXd noise_std =
      ((measured - y).colwise().squaredNorm() / static_cast<double>(y.rows())).cwiseSqrt();
  std::mt19937_64 engine(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  TimeSeries noisy = fit.sensors;
  FeatureMap draw_map(objective, weighting);
  const FeatureNoiseDraw noise = [&](int, Eigen::VectorXd* delta, std::string* why_draw) {
    return NoThrow(why_draw, [&] {
      for (Eigen::Index c = 0; c < y.cols(); ++c)
        for (Eigen::Index n = 0; n < y.rows(); ++n) noisy.values(n, c) = y(n, c) + noise_std[c] * normal(engine);
      if (!draw_map.Compute(noisy, delta, why_draw)) return false;
      if (delta->size() != fit_features.size()) {
        *why_draw = "a noise draw changed the number of features";
        return false;
      }
      *delta -= fit_features;
      return true;
    });
  };
  ParameterUncertainty result = SandwichUncertainty(features, noise, values, lower, upper, options);
  if (result.usable) {
    result.message += "; noise std per channel from the residual at the parameters";
  }
  return result;
}

}  // namespace podid::ident
