// What the time-series readers share: the uniform-grid fit of time stamps,
// clean text from files, and the dispatch on the file's extension with the
// channel selection and sampling options of DataReadOptions.
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "io_internal.hpp"
#include "io_mat_internal.hpp"
#include "podid/core/error.hpp"
#include "podid/core/io.hpp"

namespace podid {
namespace internal {

UniformGrid FitUniformGrid(const double* t,
                           std::size_t n,
                           const std::function<double(std::size_t)>& rounding,
                           const std::function<std::string(std::size_t)>& where) {
  PODID_CHECK(n >= 2);
  for (std::size_t i = 1; i < n; ++i) {
    if (!(t[i] > t[i - 1])) {
      ThrowInvalid(where(i), "an increasing time (after t = " + ToText(t[i - 1]) + ")",
                   ToText(t[i]));
    }
  }
  constexpr double kArithmetic = 8.0 * std::numeric_limits<double>::epsilon();
  auto tolerance = [&](std::size_t i, double h) {
    return rounding(i) + kTimeStepRelativeTolerance * h + kArithmetic * std::abs(t[i]);
  };
  double rounding_max = 0.0;
  for (std::size_t i = 0; i < n; ++i) rounding_max = std::max(rounding_max, rounding(i));
  std::vector<double> steps(n - 1);
  for (std::size_t i = 1; i < n; ++i) steps[i - 1] = t[i] - t[i - 1];
  const std::size_t middle = (steps.size() - 1) / 2;  // the lower median
  std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(middle), steps.end());
  const double median = steps[middle];
  std::vector<double>().swap(steps);
  // Stamps printed to a unit (2 rounding_max) of half a step or more: the
  // rounding of a uniform grid then moves a step by as much as a missing
  // sample does (0.1, 0.2, 0.4 at 10 Hz), so such stamps must be exact
  // multiples of one step, as 0.1, 0.2, 0.3 are. (The chord's step: the
  // median of steps printed to half a step is off by up to a half.)
  const double chord = (t[n - 1] - t[0]) / static_cast<double>(n - 1);
  const bool coarse = 4.0 * rounding_max >= chord;
  const auto exact = [&](std::size_t i, double h) {
    return kTimeStepRelativeTolerance * h + kArithmetic * std::abs(t[i]);
  };
  // Steps against the median step, which rounded stamps move by at most
  // 2 rounding_max: a gap or a jump is named where it is.
  for (std::size_t i = 1; i < n; ++i) {
    const double d = t[i] - t[i - 1];
    if (coarse) {
      const double allowed = exact(i, median) + exact(i - 1, median);
      if (std::abs(d - median) > allowed) {
        ThrowInvalid(where(i),
                     "a uniform time step " + ToText(median) +
                         " s exactly (the stamps' resolution, " + ToShortText(2.0 * rounding_max) +
                         " s, is half a step or more: rounding would hide a missing sample)",
                     "a step of " + ToText(d) + " s");
      }
      continue;
    }
    const double allowed = tolerance(i, median) + tolerance(i - 1, median) + 2.0 * rounding_max;
    if (std::abs(d - median) > allowed) {
      ThrowInvalid(where(i),
                   "a uniform time step " + ToText(median) + " s (within " + ToShortText(allowed) +
                       " s: the stamps' rounding and " + ToText(kTimeStepRelativeTolerance) +
                       " of a step)",
                   "a step of " + ToText(d) + " s");
    }
  }
  // Least squares on the small deviations u_i from the chord, so that sums of
  // large times lose no digits.
  const double h0 = chord;
  const double mean_i = 0.5 * static_cast<double>(n - 1);
  double mean_u = 0.0;
  for (std::size_t i = 0; i < n; ++i) mean_u += t[i] - (t[0] + static_cast<double>(i) * h0);
  mean_u /= static_cast<double>(n);
  double sxy = 0.0, sxx = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = static_cast<double>(i) - mean_i;
    const double u = t[i] - (t[0] + static_cast<double>(i) * h0);
    sxy += x * (u - mean_u);
    sxx += x * x;
  }
  const double b = sxy / sxx;
  const double a = mean_u - b * mean_i;
  UniformGrid grid{t[0] + a, h0 + b};
  if (!IsSamplingStep(grid.step_s)) {  // increasing stamps 1e-320 s apart, say
    ThrowInvalid(where(1), "a time step whose rate 1 / step is finite",
                 "a step of " + ToText(grid.step_s) + " s");
  }
  // Steps against the fitted step, whose error from the stamps' bounds is at
  // most max_i tolerance(i) sum |x_i| / sxx: a step may differ from it by the
  // rounding of its two stamps only. The median test above allows twice that,
  // so a missing sample could pass it with stamps printed to a quarter step.
  double bound_max = 0.0, sum_abs_x = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    bound_max = std::max(bound_max, tolerance(i, grid.step_s));
    sum_abs_x += std::abs(static_cast<double>(i) - mean_i);
  }
  const double slope_error = bound_max * sum_abs_x / sxx;
  for (std::size_t i = 1; i < n; ++i) {
    const double d = t[i] - t[i - 1];
    const double allowed = tolerance(i, grid.step_s) + tolerance(i - 1, grid.step_s) + slope_error;
    if (std::abs(d - grid.step_s) > allowed) {
      ThrowInvalid(where(i),
                   "a uniform time step " + ToText(grid.step_s) + " s (least squares; within " +
                       ToShortText(allowed) + " s: the two stamps' rounding and the fit's error)",
                   "a step of " + ToText(d) + " s");
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double on_grid = grid.start_s + static_cast<double>(i) * grid.step_s;
    const double off = t[i] - on_grid;
    // The fitted line errs at i by at most rounding_max sqrt(n leverage_i)
    // (Cauchy-Schwarz on the hat matrix row; 2 rounding_max at the ends).
    const double x = static_cast<double>(i) - mean_i;
    const double leverage = 1.0 / static_cast<double>(n) + x * x / sxx;
    const double fit = rounding_max * std::sqrt(static_cast<double>(n) * leverage);
    const double allowed = tolerance(i, grid.step_s) + fit + kArithmetic * std::abs(on_grid);
    if (std::abs(off) > allowed) {
      ThrowInvalid(where(i),
                   "a time on the uniform grid " + ToText(grid.start_s) + " + i * " +
                       ToText(grid.step_s) + " s (least squares) within " + ToShortText(allowed) +
                       " s",
                   ToText(t[i]) + " s (" + ToText(off) + " s off the grid)");
    }
  }
  return grid;
}

