#include "podid/ident/identify.hpp"

#include <nlopt.h>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <exception>
#include <random>
#include <sstream>

#include "podid/core/error.hpp"
#include "podid/ident/landscape.hpp"  // kMaxThreads
#include "podid/ident/objective_uncertainty.hpp"
#include "worker_threads.hpp"

namespace podid::ident {
namespace {

struct AlgorithmName {
  Algorithm algorithm;
  const char* name;
  nlopt_algorithm nlopt;
};

constexpr AlgorithmName kAlgorithms[] = {
    {Algorithm::kLnBobyqa, "LN_BOBYQA", NLOPT_LN_BOBYQA},
    {Algorithm::kLnNelderMead, "LN_NELDERMEAD", NLOPT_LN_NELDERMEAD},
    {Algorithm::kLnSbplx, "LN_SBPLX", NLOPT_LN_SBPLX},
    {Algorithm::kLnCobyla, "LN_COBYLA", NLOPT_LN_COBYLA},
    {Algorithm::kGnDirectL, "GN_DIRECT_L", NLOPT_GN_DIRECT_L},
    {Algorithm::kGnCrs2Lm, "GN_CRS2_LM", NLOPT_GN_CRS2_LM},
    {Algorithm::kGnIsres, "GN_ISRES", NLOPT_GN_ISRES},
    {Algorithm::kGnMlslLds, "GN_MLSL_LDS", NLOPT_G_MLSL_LDS},
};

nlopt_algorithm ToNlopt(Algorithm a) {
  for (const AlgorithmName& n : kAlgorithms)
    if (n.algorithm == a) return n.nlopt;
  PODID_CHECK(false);
  return NLOPT_LN_BOBYQA;
}

Termination FromNlopt(nlopt_result r) {
  switch (r) {
    case NLOPT_SUCCESS:
    case NLOPT_STOPVAL_REACHED:
    case NLOPT_FTOL_REACHED:
    case NLOPT_XTOL_REACHED:
      return Termination::kConverged;
    case NLOPT_MAXEVAL_REACHED: return Termination::kMaxEvaluations;
    case NLOPT_MAXTIME_REACHED: return Termination::kMaxTime;
    case NLOPT_ROUNDOFF_LIMITED: return Termination::kRoundoffLimited;
    case NLOPT_INVALID_ARGS: return Termination::kInvalidArguments;
    case NLOPT_FORCED_STOP: return Termination::kInterrupted;
    case NLOPT_FAILURE:
    case NLOPT_OUT_OF_MEMORY:
    default:
      return Termination::kFailure;
  }
}

const char* NloptResultText(nlopt_result r) {
  switch (r) {
    case NLOPT_SUCCESS: return "NLOPT_SUCCESS";
    case NLOPT_STOPVAL_REACHED: return "NLOPT_STOPVAL_REACHED";
    case NLOPT_FTOL_REACHED: return "NLOPT_FTOL_REACHED (relative change of the objective below ftol_rel)";
    case NLOPT_XTOL_REACHED: return "NLOPT_XTOL_REACHED (relative step below xtol_rel)";
    case NLOPT_MAXEVAL_REACHED: return "NLOPT_MAXEVAL_REACHED (evaluation budget exhausted)";
    case NLOPT_MAXTIME_REACHED: return "NLOPT_MAXTIME_REACHED (time limit)";
    case NLOPT_FAILURE: return "NLOPT_FAILURE (generic failure)";
    case NLOPT_INVALID_ARGS: return "NLOPT_INVALID_ARGS";
    case NLOPT_OUT_OF_MEMORY: return "NLOPT_OUT_OF_MEMORY";
    case NLOPT_ROUNDOFF_LIMITED: return "NLOPT_ROUNDOFF_LIMITED (round-off limited progress)";
    case NLOPT_FORCED_STOP: return "NLOPT_FORCED_STOP (cancelled)";
    default: return "unknown NLopt result";
  }
}

struct RunState {
  const ObjectiveFunction* objective = nullptr;
  int weighting = 0;
  const std::atomic<bool>* cancel = nullptr;
  nlopt_opt opt = nullptr;
  EvaluationWorkspace workspace;
  Eigen::VectorXd x;
  int start = 0;
  int evaluations = 0;
  int failed = 0;
  double best = std::numeric_limits<double>::infinity();
  double worst = 0.0;  ///< the largest value of a non-failed evaluation
  Eigen::VectorXd best_x;
  TermValues best_terms;
  std::string first_failure;  ///< the reason of the first failed evaluation
  std::vector<IterationRecord> history;
  nlopt_result result = NLOPT_FAILURE;
  std::exception_ptr error;  ///< what stopped this start (rethrown after the parallel region)
  /// Shared by the starts (Identify sets it before a start runs): set with an
  /// `error`, so that the other starts stop at their next evaluation and the
  /// progress callback is not called again.
  std::atomic<bool>* stopped = nullptr;
  const ProgressCallback* progress = nullptr;
  std::atomic<long long>* progress_done = nullptr;  ///< shared by the starts
  std::atomic<long long>* progress_failed = nullptr;
  long long progress_total = 0;
  std::chrono::steady_clock::time_point start_time;
  // The start's own evaluation, made before NLopt's (which may begin
  // elsewhere): when NLopt asks for the same point it gets this value again
  // without a second simulation or record.
  Eigen::VectorXd first_x;
  double first_value = 0.0;
  bool first_pending = false;
  TermValues first_terms;
};

bool Stopping(const RunState& s) { return (s.cancel && s.cancel->load()) || s.stopped->load(); }

// A failed evaluation's value is at least this multiple of the largest value
// seen in its start: above it, finite, and not so far above that a quadratic
// model (BOBYQA) built through it is dominated by it.
constexpr double kFailureOverWorst = 2.0;

// Records what stopped start `s` and tells the other starts to stop.
void Fail(RunState& s, std::exception_ptr error) {
  s.error = std::move(error);
  s.stopped->store(true);
}

double EvaluateOrThrow(unsigned n, const double* x, RunState& s) {
  s.x = Eigen::Map<const Eigen::VectorXd>(x, n);
  if (s.first_pending && s.x == s.first_x) {
    s.first_pending = false;
    if (Stopping(s) && s.opt) nlopt_force_stop(s.opt);
    return s.first_value;
  }
  s.first_pending = false;
  Evaluation evaluation = s.objective->Evaluate(s.x, &s.workspace);
  const TermValues& terms = evaluation.terms;
  double value = static_cast<std::size_t>(s.weighting) < evaluation.values.size()
                     ? evaluation.values[s.weighting]
                     : s.objective->options().failure_value;
  // A failed point must look worse to the optimiser than every point it has
  // seen: with objectives above failure_value (1e3: 13234 with --modes 6)
  // the search walked into the failing region.
  if (terms.failed) {
    value = std::max(value, kFailureOverWorst * s.worst);
  } else {
    s.worst = std::max(s.worst, value);
  }
  ++s.evaluations;
  if (terms.failed && s.failed++ == 0) s.first_failure = terms.failure;  // the start, when all fail
  if (!terms.failed && value < s.best) {
    s.best = value;
    s.best_x = s.x;
    s.best_terms = terms;
  }
  IterationRecord record;
  record.evaluation = s.evaluations;
  record.start = s.start;
  record.parameters = s.x;
  record.objective = value;
  record.best_objective = s.best;
  record.failed = terms.failed;
  if (terms.failed) record.failure = terms.failure;
  if (s.evaluations == 1) s.first_terms = terms;
  s.history.push_back(std::move(record));
  if (s.progress && *s.progress) {
    const long long done = ++*s.progress_done;
    const long long failed = *s.progress_failed += terms.failed ? 1 : 0;
    Progress progress;
    progress.done = done;
    progress.total = s.progress_total;
    progress.failed = failed;
    progress.elapsed_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - s.start_time).count();
    // No exception may leave the critical region: it stops every start and
    // is rethrown by Identify() after the parallel region. Once it has, the
    // callback is not called again.
    std::exception_ptr progress_error;
#pragma omp critical(podid_identify_progress)
    {
      if (!s.stopped->load()) {
        try {
          (*s.progress)(progress);
        } catch (...) {
          progress_error = std::current_exception();
          s.stopped->store(true);  // before the next thread enters, not after Fail()
        }
      }
    }
    if (progress_error) std::rethrow_exception(progress_error);
  }
  if (Stopping(s) && s.opt) nlopt_force_stop(s.opt);
  return value;
}

// NLopt's C callback: no exception may cross it. Evaluate() never throws; what
// remains (e.g. no memory for the history, a progress callback's exception)
// stops every start and is rethrown by Identify() after the parallel region.
double Evaluate(unsigned n, const double* x, double* gradient, void* data) noexcept {
  RunState& s = *static_cast<RunState*>(data);
  PODID_CHECK(gradient == nullptr);  // derivative-free algorithms only
  try {
    return EvaluateOrThrow(n, x, s);
  } catch (...) {
    Fail(s, std::current_exception());
    nlopt_force_stop(s.opt);
    return s.objective->options().failure_value;
  }
}

// Latin hypercube: one point per stratum of each axis, strata shuffled.
std::vector<Eigen::VectorXd> LatinHypercube(int points, const Eigen::VectorXd& lower,
                                            const Eigen::VectorXd& upper, std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  auto uniform = [&engine] { return static_cast<double>(engine() >> 11) * 0x1.0p-53; };
  const Eigen::Index d = lower.size();
  std::vector<Eigen::VectorXd> out(points, Eigen::VectorXd(d));
  for (Eigen::Index k = 0; k < d; ++k) {
    std::vector<int> strata(points);
    for (int i = 0; i < points; ++i) strata[i] = i;
    for (int i = points - 1; i > 0; --i) std::swap(strata[i], strata[engine() % (i + 1)]);
    for (int i = 0; i < points; ++i) {
      out[i][k] = lower[k] + (upper[k] - lower[k]) * (strata[i] + uniform()) / points;
    }
  }
  return out;
}

}  // namespace

