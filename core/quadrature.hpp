// Gauss–Legendre quadrature rules on [-1, 1] and on arbitrary intervals (thesis Appendix A.2).
// Rules are computed once to full double precision, not tabulated, so any order up to 64 is exact.
#pragma once

#include <vector>

namespace latticedyn {

/// An n-point quadrature rule: integral of f ~ sum_i weights[i] * f(points[i]) (thesis eq. A-5).
struct GaussRule {
  std::vector<double> points;   ///< abscissae, ascending when the interval is ascending
  std::vector<double> weights;  ///< weights, same length as points
};

/// Smallest and largest number of points gauss_legendre() provides.
inline constexpr int kMinGaussPoints = 1;
inline constexpr int kMaxGaussPoints = 64;

/// The n-point Gauss–Legendre rule on [-1, 1] (thesis eq. A-5, Table A-1), exact for polynomials
/// of degree up to 2n - 1. The rules are built once on first use and shared; the call is
/// thread-safe and the reference stays valid for the whole program.
/// @throws std::invalid_argument unless kMinGaussPoints <= n <= kMaxGaussPoints.
const GaussRule& gauss_legendre(int n);

/// The n-point Gauss–Legendre rule mapped affinely from [-1, 1] to [a, b] (thesis eq. A-6,
/// corrected): x = (b - a)/2 * xi + (a + b)/2, w = (b - a)/2 * w_ref. With b < a the weights are
/// negative and the points descend, consistent with integrating from a to b.
/// @throws std::invalid_argument for n out of range or a non-finite a or b.
GaussRule gauss_legendre_on(int n, double a, double b);

}  // namespace latticedyn
