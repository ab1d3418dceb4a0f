// The control trajectory as a drive table (thesis 6.4, Figure 6-4): a discrete trajectory
// resampled at equal times with steady points added at both ends, ready for a spline drive.
#pragma once

#include <span>
#include <vector>

namespace latticedyn {

struct ControlTable {
  std::vector<double> times;                 ///< from 0, equally spaced
  std::vector<std::vector<double>> values;   ///< one list per channel, one value per time
  double lead_time = 0.0;  ///< table time at which the trajectory's first instant falls
  double spacing = 0.0;    ///< time between table points
};

/// v at `at` by linear interpolation between the samples (t increasing), constant beyond the ends.
double interpolate_linear(std::span<const double> t, std::span<const double> v, double at);

/// The channels (each sampled at `times`, increasing) resampled by linear interpolation at
/// `samples` >= 2 equal steps over [times.front(), times.back()], then `steady` copies of the
/// first value before and of the last value after, at the same spacing: a spline through the
/// table starts and ends at rest (the rope lengths are controls that must not jump in rate).
/// Throws std::invalid_argument for unusable input.
ControlTable make_control_table(std::span<const double> times, const std::vector<std::vector<double>>& channels,
                                int samples, int steady);

}  // namespace latticedyn
