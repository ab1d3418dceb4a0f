// Tests of the Gauss–Legendre rules: thesis Table A-1, polynomial exactness, interval mapping.
// Table A-1's n = 11 row prints the positive points with minus signs; checked against the fix.
#include "core/quadrature.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace latticedyn {
namespace {

// Table A-1 gives 16 significant digits, so agreement is at the level of double rounding.
constexpr double kTableTol = 2e-15;

// Checks a rule against its non-negative half (ascending, starting with 0 for odd n) as printed
// in Table A-1; the negative half follows from the rule's symmetry.
void expect_matches_half(int n, const std::vector<double>& points_half,
                         const std::vector<double>& weights_half) {
  const GaussRule& r = gauss_legendre(n);
  ASSERT_EQ(r.points.size(), static_cast<std::size_t>(n));
  ASSERT_EQ(r.weights.size(), static_cast<std::size_t>(n));
  const auto offset = static_cast<std::size_t>(n / 2);  // index of the first point >= 0
  ASSERT_EQ(points_half.size(), static_cast<std::size_t>(n - n / 2));
  for (std::size_t k = 0; k < points_half.size(); ++k) {
    const std::size_t up = offset + k;
    const std::size_t down = static_cast<std::size_t>(n) - 1 - up;
    EXPECT_NEAR(r.points[up], points_half[k], kTableTol) << "n = " << n << ", k = " << k;
    EXPECT_NEAR(r.points[down], -points_half[k], kTableTol) << "n = " << n << ", k = " << k;
    EXPECT_NEAR(r.weights[up], weights_half[k], kTableTol) << "n = " << n << ", k = " << k;
    EXPECT_NEAR(r.weights[down], weights_half[k], kTableTol) << "n = " << n << ", k = " << k;
  }
}

TEST(GaussLegendre, MatchesTableA1ClosedForms) {
  expect_matches_half(1, {0.0}, {2.0});
  expect_matches_half(2, {1.0 / std::sqrt(3.0)}, {1.0});
  expect_matches_half(3, {0.0, std::sqrt(3.0 / 5.0)}, {8.0 / 9.0, 5.0 / 9.0});
  const double s30 = std::sqrt(30.0);
  expect_matches_half(4, {std::sqrt(525.0 - 70.0 * s30) / 35.0, std::sqrt(525.0 + 70.0 * s30) / 35.0},
                      {(18.0 + s30) / 36.0, (18.0 - s30) / 36.0});
  const double s70 = std::sqrt(70.0);
  expect_matches_half(5,
                      {0.0, std::sqrt(245.0 - 14.0 * s70) / 21.0,
                       std::sqrt(245.0 + 14.0 * s70) / 21.0},
                      {512.0 / 900.0, (322.0 + 13.0 * s70) / 900.0, (322.0 - 13.0 * s70) / 900.0});
}

TEST(GaussLegendre, MatchesTableA1Decimals) {
  expect_matches_half(6, {0.2386191860831968, 0.6612093864662646, 0.9324695142031521},
                      {0.4679139345726909, 0.3607615730481388, 0.1713244923791703});
  expect_matches_half(7, {0.0, 0.4058451513773977, 0.7415311855993945, 0.9491079123427586},
                      {0.4179591836734694, 0.3818300505051183, 0.2797053914892767,
                       0.1294849661688696});
  expect_matches_half(8,
                      {0.1834346424956495, 0.5255324099163293, 0.7966664774136270,
                       0.9602898564975363},
                      {0.3626837833783620, 0.3137066458778871, 0.2223810344533746,
                       0.1012285362903761});
  expect_matches_half(9,
                      {0.0, 0.3242534234038089, 0.6133714327005904, 0.8360311073266357,
                       0.9681602395076261},
                      {0.3302393550012598, 0.3123470770400029, 0.2606106964029354,
                       0.1806481606948574, 0.0812743883615745});
  expect_matches_half(10,
                      {0.1488743389816309, 0.4333953941292476, 0.6794095682990241,
                       0.8650633666889848, 0.9739065285171719},
                      {0.2955242247147528, 0.2692667193099963, 0.2190863625159821,
                       0.1494513491505809, 0.06667134430868785});
  // Table A-1 prints the last five n = 11 points as -0.2695..., ..., -0.9782...; the rule is
  // symmetric, so they are the positive mirror images of the first five.
  expect_matches_half(11,
                      {0.0, 0.2695431559523450, 0.5190961292068118, 0.7301520055740494,
                       0.8870625997680953, 0.9782286581460570},
                      {0.2729250867779006, 0.2628045445102470, 0.2331937645919904,
                       0.1862902109277342, 0.1255803694649046, 0.05566856711617369});
}

double integrate_monomial(const GaussRule& r, int k) {
  double sum = 0.0;
  for (std::size_t i = 0; i < r.points.size(); ++i) sum += r.weights[i] * std::pow(r.points[i], k);
  return sum;
}

void expect_exact_up_to_degree(int n) {
  const GaussRule& r = gauss_legendre(n);
  for (int k = 0; k <= 2 * n - 1; ++k) {
    const double exact = (k % 2 == 1) ? 0.0 : 2.0 / (k + 1);
    EXPECT_NEAR(integrate_monomial(r, k), exact, 1e-14 * (1.0 + exact))
        << "n = " << n << ", degree " << k;
  }
}

TEST(GaussLegendre, IntegratesMonomialsUpToDegree2nMinus1) {
  for (int n = 1; n <= 20; ++n) expect_exact_up_to_degree(n);
  expect_exact_up_to_degree(64);
}

TEST(GaussLegendre, IsNotExactAtDegree2n) {
  // Guards against a rule accidentally of higher order (e.g. wrong n returned).
  for (int n = 1; n <= 10; ++n) {
    const double exact = 2.0 / (2 * n + 1);
    EXPECT_GT(std::abs(integrate_monomial(gauss_legendre(n), 2 * n) - exact), 1e-6) << n;
  }
}

TEST(GaussLegendre, StructureForAllOrders) {
  for (int n = kMinGaussPoints; n <= kMaxGaussPoints; ++n) {
    const GaussRule& r = gauss_legendre(n);
    ASSERT_EQ(r.points.size(), static_cast<std::size_t>(n));
    double sum = 0.0;
    for (std::size_t i = 0; i < r.points.size(); ++i) {
      sum += r.weights[i];
      EXPECT_GT(r.weights[i], 0.0);
      EXPECT_GT(r.points[i], -1.0);
      EXPECT_LT(r.points[i], 1.0);
      if (i > 0) {
        EXPECT_LT(r.points[i - 1], r.points[i]) << "n = " << n;
      }
      EXPECT_EQ(r.points[i], -r.points[r.points.size() - 1 - i]);
    }
    EXPECT_NEAR(sum, 2.0, 1e-14) << "n = " << n;
  }
}

TEST(GaussLegendre, ReturnsTheSameCachedRule) {
  EXPECT_EQ(&gauss_legendre(7), &gauss_legendre(7));
}

TEST(GaussLegendreOn, IntegratesPolynomialsOnInterval) {
  const double a = -0.7;
  const double b = 2.3;
  // p(x) = 3 - 2x + 0.5x^2 + x^5, antiderivative P(x) = 3x - x^2 + x^3/6 + x^6/6.
  auto p = [](double x) { return 3.0 - 2.0 * x + 0.5 * x * x + std::pow(x, 5); };
  auto P = [](double x) { return 3.0 * x - x * x + x * x * x / 6.0 + std::pow(x, 6) / 6.0; };
  for (int n = 3; n <= 8; ++n) {
    const GaussRule r = gauss_legendre_on(n, a, b);
    double sum = 0.0;
    for (std::size_t i = 0; i < r.points.size(); ++i) {
      EXPECT_GT(r.points[i], a);
      EXPECT_LT(r.points[i], b);
      sum += r.weights[i] * p(r.points[i]);
    }
    EXPECT_NEAR(sum, P(b) - P(a), 1e-12) << "n = " << n;
  }
}

TEST(GaussLegendreOn, WeightsSumToLengthAndReversedIntervalFlipsSign) {
  const GaussRule r = gauss_legendre_on(5, 1.0, 4.0);
  double sum = 0.0;
  for (double w : r.weights) sum += w;
  EXPECT_NEAR(sum, 3.0, 1e-14);
  const GaussRule back = gauss_legendre_on(5, 4.0, 1.0);
  double back_sum = 0.0;
  for (double w : back.weights) back_sum += w;
  EXPECT_NEAR(back_sum, -3.0, 1e-14);
}

TEST(GaussLegendre, InvalidOrderThrowsNamingN) {
  for (int n : {0, -3, 65}) {
    try {
      (void)gauss_legendre(n);
      FAIL() << "no throw for n = " << n;
    } catch (const std::invalid_argument& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("n = " + std::to_string(n)), std::string::npos) << msg;
      EXPECT_NE(msg.find("[1, 64]"), std::string::npos) << msg;
    }
  }
  EXPECT_THROW((void)gauss_legendre_on(0, 0.0, 1.0), std::invalid_argument);
  EXPECT_THROW((void)gauss_legendre_on(3, 0.0, INFINITY), std::invalid_argument);
}

}  // namespace
}  // namespace latticedyn
