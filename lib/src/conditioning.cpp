#include "podid/core/conditioning.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include "podid/core/error.hpp"

namespace podid {
namespace {

using Complex = std::complex<double>;
using Section = std::array<double, 6>;

/// Analog zeros, poles and gain (scipy's zpk), then digital after Bilinear().
struct Zpk {
  std::vector<Complex> zeros, poles;
  double gain = 1.0;
};

// The analog Butterworth prototype (scipy buttap): |H(j w)|^2 = 1 / (1 + w^2N).
Zpk Prototype(int order) {
  Zpk zpk;
  for (int m = -order + 1; m < order; m += 2) {
    zpk.poles.push_back(-std::exp(Complex(0.0, std::numbers::pi * m / (2.0 * order))));
  }
  return zpk;
}

Complex Product(const std::vector<Complex>& v, Complex shift, double sign) {
  Complex p = 1.0;
  for (const Complex& x : v) p *= shift + sign * x;
  return p;
}

// Bilinear transform with fs = 2 (cutoffs normalised to Nyquist, pre-warped).
Zpk Bilinear(const Zpk& analog) {
  constexpr double kFs2 = 4.0;
  Zpk out;
  for (const Complex& z : analog.zeros) out.zeros.push_back((kFs2 + z) / (kFs2 - z));
  for (const Complex& p : analog.poles) out.poles.push_back((kFs2 + p) / (kFs2 - p));
  const std::size_t degree = analog.poles.size() - analog.zeros.size();
  for (std::size_t i = 0; i < degree; ++i) out.zeros.push_back(-1.0);
  out.gain =
      analog.gain * (Product(analog.zeros, kFs2, -1.0) / Product(analog.poles, kFs2, -1.0)).real();
  return out;
}

bool IsReal(const Complex& z) { return std::abs(z.imag()) <= 1e-12 * std::max(1.0, std::abs(z)); }

// Pairs conjugate poles (and real poles two by two, a lone real pole last as
// a first-order section); zeros are paired the same way, as they come.
std::vector<Section> ToSections(const Zpk& zpk) {
  auto pairs = [](const std::vector<Complex>& roots) {
    std::vector<std::array<double, 3>> out;  // [1, c1, c2]: z^2 + c1 z + c2 (or z + c1)
    std::vector<double> reals;
    for (const Complex& r : roots) {
      if (IsReal(r)) {
        reals.push_back(r.real());
      } else if (r.imag() > 0) {
        out.push_back({1.0, -2.0 * r.real(), std::norm(r)});
      }
    }
    std::sort(reals.begin(), reals.end());
    for (std::size_t i = 0; i + 1 < reals.size(); i += 2) {
      out.push_back({1.0, -(reals[i] + reals[i + 1]), reals[i] * reals[i + 1]});
    }
    if (reals.size() % 2 == 1) out.push_back({1.0, -reals.back(), 0.0});  // first order
    return out;
  };
  const auto p = pairs(zpk.poles);
  auto z = pairs(zpk.zeros);
  PODID_CHECK(z.size() == p.size());
  // A first-order pole section takes the first-order zero section.
  std::vector<Section> sections;
  for (std::size_t i = 0; i < p.size(); ++i) {
    sections.push_back({z[i][0], z[i][1], z[i][2], 1.0, p[i][1], p[i][2]});
  }
  for (int k = 0; k < 3; ++k) sections.front()[k] *= zpk.gain;
  return sections;
}

// Steady state of one transposed direct-form II section for a unit input
// (scipy lfilter_zi): y = sum(b) / sum(a).
std::array<double, 2> SteadyState(const Section& s) {
  const double y = (s[0] + s[1] + s[2]) / (s[3] + s[4] + s[5]);
  const double z1 = s[2] - s[5] * y;
  return {s[1] - s[4] * y + z1, z1};
}

// In place: every section over x (the sosfilt recursion), starting from the
// steady state for a constant input x0.
void FilterForward(const std::vector<Section>& sections, double x0, std::vector<double>& x) {
  double scale = x0;
  for (const Section& s : sections) {
    const auto zi = SteadyState(s);
    double z0 = zi[0] * scale, z1 = zi[1] * scale;
    for (double& v : x) {
      const double in = v;
      const double y = s[0] * in + z0;
      z0 = s[1] * in - s[4] * y + z1;
      z1 = s[2] * in - s[5] * y;
      v = y;
    }
    scale *= (s[0] + s[1] + s[2]) / (s[3] + s[4] + s[5]);
  }
}

int PadLength(const std::vector<Section>& sections) {
  int first_order = 0;
  for (const Section& s : sections) first_order += (s[2] == 0.0 && s[5] == 0.0) ? 1 : 0;
  return 3 * (2 * static_cast<int>(sections.size()) + 1 - first_order);
}

void CheckCutoff(double f_Hz, double nyquist_Hz, const char* name) {
  if (!(f_Hz > 0.0 && f_Hz < nyquist_Hz)) {
    ThrowInvalid(std::string("filter ") + name,
                 "a cutoff in (0, " + ToText(nyquist_Hz) + ") Hz (the Nyquist frequency)",
                 ToText(f_Hz) + " Hz");
  }
  const double lowest = kMinFilterCutoffFraction * nyquist_Hz;
  const double highest = (1.0 - kMinFilterCutoffFraction) * nyquist_Hz;
  if (!(f_Hz >= lowest && f_Hz <= highest)) {
    ThrowInvalid(std::string("filter ") + name,
                 "a cutoff in [" + ToText(lowest) + ", " + ToText(highest) + "] Hz (" +
                     ToText(kMinFilterCutoffFraction) +
                     " of the Nyquist frequency from 0 and from it: closer, the filter loses "
                     "its accuracy in double precision)",
                 ToText(f_Hz) + " Hz");
  }
}

}  // namespace

const char* ToString(Detrend detrend) {
  switch (detrend) {
    case Detrend::kNone:
      return "none";
    case Detrend::kConstant:
      return "constant";
    case Detrend::kLinear:
      return "linear";
  }
  return "?";
}

const char* ToString(FilterType type) {
  switch (type) {
    case FilterType::kNone:
      return "none";
    case FilterType::kLowpass:
      return "lowpass";
    case FilterType::kHighpass:
      return "highpass";
    case FilterType::kBandpass:
      return "bandpass";
  }
  return "?";
}

bool ConditioningOptions::KeepsTimeGrid() const {
  return decimate == 1 && window_start_s == -std::numeric_limits<double>::infinity() &&
         window_end_s == std::numeric_limits<double>::infinity();
}

bool ConditioningOptions::IsIdentity() const {
  return channels.empty() && KeepsTimeGrid() && detrend == Detrend::kNone &&
         filter.type == FilterType::kNone;
}

bool ConditioningOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!(window_start_s < window_end_s) || std::isnan(window_start_s) || std::isnan(window_end_s)) {
    return fail("window: expected start < end, got " + ToText(window_start_s) + " .. " +
                ToText(window_end_s) + " s");
  }
  if (decimate < 1 || decimate > kMaxDecimation) {
    return fail("decimate: expected an integer in [1, " + ToText(kMaxDecimation) + "], got " +
                ToText(decimate));
  }
  if (channels.size() > 65536) {
    return fail("channels: expected at most 65536 names, got " + ToText(channels.size()));
  }
  if (filter.type == FilterType::kNone) return true;
  if (filter.order < 1 || filter.order > kMaxFilterOrder) {
    return fail("filter order: expected an integer in [1, " + ToText(kMaxFilterOrder) + "], got " +
                ToText(filter.order));
  }
  const bool low = filter.type != FilterType::kLowpass;
  const bool high = filter.type != FilterType::kHighpass;
  if (low && !(filter.low_Hz > 0.0 && std::isfinite(filter.low_Hz))) {
    return fail("filter low cutoff: expected a frequency > 0 Hz, got " + ToText(filter.low_Hz));
  }
  if (high && !(filter.high_Hz > 0.0 && std::isfinite(filter.high_Hz))) {
    return fail("filter high cutoff: expected a frequency > 0 Hz, got " + ToText(filter.high_Hz));
  }
  if (low && high && !(filter.low_Hz < filter.high_Hz)) {
    return fail("filter cutoffs: expected low < high, got " + ToText(filter.low_Hz) + " and " +
                ToText(filter.high_Hz) + " Hz");
  }
  return true;
}