Algorithm ParseAlgorithm(std::string_view name) {
  std::string upper(name);
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  for (const AlgorithmName& n : kAlgorithms)
    if (upper == n.name) return n.algorithm;
  std::string choices;
  for (const AlgorithmName& n : kAlgorithms) choices += std::string(choices.empty() ? "" : ", ") + n.name;
  ThrowInvalid("algorithm", "one of " + choices, Excerpt(name));
}

const char* ToString(Algorithm algorithm) {
  for (const AlgorithmName& n : kAlgorithms)
    if (n.algorithm == algorithm) return n.name;
  return "unknown";
}

bool IsLocal(Algorithm a) {
  return a == Algorithm::kLnBobyqa || a == Algorithm::kLnNelderMead || a == Algorithm::kLnSbplx ||
         a == Algorithm::kLnCobyla;
}

const char* ToString(Termination t) {
  switch (t) {
    case Termination::kNotRun: return "not run";
    case Termination::kConverged: return "converged";
    case Termination::kMaxEvaluations: return "evaluation budget exhausted";
    case Termination::kMaxTime: return "time limit reached";
    case Termination::kRoundoffLimited: return "round-off limited";
    case Termination::kFailure: return "optimiser failure";
    case Termination::kInvalidArguments: return "invalid arguments";
    case Termination::kInterrupted: return "interrupted";
    case Termination::kAllEvaluationsFailed: return "all evaluations failed";
  }
  return "unknown";
}

