// Forward AD numbers: the gradient and Hessian of a composite function of every operation and
// elementary function against central finite differences, and Eigen matrices of them.
#include "core/dual.hpp"

#include "core/types.hpp"

#include <gtest/gtest.h>

#include <array>

namespace latticedyn {
namespace {

// Uses +, -, *, / with numbers and doubles, sqrt, sin, cos, exp, log, asin, acos, atan2, abs.
template <class S>
S composite(const S& x, const S& y, const S& z) {
  using std::acos;
  using std::asin;
  using std::atan2;
  using std::cos;
  using std::exp;
  using std::log;
  using std::sin;
  using std::sqrt;
  using std::abs;
  const S a = sqrt(x * x + 2.0 * y * y + 1.0) / (3.0 - z);
  const S b = atan2(sin(x) * y, cos(z) + 2.0) - 0.5 * exp(-z * x);
  const S c = asin(0.3 * y) * acos(0.2 * x) + log(2.0 + x * z) - abs(-y) / x;
  return a * b + c - 1.0 / (x + 4.0);
}

TEST(Dual, GradientAndHessianMatchFiniteDifferences) {
  const std::array<double, 3> p = {0.7, -0.4, 0.3};
  using H = HyperDual<3>;
  using D = Dual<3>;
  const H f = composite(H::variable(p[0], 0), H::variable(p[1], 1), H::variable(p[2], 2));
  const D f1 = composite(D::variable(p[0], 0), D::variable(p[1], 1), D::variable(p[2], 2));
  const double h = 1e-5;
  auto at = [&](int i, double di, int j, double dj) {
    std::array<double, 3> q = p;
    q[i] += di;
    q[j] += dj;
    return composite(q[0], q[1], q[2]);
  };
  EXPECT_NEAR(f.value(), composite(p[0], p[1], p[2]), 1e-15);
  EXPECT_NEAR(f1.value(), f.value(), 1e-15);
  for (int i = 0; i < 3; ++i) {
    const double gi = (at(i, h, i, 0) - at(i, -h, i, 0)) / (2 * h);
    EXPECT_NEAR(f.g[i], gi, 1e-8);
    EXPECT_NEAR(f1.g[i], f.g[i], 1e-14);
    for (int j = 0; j < 3; ++j) {
      const double hij = (at(i, h, j, h) - at(i, h, j, -h) - at(i, -h, j, h) + at(i, -h, j, -h)) / (4 * h * h);
      EXPECT_NEAR(f.hessian(i, j), hij, 2e-5) << i << "," << j;
    }
  }
}

TEST(Dual, WorksInEigenExpressions) {
  using H = HyperDual<2>;
  Vec3T<H> v(H::variable(1.0, 0), H::variable(2.0, 1), H(3.0));
  const Mat3 R = Mat3::Identity() * 2.0;
  const H n2 = (R * v).squaredNorm();  // 4 (x^2 + y^2 + 9)
  EXPECT_DOUBLE_EQ(n2.value(), 56.0);
  EXPECT_DOUBLE_EQ(n2.g[0], 8.0);
  EXPECT_DOUBLE_EQ(n2.g[1], 16.0);
  EXPECT_DOUBLE_EQ(n2.hessian(0, 0), 8.0);
  EXPECT_DOUBLE_EQ(n2.hessian(0, 1), 0.0);
  EXPECT_DOUBLE_EQ(scalar_value(v.normalized()(2)), 3.0 / std::sqrt(14.0));
}

}  // namespace
}  // namespace latticedyn