double FilterOptions::PassbandLow_Hz() const {
  return type == FilterType::kHighpass || type == FilterType::kBandpass ? low_Hz : 0.0;
}

double FilterOptions::PassbandHigh_Hz() const {
  return type == FilterType::kLowpass || type == FilterType::kBandpass
             ? high_Hz
             : std::numeric_limits<double>::infinity();
}

std::string FilterOptions::DescribePassband() const {
  switch (type) {
    case FilterType::kNone:
      return "all frequencies";
    case FilterType::kLowpass:
      return "below " + ToText(high_Hz) + " Hz";
    case FilterType::kHighpass:
      return "above " + ToText(low_Hz) + " Hz";
    case FilterType::kBandpass:
      break;
  }
  return ToText(low_Hz) + ".." + ToText(high_Hz) + " Hz";
}

std::string ConditioningOptions::Describe() const {
  std::string out;
  auto add = [&out](const std::string& s) { out += (out.empty() ? "" : ", ") + s; };
  if (!channels.empty()) add("channels " + ToText(channels.size()));
  if (std::isfinite(window_start_s) || std::isfinite(window_end_s)) {
    add("window " + ToText(window_start_s) + ".." + ToText(window_end_s) + " s");
  }
  if (detrend != Detrend::kNone) add(std::string("detrend ") + ToString(detrend));
  switch (filter.type) {
    case FilterType::kNone:
      break;
    case FilterType::kLowpass:
      add("lowpass " + ToText(filter.high_Hz) + " Hz order " + ToText(filter.order));
      break;
    case FilterType::kHighpass:
      add("highpass " + ToText(filter.low_Hz) + " Hz order " + ToText(filter.order));
      break;
    case FilterType::kBandpass:
      add("bandpass " + ToText(filter.low_Hz) + ".." + ToText(filter.high_Hz) + " Hz order " +
          ToText(filter.order));
      break;
  }
  if (decimate > 1) add("decimate " + ToText(decimate));
  return out.empty() ? "none" : out;
}