bool IdentifyOptions::IsValid(int parameter_count, std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!IsLocal(local_algorithm))
    return fail(std::string("local algorithm: expected an LN_ algorithm, got ") + ToString(local_algorithm));
  if (start.size() != 0 && start.size() != parameter_count)
    return fail("start: expected " + ToText(parameter_count) + " values, got " + ToText(start.size()));
  // Finite: NLopt stops at its first step on an infinite relative tolerance.
  if (!(xtol_rel > 0 && std::isfinite(xtol_rel)))
    return fail("xtol_rel: expected a finite value > 0, got " + ToText(xtol_rel));
  if (!(ftol_rel >= 0 && std::isfinite(ftol_rel)))
    return fail("ftol_rel: expected a finite value >= 0, got " + ToText(ftol_rel));
  if (max_evaluations < 1 || max_evaluations > kMaxEvaluations)
    return fail("max_evaluations: expected 1 to " + ToText(kMaxEvaluations) + ", got " +
                ToText(max_evaluations));
  if (!(max_time_s >= 0)) return fail("max_time_s: expected >= 0, got " + ToText(max_time_s));
  if (multistart < 1 || multistart > kMaxMultistart)
    return fail("multistart: expected 1 to " + ToText(kMaxMultistart) + ", got " +
                ToText(multistart));
  std::string uncertainty_why;
  if (uncertainty && !uncertainty_options.IsValid(&uncertainty_why))
    return fail("uncertainty: " + uncertainty_why);
  if (threads < 0 || threads > kMaxThreads)
    return fail("threads: expected 0 to " + ToText(kMaxThreads) + ", got " + ToText(threads));
  if (share_count < 1 || share_count > 65536 || share_index < 0 || share_index >= share_count)
    return fail("share: expected 0 <= index < count <= 65536, got " + ToText(share_index) + " of " +
                ToText(share_count));
  if (static_cast<long long>(multistart) * max_evaluations > kMaxTotalEvaluations)
    return fail("multistart * max_evaluations: expected at most " +
                ToText(kMaxTotalEvaluations) + " evaluations in all, got " +
                ToText(multistart) + " * " + ToText(max_evaluations));
  return true;
}

