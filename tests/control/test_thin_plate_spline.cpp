// Thin plate spline surfaces: exact through the samples, exact for affine data everywhere (the
// spline's polynomial part), close to a smooth function between grid samples, gradients against
// finite differences, smoothing that filters noise, and clear errors for unusable samples.
#include "control/thin_plate_spline.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace latticedyn {
namespace {

struct Samples {
  std::vector<double> x, y, z;
};

// A grid like the quasi-static map's: 11 x 9 points over metres of rope and degrees.
template <class F>
Samples grid(F f) {
  Samples s;
  for (int i = 0; i <= 10; ++i)
    for (int j = 0; j <= 8; ++j) {
      const double x = 6.0 + 1.6 * i, y = 45.0 + 5.0 * j;
      s.x.push_back(x);
      s.y.push_back(y);
      s.z.push_back(f(x, y));
    }
  return s;
}

double smooth(double x, double y) { return std::sin(0.2 * x) * std::cos(0.03 * y) + 0.01 * x * y; }

TEST(ThinPlateSpline, InterpolatesTheSamplesExactly) {
  const Samples s = grid(smooth);
  const auto tps = ThinPlateSpline::fit(s.x, s.y, s.z);
  EXPECT_LT(tps.max_residual(), 1e-9);
  for (std::size_t k = 0; k < s.x.size(); k += 7) EXPECT_NEAR(tps(s.x[k], s.y[k]), s.z[k], 1e-9);
}

TEST(ThinPlateSpline, ReproducesAffineDataEverywhere) {
  auto affine = [](double x, double y) { return 3.0 - 0.5 * x + 0.25 * y; };
  const Samples s = grid(affine);
  const auto tps = ThinPlateSpline::fit(s.x, s.y, s.z);
  for (double x : {6.5, 11.1, 21.9})
    for (double y : {46.0, 63.3, 84.0}) EXPECT_NEAR(tps(x, y), affine(x, y), 1e-9);
}

TEST(ThinPlateSpline, FollowsASmoothFunctionBetweenTheSamples) {
  const Samples s = grid(smooth);
  const auto tps = ThinPlateSpline::fit(s.x, s.y, s.z);
  double worst = 0;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 8; ++j) {
      const double x = 6.8 + 1.6 * i, y = 47.5 + 5.0 * j;  // cell centres, farthest from samples
      worst = std::max(worst, std::abs(tps(x, y) - smooth(x, y)));
    }
  // The function varies by about 4 over the grid; the worst cell centre (0.028 measured, at the
  // border where the spline flattens out) stays within 1 % of that.
  EXPECT_LT(worst, 0.04);
}

TEST(ThinPlateSpline, GradientMatchesFiniteDifferences) {
  const Samples s = grid(smooth);
  const auto tps = ThinPlateSpline::fit(s.x, s.y, s.z, 1e-3);
  for (auto [x, y] : {std::pair{7.3, 50.2}, std::pair{14.0, 66.6}, std::pair{20.9, 83.1}}) {
    const auto [gx, gy] = tps.gradient(x, y);
    const double h = 1e-5;
    EXPECT_NEAR(gx, (tps(x + h, y) - tps(x - h, y)) / (2 * h), 1e-6);
    EXPECT_NEAR(gy, (tps(x, y + h) - tps(x, y - h)) / (2 * h), 1e-6);
  }
}

TEST(ThinPlateSpline, SmoothingFiltersNoise) {
  Samples s = grid(smooth);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.02);
  for (double& z : s.z) z += noise(rng);
  const auto exact = ThinPlateSpline::fit(s.x, s.y, s.z, 0.0);
  const auto smoothed = ThinPlateSpline::fit(s.x, s.y, s.z, 1e-2);
  EXPECT_LT(exact.max_residual(), 1e-9);
  EXPECT_GT(smoothed.rms_residual(), 1e-3);  // it no longer passes through the noisy samples
  double err_exact = 0, err_smooth = 0;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 8; ++j) {
      const double x = 6.8 + 1.6 * i, y = 47.5 + 5.0 * j;
      err_exact += std::pow(exact(x, y) - smooth(x, y), 2);
      err_smooth += std::pow(smoothed(x, y) - smooth(x, y), 2);
    }
  EXPECT_LT(err_smooth, err_exact);  // closer to the truth between the samples
}

TEST(ThinPlateSpline, RejectsUnusableSamples) {
  const std::vector<double> x{0, 1, 1}, y{0, 0, 0}, z{1, 2, 3};
  EXPECT_THROW(ThinPlateSpline::fit(x, y, z), std::invalid_argument);  // one line
  const std::vector<double> x2{0, 1, 0, 0}, y2{0, 0, 1, 0}, z2{1, 2, 3, 4};
  EXPECT_THROW(ThinPlateSpline::fit(x2, y2, z2), std::invalid_argument);  // coincident
  const std::vector<double> x3{0, 1, 0}, y3{0, 0, 1}, z3{1, 2, 3};
  EXPECT_THROW(ThinPlateSpline::fit(x3, y3, z3, -1.0), std::invalid_argument);
  EXPECT_NO_THROW(ThinPlateSpline::fit(x3, y3, z3));
}

}  // namespace
}  // namespace latticedyn