std::vector<Section> ButterworthSections(const FilterOptions& filter, double sample_rate_Hz) {
  PODID_CHECK(sample_rate_Hz > 0.0);
  if (filter.order < 1 || filter.order > kMaxFilterOrder) {
    ThrowInvalid("filter order", "an integer in [1, " + ToText(kMaxFilterOrder) + "]",
                 ToText(filter.order));
  }
  const double nyquist = 0.5 * sample_rate_Hz;
  // Pre-warped analog cutoffs for fs = 2: 4 tan(pi Wn / 2), Wn = f / Nyquist.
  auto warp = [&](double f_Hz) {
    return 4.0 * std::tan(std::numbers::pi * (f_Hz / nyquist) / 2.0);
  };
  Zpk a = Prototype(filter.order);
  const std::size_t degree = a.poles.size();
  switch (filter.type) {
    case FilterType::kLowpass: {
      CheckCutoff(filter.high_Hz, nyquist, "cutoff");
      const double w = warp(filter.high_Hz);
      for (Complex& p : a.poles) p *= w;
      a.gain *= std::pow(w, static_cast<double>(degree));
      break;
    }
    case FilterType::kHighpass: {
      CheckCutoff(filter.low_Hz, nyquist, "cutoff");
      const double w = warp(filter.low_Hz);
      a.gain *= (1.0 / Product(a.poles, 0.0, -1.0)).real();
      for (Complex& p : a.poles) p = w / p;
      a.zeros.assign(degree, 0.0);
      break;
    }
    case FilterType::kBandpass: {
      CheckCutoff(filter.low_Hz, nyquist, "low cutoff");
      CheckCutoff(filter.high_Hz, nyquist, "high cutoff");
      if (!(filter.low_Hz < filter.high_Hz)) {
        ThrowInvalid("filter cutoffs", "low < high",
                     ToText(filter.low_Hz) + " and " + ToText(filter.high_Hz) + " Hz");
      }
      const double w1 = warp(filter.low_Hz), w2 = warp(filter.high_Hz);
      const double bw = w2 - w1, w0 = std::sqrt(w1 * w2);
      std::vector<Complex> poles;
      for (const Complex& p : a.poles) {
        const Complex lp = p * bw / 2.0;
        const Complex root = std::sqrt(lp * lp - w0 * w0);
        poles.push_back(lp + root);
        poles.push_back(lp - root);
      }
      a.poles = poles;
      a.zeros.assign(degree, 0.0);
      a.gain *= std::pow(bw, static_cast<double>(degree));
      break;
    }
    case FilterType::kNone:
      PODID_CHECK(false);
  }
  return ToSections(Bilinear(a));
}