bool IdentifySummary::IsSolutionUsable() const {
  switch (termination) {
    case Termination::kConverged:
    case Termination::kMaxEvaluations:
    case Termination::kMaxTime:
    case Termination::kRoundoffLimited:
      return std::isfinite(final_objective);
    default:
      return false;
  }
}

std::string TermContributions(const TermValues& terms, const ObjectiveWeights& weights) {
  if (terms.failed) return {};
  const double total = terms.Combine(weights, std::numeric_limits<double>::quiet_NaN());
  if (!(total > 0)) return {};
  std::ostringstream os;
  os.precision(3);
  bool first = true;
  auto add = [&](double w, double value, const char* name) {
    if (w == 0) return;
    os << (first ? "" : ", ") << name << " " << 100 * w * value / total << " %";
    first = false;
  };
  add(weights.u, terms.u, "dU");
  add(weights.s, terms.s, "dS");
  add(weights.v, terms.v, "dV");
  add(weights.f, terms.f, "dIF");
  return os.str();
}

std::string IdentifySummary::BriefReport() const {
  std::ostringstream os;
  os.precision(6);
  os << "identify (" << algorithm << ", " << objective << "): " << ToString(termination) << ", ";
  for (std::size_t i = 0; i < parameter_names.size() && i < static_cast<std::size_t>(parameters.size()); ++i) {
    os << parameter_names[i] << " = " << parameters[i];
    if (uncertainty.usable && static_cast<Eigen::Index>(i) < uncertainty.lower.size()) {
      os << " (" << 100 * uncertainty.confidence << " % interval " << uncertainty.lower[i] << ".."
         << uncertainty.upper[i];
      if (i < uncertainty.bound_notes.size() && !uncertainty.bound_notes[i].empty()) {
        os << ", " << uncertainty.bound_notes[i];
      }
      os << ")";
    }
    os << ", ";
  }
  os << "F = " << final_objective << " (start " << initial_objective << "), " << evaluations
     << " evaluations";
  if (failed_evaluations) os << " (" << failed_evaluations << " failed)";
  os.precision(3);
  os << ", " << wall_time_s << " s";
  return os.str();
}