Eigen::VectorXd UniformTimes(double start_s,
                             double step_s,
                             std::size_t n,
                             const std::string& where) {
  // Half an ulp of |t| is at most eps / 2 |t|; at most 1e-3 of a step when
  // step >= 500 eps |t|.
  constexpr double kResolved = 500.0 * std::numeric_limits<double>::epsilon();
  const double end_s = start_s + static_cast<double>(n > 0 ? n - 1 : 0) * step_s;
  const double largest = std::max(std::abs(start_s), std::abs(end_s));
  if (step_s > 0.0 && !IsSamplingStep(step_s)) {  // 1e-320 s: an infinite rate
    ThrowInvalid(where, "a time step whose rate 1 / step is finite",
                 "a step of " + ToText(step_s) + " s");
  }
  if (!std::isfinite(start_s) || !(step_s > 0.0) || !std::isfinite(end_s) ||
      !(step_s >= kResolved * largest)) {
    ThrowInvalid(where,
                 "a finite time grid whose step > 0 s is at least " + ToShortText(kResolved) +
                     " of its largest time (double precision resolves it)",
                 "a start of " + ToText(start_s) + " s, a step of " + ToText(step_s) + " s and " +
                     std::to_string(n) + " samples (up to " + ToText(end_s) + " s)");
  }
  Eigen::VectorXd t(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i)
    t(static_cast<Eigen::Index>(i)) = start_s + static_cast<double>(i) * step_s;
  return t;
}

