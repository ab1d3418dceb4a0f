// Tests of the cubic Hermite and linear shape functions: interpolation, derivatives, exactness.
// Also instantiates them with Eigen::AutoDiffScalar, as element kernels will.
#include "core/hermite.hpp"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <unsupported/Eigen/AutoDiff>

#include <array>

namespace latticedyn {
namespace {

constexpr double kL = 2.7;  // a non-unit length, so a missing 1/L factor shows up

TEST(HermiteCubic, InterpolationConditionsAtBothEnds) {
  const HermiteCubic<double> h0 = hermite_cubic(0.0, kL);
  const HermiteCubic<double> h1 = hermite_cubic(1.0, kL);
  const std::array<double, 4> value_at_0{1, 0, 0, 0}, slope_at_0{0, 1, 0, 0};
  const std::array<double, 4> value_at_1{0, 0, 1, 0}, slope_at_1{0, 0, 0, 1};
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(h0.N[k], value_at_0[k], 1e-15) << k;
    EXPECT_NEAR(h0.dN[k], slope_at_0[k], 1e-15) << k;
    EXPECT_NEAR(h1.N[k], value_at_1[k], 1e-15) << k;
    EXPECT_NEAR(h1.dN[k], slope_at_1[k], 1e-15) << k;
  }
}

TEST(HermiteCubic, PartitionOfUnity) {
  for (double xi = 0.0; xi <= 1.0; xi += 0.05) {
    const HermiteCubic<double> h = hermite_cubic(xi, kL);
    EXPECT_NEAR(h.N[0] + h.N[2], 1.0, 1e-15) << xi;
    EXPECT_NEAR(h.dN[0] + h.dN[2], 0.0, 1e-14) << xi;
    EXPECT_NEAR(h.ddN[0] + h.ddN[2], 0.0, 1e-14) << xi;
  }
}

TEST(HermiteCubic, DerivativesMatchCentralDifferences) {
  const double d = 1e-5;  // step in xi; the step in x is d * L
  for (double xi = 0.05; xi < 1.0; xi += 0.1) {
    const HermiteCubic<double> h = hermite_cubic(xi, kL);
    const HermiteCubic<double> hp = hermite_cubic(xi + d, kL);
    const HermiteCubic<double> hm = hermite_cubic(xi - d, kL);
    for (std::size_t k = 0; k < 4; ++k) {
      EXPECT_NEAR(h.dN[k], (hp.N[k] - hm.N[k]) / (2.0 * d * kL), 1e-8) << "k " << k;
      EXPECT_NEAR(h.ddN[k], (hp.dN[k] - hm.dN[k]) / (2.0 * d * kL), 1e-8) << "k " << k;
    }
  }
}

TEST(HermiteCubic, ReproducesAnyCubicAndItsDerivatives) {
  // p(x) = c0 + c1 x + c2 x^2 + c3 x^3 on the element [0, L].
  const double c0 = 0.4, c1 = -1.3, c2 = 2.2, c3 = -0.75;
  auto p = [&](double x) { return c0 + x * (c1 + x * (c2 + x * c3)); };
  auto dp = [&](double x) { return c1 + x * (2.0 * c2 + 3.0 * c3 * x); };
  auto ddp = [&](double x) { return 2.0 * c2 + 6.0 * c3 * x; };
  const std::array<double, 4> dofs{p(0.0), dp(0.0), p(kL), dp(kL)};
  for (double xi = 0.0; xi <= 1.0; xi += 0.125) {
    const HermiteCubic<double> h = hermite_cubic(xi, kL);
    double y = 0, dy = 0, ddy = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      y += h.N[k] * dofs[k];
      dy += h.dN[k] * dofs[k];
      ddy += h.ddN[k] * dofs[k];
    }
    const double x = xi * kL;
    EXPECT_NEAR(y, p(x), 1e-12) << xi;
    EXPECT_NEAR(dy, dp(x), 1e-12) << xi;
    EXPECT_NEAR(ddy, ddp(x), 1e-12) << xi;
  }
}

TEST(LinearShape, ValuesDerivativesAndExactness) {
  const double ya = 1.5, yb = -0.5;
  for (double xi = 0.0; xi <= 1.0; xi += 0.25) {
    const LinearShape<double> s = linear_shape(xi, kL);
    EXPECT_DOUBLE_EQ(s.N[0] + s.N[1], 1.0);
    EXPECT_DOUBLE_EQ(s.dN[0], -1.0 / kL);
    EXPECT_DOUBLE_EQ(s.dN[1], 1.0 / kL);
    EXPECT_NEAR(s.N[0] * ya + s.N[1] * yb, ya + xi * (yb - ya), 1e-15);
  }
  const LinearShape<double> s0 = linear_shape(0.0, kL);
  EXPECT_EQ(s0.N[0], 1.0);
  EXPECT_EQ(s0.N[1], 0.0);
}

using AD = Eigen::AutoDiffScalar<Eigen::Vector2d>;

TEST(HermiteCubic, WorksWithAutoDiffScalar) {
  for (double xi0 : {0.0, 0.3, 0.85, 1.0}) {
    const AD xi(xi0, 2, 0);  // d/dxi in slot 0, slot 1 must stay zero
    const HermiteCubic<AD> h = hermite_cubic(xi, kL);
    const HermiteCubic<double> ref = hermite_cubic(xi0, kL);
    for (std::size_t k = 0; k < 4; ++k) {
      EXPECT_NEAR(h.N[k].value(), ref.N[k], 1e-15);
      EXPECT_NEAR(h.N[k].derivatives()(0), ref.dN[k] * kL, 1e-13) << k;
      EXPECT_NEAR(h.dN[k].derivatives()(0), ref.ddN[k] * kL, 1e-13) << k;
      EXPECT_EQ(h.N[k].derivatives()(1), 0.0);
    }
  }
}

TEST(LinearShape, WorksWithAutoDiffScalar) {
  const AD xi(0.4, 2, 0);
  const LinearShape<AD> s = linear_shape(xi, kL);
  const LinearShape<double> ref = linear_shape(0.4, kL);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_NEAR(s.N[k].value(), ref.N[k], 1e-15);
    EXPECT_NEAR(s.N[k].derivatives()(0), ref.dN[k] * kL, 1e-15);
    EXPECT_NEAR(s.dN[k].value(), ref.dN[k], 1e-15);
    EXPECT_EQ(s.dN[k].derivatives()(0), 0.0);
  }
}

}  // namespace
}  // namespace latticedyn