std::string IdentifySummary::FullReport() const {
  std::ostringstream os;
  os.precision(8);
  os << "Identification summary\n"
     << "  algorithm:            " << algorithm << "\n"
     << "  objective:            " << objective << "\n"
     << "  starts:               " << starts << " (best: start " << best_start + 1 << ")\n";
  for (std::size_t i = 0; i < parameter_names.size(); ++i) {
    os << "  " << parameter_names[i] << ":";
    for (std::size_t pad = parameter_names[i].size(); pad < 20; ++pad) os << ' ';
    os << (i < static_cast<std::size_t>(initial_parameters.size()) ? initial_parameters[i] : NAN)
       << " -> " << (i < static_cast<std::size_t>(parameters.size()) ? parameters[i] : NAN) << "\n";
  }
  os << "  initial objective:    " << initial_objective << "\n"
     << "  final objective:      " << final_objective << "\n"
     << "  initial terms:        dU = " << initial_terms.u << ", dS = " << initial_terms.s
     << ", dV = " << initial_terms.v << ", dIF = " << initial_terms.f << "\n"
     << "    share of F:         " << TermContributions(initial_terms, weights) << "\n"
     << "  final terms:          dU = " << final_terms.u << ", dS = " << final_terms.s
     << ", dV = " << final_terms.v << ", dIF = " << final_terms.f << "\n"
     << "    share of F:         " << TermContributions(final_terms, weights) << "\n"
     << "  evaluations:          " << evaluations << " (" << failed_evaluations << " failed)\n"
     << "  wall time:            " << wall_time_s << " s\n"
     << "  termination:          " << ToString(termination) << "\n"
     << "  message:              " << message << "\n";
  if (uncertainty.usable) {
    os << "  uncertainty:          " << uncertainty.message << "\n";
    for (std::size_t i = 0; i < parameter_names.size(); ++i) {
      os << "    " << parameter_names[i] << ": standard error " << uncertainty.standard_error[i]
         << ", " << 100 * uncertainty.confidence << " % interval [" << uncertainty.lower[i] << ", "
         << uncertainty.upper[i] << "]";
      if (i < uncertainty.bound_notes.size() && !uncertainty.bound_notes[i].empty()) {
        os << ", " << uncertainty.bound_notes[i];
      }
      os << "\n";
    }
    if (parameter_names.size() > 1) {
      os << "    correlation:\n";
      for (Eigen::Index i = 0; i < uncertainty.correlation.rows(); ++i) {
        os << "     ";
        for (Eigen::Index j = 0; j < uncertainty.correlation.cols(); ++j) os << " " << uncertainty.correlation(i, j);
        os << "\n";
      }
    }
  } else if (uncertainty.message != "not computed") {
    os << "  uncertainty:          not available: " << uncertainty.message << "\n";
  }
  return os.str();
}