PrintedNumber Printed(std::string_view number) {
  PrintedNumber out;
  const std::size_t e = number.find_first_of("eE");
  const std::string_view mantissa = number.substr(0, e);
  int exponent = 0;
  if (e != std::string_view::npos) {
    std::string_view text = number.substr(e + 1);
    if (!text.empty() && text.front() == '+') text.remove_prefix(1);
    std::from_chars(text.data(), text.data() + text.size(), exponent);
  }
  const std::size_t point = mantissa.find('.');
  int after_point = 0;
  bool leading = true;
  for (std::size_t i = 0; i < mantissa.size(); ++i) {
    const char c = mantissa[i];
    if (c < '0' || c > '9') continue;
    if (point != std::string_view::npos && i > point) ++after_point;
    if (c != '0') leading = false;
    if (!leading) ++out.significant;
  }
  out.half_unit = 0.5 * std::pow(10.0, exponent - after_point);
  out.decimals = e == std::string_view::npos ? after_point : -1;
  return out;
}

Eigen::VectorXd GridOrStamps(const double* t, std::size_t n, const UniformGrid& grid) {
  constexpr double kKeep = 1e-9;  // of a step: stamps printed or stored at full precision
  Eigen::VectorXd out(static_cast<Eigen::Index>(n));
  bool rounded = false;
  for (std::size_t i = 0; i < n; ++i) {
    const double on_grid = grid.start_s + static_cast<double>(i) * grid.step_s;
    out(static_cast<Eigen::Index>(i)) = on_grid;
    rounded = rounded || std::abs(t[i] - on_grid) > kKeep * grid.step_s;
  }
  if (!rounded) std::copy(t, t + n, out.data());
  return out;
}

std::string CleanText(std::string_view bytes) {
  std::string out;
  out.reserve(bytes.size());
  std::size_t i = 0;
  while (i < bytes.size()) {
    const auto c = static_cast<unsigned char>(bytes[i]);
    const std::size_t length = Utf8SequenceLength(bytes, i);  // 0: not valid UTF-8 here
    if (c < 0x20 || c == 0x7F) {
      out += '?';
      ++i;
    } else if (c < 0x80) {
      out += static_cast<char>(c);
      ++i;
    } else if (length > 0) {
      out.append(bytes.substr(i, length));
      i += length;
    } else if (c < 0xA0) {  // C1 controls of Latin-1
      out += '?';
      ++i;
    } else {  // Latin-1 -> UTF-8
      out += static_cast<char>(0xC0 | (c >> 6));
      out += static_cast<char>(0x80 | (c & 0x3F));
      ++i;
    }
  }
  const auto first = out.find_first_not_of(' ');
  if (first == std::string::npos) return "";
  return out.substr(first, out.find_last_not_of(' ') - first + 1);
}

}  // namespace internal

namespace {

constexpr std::size_t kMaxSelectedChannels = 65536;

bool EndsWith(const std::string& path, std::string_view suffix) {
  if (path.size() < suffix.size()) return false;
  return std::equal(suffix.rbegin(), suffix.rend(), path.rbegin(), [](char a, char b) {
    return a == static_cast<char>(std::tolower(static_cast<unsigned char>(b)));
  });
}

std::string Names(const std::vector<std::string>& names) {
  std::string out;
  constexpr std::size_t kShown = 20;
  for (std::size_t i = 0; i < names.size() && i < kShown; ++i) out += (i ? ", " : "") + names[i];
  if (names.size() > kShown) out += ", ... (" + std::to_string(names.size()) + " channels)";
  return out;
}

}  // namespace

void DataReadOptions::Check() const {
  if (rate_Hz != 0.0 && step_s != 0.0) {
    ThrowInvalid("data options", "a sampling rate or a step", "both");
  }
  if (rate_Hz != 0.0 && !IsSamplingRate(rate_Hz)) {
    ThrowInvalid("sampling rate", "a finite rate > 0 Hz", ToText(rate_Hz));
  }
  if (step_s != 0.0 && !IsSamplingStep(step_s)) {
    ThrowInvalid("sampling step", "a finite step > 0 s whose rate 1 / step is finite",
                 ToText(step_s));
  }
  if (channels.size() > kMaxSelectedChannels) {
    ThrowInvalid("channels", "at most " + std::to_string(kMaxSelectedChannels) + " names",
                 std::to_string(channels.size()));
  }
  std::set<std::string> seen;
  for (const auto& name : channels) {
    if (name.empty()) ThrowInvalid("channels", "non-empty channel names", "an empty name");
    if (!seen.insert(name).second)
      ThrowInvalid("channels", "distinct channel names", "\"" + name + "\" twice");
  }
}