Eigen::MatrixXd FiltFilt(const std::vector<Section>& sections, const Eigen::MatrixXd& values) {
  const int pad = PadLength(sections);
  const Eigen::Index n = values.rows();
  if (n <= pad) {
    ThrowInvalid("filter",
                 "a record of more than " + ToText(pad) + " samples (the filter's padding)",
                 ToText(n) + " samples");
  }
  Eigen::MatrixXd out(n, values.cols());
  std::vector<double> x(static_cast<std::size_t>(n + 2 * pad));
  for (Eigen::Index c = 0; c < values.cols(); ++c) {
    const auto v = values.col(c);
    // Odd extension: 2 x[0] - x[pad..1], x, 2 x[n-1] - x[n-2..n-1-pad].
    for (int i = 0; i < pad; ++i) {
      x[static_cast<std::size_t>(i)] = 2.0 * v[0] - v[pad - i];
      x[static_cast<std::size_t>(n + pad + i)] = 2.0 * v[n - 1] - v[n - 2 - i];
    }
    for (Eigen::Index i = 0; i < n; ++i) x[static_cast<std::size_t>(pad + i)] = v[i];
    FilterForward(sections, x.front(), x);
    std::reverse(x.begin(), x.end());
    FilterForward(sections, x.front(), x);
    std::reverse(x.begin(), x.end());
    for (Eigen::Index i = 0; i < n; ++i) out(i, c) = x[static_cast<std::size_t>(pad + i)];
  }
  return out;
}

