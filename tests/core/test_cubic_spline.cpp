// Tests of the C2 cubic spline behind the tabulated drive: exactness, end conditions, order.
// Checked on its own so a Table drive failure can be told apart from a spline failure.
#include "core/cubic_spline.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace latticedyn {
namespace {

TEST(CubicSpline, NaturalReproducesStraightLine) {
  const std::vector<double> x{-1.0, 0.2, 0.5, 2.0, 2.1};
  std::vector<double> y;
  for (double xi : x) y.push_back(3.0 - 2.0 * xi);
  const CubicSpline s(x, y, CubicSpline::EndCondition::natural);
  for (double t = -1.0; t <= 2.1; t += 0.05) {
    const CubicSpline::Sample v = s.evaluate(t);
    EXPECT_NEAR(v.value, 3.0 - 2.0 * t, 1e-13) << t;
    EXPECT_NEAR(v.d1, -2.0, 1e-13) << t;
    EXPECT_NEAR(v.d2, 0.0, 1e-12) << t;
  }
}

TEST(CubicSpline, TwoPointClampedIsTheSmoothstep) {
  const CubicSpline s({1.0, 3.0}, {2.0, 6.0}, CubicSpline::EndCondition::zero_slope);
  for (double t = 1.0; t <= 3.0; t += 0.1) {
    const double u = (t - 1.0) / 2.0;
    EXPECT_NEAR(s.evaluate(t).value, 2.0 + 4.0 * u * u * (3.0 - 2.0 * u), 1e-13) << t;
  }
}

TEST(CubicSpline, ClampedConvergesAtFourthOrder) {
  // cos has zero slope at 0 and pi, so the zero-slope clamped spline is the complete spline.
  auto max_error = [](int intervals) {
    std::vector<double> x, y;
    for (int i = 0; i <= intervals; ++i) {
      x.push_back(std::numbers::pi * i / intervals);
      y.push_back(std::cos(x.back()));
    }
    const CubicSpline s(x, y, CubicSpline::EndCondition::zero_slope);
    double err = 0.0;
    for (double t = 0.0; t <= std::numbers::pi; t += 1e-3) {
      err = std::max(err, std::abs(s.evaluate(t).value - std::cos(t)));
    }
    return err;
  };
  const double order = std::log2(max_error(10) / max_error(20));
  EXPECT_GT(order, 3.8);
  EXPECT_LT(order, 4.3);
}

TEST(CubicSpline, ValueAtKnotIsExact) {
  const std::vector<double> x{0.0, 0.1, 0.7, 1.3};
  const std::vector<double> y{0.3, -0.1, 0.25, 1.0 / 3.0};
  const CubicSpline s(x, y, CubicSpline::EndCondition::zero_slope);
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_EQ(s.evaluate(x[i]).value, y[i]);
}

TEST(CubicSpline, RejectsBadKnots) {
  using E = CubicSpline::EndCondition;
  EXPECT_THROW(CubicSpline({0.0}, {1.0}, E::natural), std::invalid_argument);
  EXPECT_THROW(CubicSpline({0.0, 1.0}, {1.0, 2.0, 3.0}, E::natural), std::invalid_argument);
  EXPECT_THROW(CubicSpline({0.0, -1.0}, {1.0, 2.0}, E::natural), std::invalid_argument);
  EXPECT_THROW(CubicSpline({0.0, INFINITY}, {1.0, 2.0}, E::natural), std::invalid_argument);
}

}  // namespace
}  // namespace latticedyn