void internal::RequireRegularFile(const std::string& path, const std::string& expected) {
  struct stat status {};
  if (::stat(path.c_str(), &status) != 0 || S_ISREG(status.st_mode)) return;
  const char* kind = S_ISDIR(status.st_mode)                              ? "a directory"
                     : S_ISFIFO(status.st_mode)                           ? "a FIFO (named pipe)"
                     : S_ISSOCK(status.st_mode)                           ? "a socket"
                     : S_ISCHR(status.st_mode) || S_ISBLK(status.st_mode) ? "a device"
                                                                          : "not a regular file";
  ThrowInvalid(path, expected, kind);
}

namespace {

// The chosen channels, in the order asked.
TimeSeries SelectChannels(const std::string& path,
                          TimeSeries series,
                          const std::vector<std::string>& channels) {
  TimeSeries selected;
  selected.time_s = std::move(series.time_s);
  selected.values.resize(series.values.rows(), static_cast<Eigen::Index>(channels.size()));
  for (std::size_t k = 0; k < channels.size(); ++k) {
    const int index = series.ChannelIndex(channels[k]);
    if (index < 0) {
      ThrowInvalid(
          path, "a channel \"" + channels[k] + "\" (channels: " + Names(series.channel_names) + ")",
          "none");
    }
    selected.values.col(static_cast<Eigen::Index>(k)) = series.values.col(index);
    selected.channel_names.push_back(series.channel_names[index]);
    selected.units.push_back(series.units[index]);
  }
  return selected;
}

// A channel without a single change (all zero, or one value throughout) is
// usually a dead or unplugged sensor: it adds nothing to a POD but a zero
// entry in every POM, and its own wavelet transform is empty. Said, not
// refused: a clamped dof recorded on purpose is legitimate.
void NoteConstantChannels(const std::string& path,
                          const TimeSeries& series,
                          std::vector<std::string>* notes) {
  if (notes == nullptr || series.samples() < 2) return;
  for (Eigen::Index c = 0; c < series.values.cols(); ++c) {
    const auto column = series.values.col(c);
    const double first = column[0];
    if (!(column.array() == first).all()) continue;
    notes->push_back(
        path + ": channel " + series.channel_names[static_cast<std::size_t>(c)] + " is " +
        (first == 0 ? std::string("zero") : "constant (" + ToText(first) + ")") + " in all " +
        std::to_string(series.samples()) + " samples: a dead or disconnected sensor?");
  }
}

}  // namespace

TimeSeries ReadTimeSeries(const std::string& path,
                          const DataReadOptions& options,
                          std::vector<std::string>* notes) {
  options.Check();
  const double step = options.rate_Hz > 0.0 ? 1.0 / options.rate_Hz : options.step_s;
  const bool is_mat = EndsWith(path, ".mat");
  if (!options.variable.empty() && !is_mat) {
    ThrowInvalid(path, "a variable name only for a .mat file", "\"" + options.variable + "\"");
  }
  TimeSeries series;
  bool has_time = true;
  if (EndsWith(path, ".csv")) {
    series = ReadCsv(path);
  } else if (is_mat) {
    series = internal::ReadMatFile(path, options.variable, "", step, &has_time, notes);
  } else if (EndsWith(path, ".uff") || EndsWith(path, ".unv")) {
    series = ReadUff(path, notes);
  } else {
    ThrowInvalid(path, "a time-series file ending in .csv, .mat, .uff or .unv", "\"" + path + "\"");
  }
  if (step > 0.0 && has_time) {
    const double own = series.step_s();
    if (std::abs(own - step) > kTimeStepRelativeTolerance * own) {
      ThrowInvalid(
          path,
          "a sampling step (" + ToText(step) + " s given) that agrees with the file's own time",
          "a step of " + ToText(own) + " s in the file");
    }
  }
  if (series.units.size() != series.channel_names.size())
    series.units.assign(series.channel_names.size(), "");
  if (!options.channels.empty()) series = SelectChannels(path, std::move(series), options.channels);
  NoteConstantChannels(path, series, notes);
  return series;
}

TimeSeries ReadTimeSeries(const std::string& path) {
  return ReadTimeSeries(path, DataReadOptions{});
}

}  // namespace podid
