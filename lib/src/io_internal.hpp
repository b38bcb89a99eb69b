#pragma once
// Helpers shared by the time-series readers (not installed).

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>

#include "podid/core/io.hpp"

namespace podid::internal {

/// A uniform time grid t0 + i * step_s fitted to stamps.
struct UniformGrid {
  double start_s = 0.0;
  double step_s = 0.0;
};

/// Throws std::invalid_argument "<path>: expected <expected>, got a FIFO
/// (named pipe)" (or a directory, a device, a socket) unless `path` is a
/// regular file; nothing when it does not exist (the open says so). Opening a
/// FIFO without a writer blocked podid for ever.
void RequireRegularFile(const std::string& path, const std::string& expected);

/// Fits t_i = t0 + i h by least squares to n >= 2 increasing stamps and checks
/// them (io.hpp, kTimeStepRelativeTolerance): each step against the median step
/// and the fitted step, within the rounding of its two stamps plus 1e-6 of a
/// step (within 1e-6 of the median step alone when the stamps are rounded to
/// half a step or more), and each stamp within its rounding plus 1e-6 h of
/// the fitted grid. `rounding(i)`
/// is the half-unit rounding bound of stamp i (s); `where(i)` names it in
/// messages. Throws std::invalid_argument: "<where(i)>: expected an increasing
/// time ...", "... a uniform time step <h> s ..., got a step of <d> s", or
/// "... a time on the uniform grid ...".
UniformGrid FitUniformGrid(const double* t,
                           std::size_t n,
                           const std::function<double(std::size_t)>& rounding,
                           const std::function<std::string(std::size_t)>& where);

/// The stamps as given when each is within 1e-9 of a step of `grid`, else
/// (rounded stamps) the grid itself.
Eigen::VectorXd GridOrStamps(const double* t, std::size_t n, const UniformGrid& grid);

/// The uniform times start_s + i step_s, i < n, for a reader whose
/// file gives a start and a step. Throws std::invalid_argument naming `where`
/// unless they are finite, step_s > 0, and the step is resolved at the
/// record's largest time: a time's rounding in double (half an ulp) at most
/// 1e-3 of a step, so that the grid is increasing and uniform to 1e-3
/// (a start of 1e300 s every 1e-300 s gave equal times, found by podid_fuzz_uff).
Eigen::VectorXd UniformTimes(double start_s,
                             double step_s,
                             std::size_t n,
                             const std::string& where);

/// How precisely a number is printed: half a unit of its last digit, its
/// significant digits, and its decimals (-1 in exponent notation).
/// "0.0009766" -> 5e-8, 4, 7; "1.953e-3" -> 5e-7, 4, -1; "12" -> 0.5, 2, 0.
struct PrintedNumber {
  double half_unit = 0.0;
  int significant = 0;
  int decimals = -1;
};
PrintedNumber Printed(std::string_view number);

/// Text from a file made safe to print and to put in JSON: valid UTF-8 is
/// kept, other bytes are read as Latin-1 (as Windows writers store "m/s²"),
/// control characters become '?', and spaces at both ends are trimmed.
std::string CleanText(std::string_view bytes);

}  // namespace podid::internal