IdentifySummary Identify(const ObjectiveFunction& objective, const IdentifyOptions& options) {
  const int n = objective.parameter_count();
  std::string why;
  if (!options.IsValid(n, &why)) throw std::invalid_argument("identify options: " + why);
  if (options.weighting < 0 || options.weighting >= objective.weighting_count()) {
    ThrowInvalid("identify options: weighting",
                 "an index of the objective's weightings in 0.." + ToText(objective.weighting_count() - 1),
                 ToText(options.weighting));
  }
  const auto start_time = std::chrono::steady_clock::now();
  Eigen::VectorXd lower(n), upper(n);
  for (int i = 0; i < n; ++i) {
    lower[i] = objective.parameters()[i].lower;
    upper[i] = objective.parameters()[i].upper;
  }
  const Eigen::VectorXd first = options.start.size() ? options.start : objective.StartValues();
  for (int i = 0; i < n; ++i) {
    if (!(first[i] >= lower[i] && first[i] <= upper[i])) {
      ThrowInvalid("start of " + objective.parameters()[i].name,
                   "a value in its bounds [" + ToText(lower[i]) + ", " + ToText(upper[i]) + "]",
                   ToText(first[i]));
    }
  }
  std::vector<Eigen::VectorXd> starts = {first};
  const bool local = IsLocal(options.algorithm);
  if (local && options.multistart > 1) {
    for (const Eigen::VectorXd& p : LatinHypercube(options.multistart - 1, lower, upper, options.seed))
      starts.push_back(p);
  }
  nlopt_srand(options.seed);  // GN_CRS2_LM, GN_ISRES and MLSL draw from NLopt's generator

  std::vector<RunState> runs(starts.size());
  std::atomic<long long> progress_done{0}, progress_failed{0};
  std::atomic<bool> stopped{false};
  // This process's share of the starts.
  std::vector<std::size_t> mine;
  for (std::size_t s = options.share_index; s < starts.size(); s += options.share_count) mine.push_back(s);
  const int threads = internal::WorkerThreads(options.threads, mine.size());
  // Starts run in parallel, each with its own workspace and NLopt object.
#pragma omp parallel for schedule(dynamic) num_threads(threads) if (local && mine.size() > 1)
  for (std::size_t q = 0; q < mine.size(); ++q) {
    const std::size_t s = mine[q];
    RunState& run = runs[s];
    run.stopped = &stopped;
    if (stopped.load()) continue;  // another start failed: its error is rethrown below
    run.progress = &options.progress;
    run.progress_done = &progress_done;
    run.progress_failed = &progress_failed;
    run.progress_total = static_cast<long long>(starts.size()) * options.max_evaluations;
    run.start_time = start_time;
    // No exception may leave the parallel region: keep it for after.
    try {
      run.objective = &objective;
      run.weighting = options.weighting;
      run.cancel = options.cancel;
      run.start = static_cast<int>(s);
      // A first trust region / simplex of a tenth of the box. Allocate before
      // the NLopt objects, which nothing below may leak: after nlopt_create
      // only NLopt's C calls run, and its callback does not throw.
      Eigen::VectorXd x = starts[s];
      // A first step of a tenth of the box, but not beyond the nearest bound:
      // BOBYQA moves a start lying within its first step of a bound. (At a
      // bound, or within 1e-4 of the range of it, the tenth is kept.)
      Eigen::VectorXd step = 0.1 * (upper - lower);
      for (Eigen::Index i = 0; i < step.size(); ++i) {
        const double room = std::min(x[i] - lower[i], upper[i] - x[i]);
        if (room > 1e-4 * (upper[i] - lower[i])) step[i] = std::min(step[i], room);
      }
      // The start as given, first (see RunState::first_x).
      run.first_x = x;
      run.first_value = EvaluateOrThrow(static_cast<unsigned>(n), x.data(), run);
      run.first_pending = true;
      run.opt = nlopt_create(ToNlopt(options.algorithm), static_cast<unsigned>(n));
      nlopt_opt local_opt = nullptr;
      if (options.algorithm == Algorithm::kGnMlslLds) {
        local_opt = nlopt_create(ToNlopt(options.local_algorithm), static_cast<unsigned>(n));
        nlopt_set_xtol_rel(local_opt, options.xtol_rel);
        nlopt_set_ftol_rel(local_opt, options.ftol_rel);
        nlopt_set_local_optimizer(run.opt, local_opt);
      }
      nlopt_set_lower_bounds(run.opt, lower.data());
      nlopt_set_upper_bounds(run.opt, upper.data());
      nlopt_set_min_objective(run.opt, Evaluate, &run);
      nlopt_set_xtol_rel(run.opt, options.xtol_rel);
      nlopt_set_ftol_rel(run.opt, options.ftol_rel);
      nlopt_set_maxeval(run.opt, options.max_evaluations);
      if (options.max_time_s > 0) nlopt_set_maxtime(run.opt, options.max_time_s);
      nlopt_set_initial_step(run.opt, step.data());
      double f = 0.0;
      run.result = nlopt_optimize(run.opt, x.data(), &f);
      if (local_opt) nlopt_destroy(local_opt);
      nlopt_destroy(run.opt);
      run.opt = nullptr;
    } catch (...) {
      Fail(run, std::current_exception());
    }
  }

  for (const RunState& run : runs) {
    if (run.error) std::rethrow_exception(run.error);
  }

  IdentifySummary summary;
  summary.algorithm = ToString(options.algorithm);
  if (options.algorithm == Algorithm::kGnMlslLds)
    summary.algorithm += std::string(" + ") + ToString(options.local_algorithm);
  summary.objective = objective.options().weightings[options.weighting].weights.ToString();
  summary.weights = objective.options().weightings[options.weighting].weights;
  for (const ParameterSpec& p : objective.parameters()) summary.parameter_names.push_back(p.name);
  summary.initial_parameters = first;
  summary.starts = static_cast<int>(starts.size());
  summary.start_results.resize(runs.size());
  for (std::size_t q = 0; q < mine.size(); ++q) {
    RunState& run = runs[mine[q]];
    StartResult& r = summary.start_results[mine[q]];
    r.computed = true;
    r.evaluations = run.evaluations;
    r.failed_evaluations = run.failed;
    r.best_objective = run.best;
    r.best_parameters = run.best_x;
    r.best_terms = run.best_terms;
    r.nlopt_result = static_cast<int>(run.result);
    r.first_failure = run.first_failure;
    summary.history.insert(summary.history.end(), run.history.begin(), run.history.end());
  }
  if (!mine.empty() && mine.front() == 0) summary.initial_terms = runs[0].first_terms;
  SummariseStarts(&summary);
  if (options.uncertainty && options.share_count == 1 && summary.IsSolutionUsable()) {
    summary.uncertainty = ObjectiveUncertainty(objective, summary.parameters, options.weighting,
                                               options.uncertainty_options, options.seed);
  }
  summary.wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return summary;
}

