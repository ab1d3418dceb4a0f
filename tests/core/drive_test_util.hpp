// Shared checks for the drive tests: derivatives against central differences, continuity.
// Header-only helpers used by several test files of the test_core_drive executable.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "core/drive_params.hpp"

namespace latticedyn::test {

using DriveFn = std::function<DriveValue(double)>;

/// rate and accel against central differences of value and rate at each time, with step h.
/// Relative tolerance tol, scaled by the size of the quantity (plus one, for zero crossings).
inline void expect_derivatives_match_fd(const DriveFn& f, const std::vector<double>& times,
                                        double h, double tol) {
  for (double t : times) {
    const DriveValue v = f(t);
    const DriveValue vp = f(t + h);
    const DriveValue vm = f(t - h);
    const double fd_rate = (vp.value - vm.value) / (2.0 * h);
    const double fd_accel = (vp.rate - vm.rate) / (2.0 * h);
    EXPECT_NEAR(v.rate, fd_rate, tol * (1.0 + std::abs(v.rate))) << "t = " << t;
    EXPECT_NEAR(v.accel, fd_accel, tol * (1.0 + std::abs(v.accel))) << "t = " << t;
  }
}

/// Evenly spaced sample times in (a, b), skipping anything within `gap` of a listed boundary.
inline std::vector<double> sample_times(double a, double b, int count,
                                        const std::vector<double>& boundaries, double gap) {
  std::vector<double> out;
  for (int i = 1; i < count; ++i) {
    const double t = a + (b - a) * i / count;
    bool near = false;
    for (double s : boundaries) near = near || std::abs(t - s) < gap;
    if (!near) out.push_back(t);
  }
  return out;
}

/// Value (and, if requested, rate) agree on both sides of t to within slope * eps-size steps.
inline void expect_continuous_at(const DriveFn& f, double t, bool rate_too) {
  const double eps = 1e-9;
  const DriveValue left = f(t - eps);
  const DriveValue right = f(t + eps);
  EXPECT_NEAR(left.value, right.value, 1e-7) << "value jumps at t = " << t;
  if (rate_too) {
    EXPECT_NEAR(left.rate, right.rate, 1e-7) << "rate jumps at t = " << t;
  }
}

}  // namespace latticedyn::test
