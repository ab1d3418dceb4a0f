// Polynomial surfaces of two variables: a known polynomial is reproduced exactly on data in the
// ranges of the crane's map (rope lengths near 50 m, boom angles in degrees), noise shows in the
// residuals, the gradient matches finite differences, bad input is refused.
#include "control/polynomial_surface.hpp"

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

// A grid over x in [45, 85] (a boom angle) and y in [34, 55] (a rope length), z from f.
template <class F>
Samples grid(int nx, int ny, F f) {
  Samples s;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      const double x = 45.0 + 40.0 * i / (nx - 1), y = 34.0 + 21.0 * j / (ny - 1);
      s.x.push_back(x);
      s.y.push_back(y);
      s.z.push_back(f(x, y));
    }
  return s;
}

// A known polynomial of degree 2 in x and 3 in y, in raw (unscaled) powers.
double known(double x, double y) { return 3.0 - 0.2 * x + 0.01 * x * x + 0.5 * y - 0.003 * x * y * y + 1e-4 * y * y * y; }

TEST(PolynomialSurface, ReproducesAKnownPolynomial) {
  const Samples s = grid(9, 8, known);
  const PolynomialSurface p = PolynomialSurface::fit(s.x, s.y, s.z, 2, 3);
  EXPECT_LT(p.max_residual(), 1e-9);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ux(45, 85), uy(34, 55);
  for (int k = 0; k < 50; ++k) {
    const double x = ux(rng), y = uy(rng);
    EXPECT_NEAR(p(x, y), known(x, y), 1e-9 * std::max(1.0, std::abs(known(x, y))));
  }
  // Higher orders than needed fit the same function (orders up to 5, thesis 6.2).
  const PolynomialSurface p55 = PolynomialSurface::fit(s.x, s.y, s.z, 5, 5);
  EXPECT_LT(p55.max_residual(), 1e-8);
  EXPECT_NEAR(p55(60.0, 40.0), known(60.0, 40.0), 1e-8);
}

TEST(PolynomialSurface, TooLowAnOrderLeavesAResidual) {
  const Samples s = grid(9, 8, known);
  const PolynomialSurface p = PolynomialSurface::fit(s.x, s.y, s.z, 1, 1);
  EXPECT_GT(p.max_residual(), 1e-2);  // the x^2 and y^3 terms cannot be carried
  EXPECT_GE(p.max_residual(), p.rms_residual());
}

TEST(PolynomialSurface, NoiseShowsInTheResidual) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1e-3);
  Samples s = grid(21, 21, known);
  for (double& z : s.z) z += noise(rng);
  const PolynomialSurface p = PolynomialSurface::fit(s.x, s.y, s.z, 2, 3);
  EXPECT_NEAR(p.rms_residual(), 1e-3, 2e-4);  // 441 samples, 12 coefficients
  EXPECT_NEAR(p(65.0, 44.5), known(65.0, 44.5), 1e-3);
}

TEST(PolynomialSurface, GradientMatchesFiniteDifferences) {
  const Samples s = grid(9, 8, known);
  const PolynomialSurface p = PolynomialSurface::fit(s.x, s.y, s.z, 2, 3);
  for (const auto& [x, y] : {std::pair{50.0, 40.0}, std::pair{80.0, 54.0}, std::pair{63.3, 35.1}}) {
    const double h = 1e-5;
    const auto [gx, gy] = p.gradient(x, y);
    EXPECT_NEAR(gx, (p(x + h, y) - p(x - h, y)) / (2 * h), 1e-6);
    EXPECT_NEAR(gy, (p(x, y + h) - p(x, y - h)) / (2 * h), 1e-6);
  }
}

TEST(PolynomialSurface, RefusesBadInput) {
  const Samples s = grid(3, 3, known);
  EXPECT_THROW(PolynomialSurface::fit(s.x, s.y, s.z, 6, 1), std::invalid_argument);   // order too high
  EXPECT_THROW(PolynomialSurface::fit(s.x, s.y, s.z, -1, 1), std::invalid_argument);
  EXPECT_THROW(PolynomialSurface::fit(s.x, s.y, s.z, 3, 3), std::invalid_argument);   // 9 samples, 16 terms
  std::vector<double> shorter(s.z.begin(), s.z.end() - 1);
  EXPECT_THROW(PolynomialSurface::fit(s.x, s.y, shorter, 1, 1), std::invalid_argument);
  Samples nan = s;
  nan.z[4] = NAN;
  EXPECT_THROW(PolynomialSurface::fit(nan.x, nan.y, nan.z, 1, 1), std::invalid_argument);
  // 16 samples but only 2 distinct x values cannot carry x^2.
  Samples two;
  for (int i = 0; i < 16; ++i) {
    two.x.push_back(i % 2 ? 50.0 : 60.0);
    two.y.push_back(34.0 + i);
    two.z.push_back(known(two.x.back(), two.y.back()));
  }
  EXPECT_THROW(PolynomialSurface::fit(two.x, two.y, two.z, 2, 1), std::invalid_argument);
  // A constant x with order 0 in it is a curve in y (known is cubic in y: order 3 carries it).
  std::vector<double> x0(two.y.size(), 50.0), z0;
  for (double y : two.y) z0.push_back(known(50.0, y));
  const PolynomialSurface line = PolynomialSurface::fit(x0, two.y, z0, 0, 3);
  EXPECT_LT(line.max_residual(), 1e-9);
  EXPECT_NEAR(line(50.0, 40.5), known(50.0, 40.5), 1e-9 * std::abs(known(50.0, 40.5)));
  EXPECT_THROW(PolynomialSurface::fit(x0, two.y, z0, 1, 3), std::invalid_argument);  // x is constant
}

}  // namespace
}  // namespace latticedyn
