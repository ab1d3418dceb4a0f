// Computes the Gauss–Legendre rules by Newton iteration on the Legendre polynomial P_n.
// Replaces the thesis's Table A-1 (which stops at n = 11 and has sign typos) by exact computation.
#include "core/quadrature.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <string>

namespace latticedyn {
namespace {

// Roots and weights are computed in long double and rounded once: a weight depends on its node
// with sensitivity ~2/(1 - x^2), so a node rounded to double before the weight is formed would
// cost about three digits of the weights near x = +-1 at n = 64. Where long double is double
// the rule is still correct, just a few ulps less accurate.
using Real = long double;

struct LegendreEval {
  Real p;   // P_n(x)
  Real dp;  // P_n'(x)
};

// Bonnet's three-term recurrence; stable for |x| <= 1 at every n we support.
LegendreEval legendre(int n, Real x) {
  Real p_prev = 1.0L;
  Real p = x;
  for (int k = 2; k <= n; ++k) {
    const Real p_next = ((2.0L * k - 1.0L) * x * p - (k - 1.0L) * p_prev) / k;
    p_prev = p;
    p = p_next;
  }
  // P_n' from P_n and P_{n-1}; singular only at x = +-1, which is never a root.
  const Real dp = n * (x * p - p_prev) / (x * x - 1.0L);
  return {p, dp};
}

GaussRule compute_rule(int n) {
  GaussRule rule;
  rule.points.assign(static_cast<std::size_t>(n), 0.0);
  rule.weights.assign(static_cast<std::size_t>(n), 0.0);
  if (n == 1) {
    rule.weights[0] = 2.0;
    return rule;
  }
  // Convergence is quadratic, so a step this small already left x at rounding level.
  const Real tol = 8 * std::numeric_limits<Real>::epsilon();
  // Only the positive roots are iterated; mirroring them makes the rule exactly symmetric and
  // puts the middle point of an odd rule exactly at 0 (P_n is odd then, so 0 is a root).
  const int half = n / 2;
  for (int i = 0; i < half; ++i) {
    // Root i (descending from the largest) is close to cos(pi (i + 3/4) / (n + 1/2)).
    Real x = std::cos(std::numbers::pi_v<Real> * (i + 0.75L) / (n + 0.5L));
    for (int iter = 0; iter < 100; ++iter) {
      const LegendreEval e = legendre(n, x);
      const Real dx = e.p / e.dp;
      x -= dx;
      if (std::abs(dx) <= tol) break;
    }
    const LegendreEval e = legendre(n, x);  // derivative at the converged root, for the weight
    const auto w = static_cast<double>(2.0L / ((1.0L - x * x) * e.dp * e.dp));
    const auto xd = static_cast<double>(x);
    const auto lo = static_cast<std::size_t>(i);
    const auto hi = static_cast<std::size_t>(n - 1 - i);
    rule.points[lo] = -xd;
    rule.points[hi] = xd;
    rule.weights[lo] = w;
    rule.weights[hi] = w;
  }
  if (n % 2 == 1) {
    const LegendreEval e = legendre(n, 0.0L);
    rule.weights[static_cast<std::size_t>(half)] = static_cast<double>(2.0L / (e.dp * e.dp));
  }
  return rule;
}

void check_order(int n) {
  if (n < kMinGaussPoints || n > kMaxGaussPoints) {
    throw std::invalid_argument("gauss_legendre: number of points n = " + std::to_string(n) +
                                " is outside the supported range [" +
                                std::to_string(kMinGaussPoints) + ", " +
                                std::to_string(kMaxGaussPoints) + "]");
  }
}

}  // namespace

const GaussRule& gauss_legendre(int n) {
  check_order(n);
  // Each rule is computed on its first use, exactly once even under concurrent first calls (all
  // 64 in long double took about 30 ms: a process's start-up, for the one or two it needs).
  static std::array<GaussRule, kMaxGaussPoints> rules;
  static std::array<std::once_flag, kMaxGaussPoints> computed;
  const auto k = static_cast<std::size_t>(n - 1);
  std::call_once(computed[k], [&] { rules[k] = compute_rule(n); });
  return rules[k];
}

GaussRule gauss_legendre_on(int n, double a, double b) {
  if (!std::isfinite(a) || !std::isfinite(b)) {
    throw std::invalid_argument("gauss_legendre_on: interval bounds must be finite, got a = " +
                                std::to_string(a) + ", b = " + std::to_string(b));
  }
  GaussRule rule = gauss_legendre(n);
  // The thesis's A-6, x = (xi + 1) / (2 (ub - lb)) + lb, divides by the interval length and
  // never scales the weights; the correct affine map multiplies by the half-length.
  const double half_length = 0.5 * (b - a);
  const double mid = 0.5 * (a + b);
  for (std::size_t i = 0; i < rule.points.size(); ++i) {
    rule.points[i] = half_length * rule.points[i] + mid;
    rule.weights[i] *= half_length;
  }
  return rule;
}

}  // namespace latticedyn