TimeSeries ConditionRecord(const TimeSeries& series,
                           const ConditioningOptions& options,
                           const std::string& where) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument(where + ": conditioning: " + why);
  PODID_CHECK(series.time_s.size() == series.values.rows());
  if (options.IsIdentity()) return series;
  TimeSeries out;
  // 1. Channels.
  std::vector<Eigen::Index> columns;
  if (options.channels.empty()) {
    for (Eigen::Index c = 0; c < series.channels(); ++c) columns.push_back(c);
  } else {
    for (const std::string& name : options.channels) {
      const int c = series.ChannelIndex(name);
      if (c < 0) {
        std::string names;
        for (const auto& n : series.channel_names) names += (names.empty() ? "" : ", ") + n;
        ThrowInvalid(where + ": channel", "one of " + names, Excerpt(name));
      }
      columns.push_back(c);
    }
  }
  // 2. Window (with half a step of tolerance for printed stamps).
  const double h = series.samples() >= 2 ? series.step_s() : 0.0;
  Eigen::Index first = 0, last = series.samples() - 1;
  while (first <= last && series.time_s[first] < options.window_start_s - 0.5 * h) ++first;
  while (last >= first && series.time_s[last] > options.window_end_s + 0.5 * h) --last;
  const Eigen::Index n = last - first + 1;
  if (n < 4) {
    ThrowInvalid(where + ": window",
                 "at least 4 samples of the record (" + ToText(series.time_s[0]) + " .. " +
                     ToText(series.time_s[series.samples() - 1]) + " s)",
                 ToText(std::max<Eigen::Index>(n, 0)) + " samples in " +
                     ToText(options.window_start_s) + " .. " + ToText(options.window_end_s) + " s");
  }
  Eigen::MatrixXd values(n, static_cast<Eigen::Index>(columns.size()));
  for (std::size_t k = 0; k < columns.size(); ++k) {
    values.col(static_cast<Eigen::Index>(k)) = series.values.col(columns[k]).segment(first, n);
    out.channel_names.push_back(series.channel_names[static_cast<std::size_t>(columns[k])]);
    if (!series.units.empty())
      out.units.push_back(series.units[static_cast<std::size_t>(columns[k])]);
  }
  Eigen::VectorXd time = series.time_s.segment(first, n);
  // 3. Detrend.
  if (options.detrend == Detrend::kConstant) {
    values.rowwise() -= values.colwise().mean();
  } else if (options.detrend == Detrend::kLinear) {
    // Least-squares line in the sample index (centred: the normal equations decouple).
    const Eigen::ArrayXd i = Eigen::ArrayXd::LinSpaced(n, 0.0, static_cast<double>(n - 1)) -
                             0.5 * static_cast<double>(n - 1);
    const double ii = (i * i).sum();
    for (Eigen::Index c = 0; c < values.cols(); ++c) {
      const double mean = values.col(c).mean();
      const double slope = (i * values.col(c).array()).sum() / ii;
      values.col(c).array() -= mean + slope * i;
    }
  }
  // 4. Filter.
  const double rate = 1.0 / h;
  if (options.filter.type != FilterType::kNone) {
    try {
      const std::vector<Section> sections = ButterworthSections(options.filter, rate);
      // Below 1 / duration the filter's response outlasts the record and its
      // output is the edges' padding: a low-pass at 0.005 Hz on a 2 s record
      // gave a constant outside the data's range. Checked after the design,
      // whose own errors (a cutoff out of range) come first.
      const bool lowpass = options.filter.type == FilterType::kLowpass;
      const double lowest_Hz = lowpass ? options.filter.high_Hz : options.filter.low_Hz;
      const double shortest_Hz = 1.0 / (static_cast<double>(n - 1) * h);
      if (!(lowest_Hz >= shortest_Hz)) {
        ThrowInvalid(
            options.filter.type == FilterType::kBandpass ? "filter low cutoff" : "filter cutoff",
            "a cutoff >= 1 / duration = " + ToText(shortest_Hz) +
                " Hz (below, the filter's response outlasts the record and its output "
                "is set by the padding at the edges)",
            ToText(lowest_Hz) + " Hz");
      }
      values = FiltFilt(sections, values);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(where + ": " + e.what());
    }
    // Finite values through a stable filter overflow only near the largest
    // double: say so here rather than let a later stage find NaN.
    if (!values.allFinite()) {
      ThrowInvalid(where + ": filter", "finite filtered values",
                   "an overflow (input values of up to " +
                       ToText(series.values.cwiseAbs().maxCoeff()) + ")");
    }
  }
  // 5. Decimate.
  if (options.decimate > 1) {
    const int q = options.decimate;
    FilterOptions anti_alias;
    anti_alias.type = FilterType::kLowpass;
    anti_alias.order = kDecimationFilterOrder;
    anti_alias.high_Hz = kDecimationCutoffFraction * 0.5 * rate / q;
    const Eigen::Index kept = (n + q - 1) / q;
    if (kept < 4) {
      ThrowInvalid(where + ": decimate", "at least 4 samples after decimation",
                   ToText(kept) + " (" + ToText(n) + " samples / " + ToText(q) + ")");
    }
    try {
      values = FiltFilt(ButterworthSections(anti_alias, rate), values);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(where + ": decimate: " + e.what());
    }
    if (!values.allFinite()) {
      ThrowInvalid(where + ": decimate", "finite filtered values",
                   "an overflow in the anti-alias filter (input values of up to " +
                       ToText(series.values.cwiseAbs().maxCoeff()) + ")");
    }
    Eigen::MatrixXd decimated(kept, values.cols());
    Eigen::VectorXd decimated_time(kept);
    for (Eigen::Index k = 0; k < kept; ++k) {
      decimated.row(k) = values.row(k * q);
      decimated_time[k] = time[k * q];
    }
    values = std::move(decimated);
    time = std::move(decimated_time);
  }
  out.values = std::move(values);
  out.time_s = std::move(time);
  return out;
}

}  // namespace podid