void SummariseStarts(IdentifySummary* out) {
  IdentifySummary& summary = *out;
  summary.evaluations = summary.failed_evaluations = 0;
  int best = -1;
  bool all_computed = true;
  for (std::size_t s = 0; s < summary.start_results.size(); ++s) {
    const StartResult& r = summary.start_results[s];
    all_computed = all_computed && r.computed;
    summary.evaluations += r.evaluations;
    summary.failed_evaluations += r.failed_evaluations;
    if (r.best_parameters.size() &&
        (best < 0 || r.best_objective < summary.start_results[best].best_objective)) {
      best = static_cast<int>(s);
    }
  }
  // A failed start has no objective value (the failure value is a penalty).
  summary.initial_objective = std::numeric_limits<double>::quiet_NaN();
  for (const IterationRecord& record : summary.history) {
    if (record.start == 0 && record.evaluation == 1 && !record.failed) {
      summary.initial_objective = record.objective;
    }
  }
  if (best < 0) {
    summary.termination = all_computed ? Termination::kAllEvaluationsFailed : Termination::kInterrupted;
    summary.parameters = summary.initial_parameters;
    summary.message = "every evaluation failed";
    if (!summary.start_results.empty() && !summary.start_results.front().first_failure.empty()) {
      summary.message += "; e.g. at the start: " + summary.start_results.front().first_failure;
    }
    return;
  }
  const StartResult& b = summary.start_results[best];
  summary.best_start = best;
  summary.parameters = b.best_parameters;
  summary.final_objective = b.best_objective;
  summary.final_terms = b.best_terms;
  const nlopt_result code = static_cast<nlopt_result>(b.nlopt_result);
  summary.termination = FromNlopt(code);
  summary.message = std::string("NLopt returned ") + NloptResultText(code) + " after " +
                    ToText(b.evaluations) + " evaluations; best point seen kept";
}

}  // namespace podid::ident
