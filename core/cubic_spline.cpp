// Builds the cubic spline's knot second derivatives with the Thomas algorithm and evaluates it.
// The system is symmetric and strictly diagonally dominant, so elimination needs no pivoting.
#include "core/cubic_spline.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

namespace latticedyn {
namespace {

void validate_knots(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() != y.size()) {
    throw std::invalid_argument("CubicSpline: " + std::to_string(x.size()) + " abscissae but " +
                                std::to_string(y.size()) + " values; the sizes must match");
  }
  if (x.size() < 2) {
    throw std::invalid_argument("CubicSpline: needs at least 2 points, got " +
                                std::to_string(x.size()));
  }
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i])) {
      throw std::invalid_argument("CubicSpline: point " + std::to_string(i) +
                                  " is not finite");
    }
    if (i > 0 && !(x[i] > x[i - 1])) {
      throw std::invalid_argument("CubicSpline: abscissae must be strictly increasing, but x[" +
                                  std::to_string(i) + "] <= x[" + std::to_string(i - 1) + "]");
    }
  }
}

}  // namespace

CubicSpline::CubicSpline(std::vector<double> x, std::vector<double> y, EndCondition end)
    : x_(std::move(x)), y_(std::move(y)), end_(end) {
  validate_knots(x_, y_);
  const std::size_t n = x_.size();
  // Tridiagonal system sub[i] m[i-1] + diag[i] m[i] + sup[i] m[i+1] = rhs[i] for the moments,
  // from continuity of the first derivative at the interior knots plus two end equations.
  std::vector<double> sub(n, 0.0), diag(n, 1.0), sup(n, 0.0), rhs(n, 0.0);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double h0 = x_[i] - x_[i - 1];
    const double h1 = x_[i + 1] - x_[i];
    sub[i] = h0;
    diag[i] = 2.0 * (h0 + h1);
    sup[i] = h1;
    rhs[i] = 6.0 * ((y_[i + 1] - y_[i]) / h1 - (y_[i] - y_[i - 1]) / h0);
  }
  if (end_ == EndCondition::zero_slope) {
    // S'(x_0) = 0 and S'(x_{n-1}) = 0 written in terms of the end moments.
    const double h_first = x_[1] - x_[0];
    const double h_last = x_[n - 1] - x_[n - 2];
    diag[0] = 2.0 * h_first;
    sup[0] = h_first;
    rhs[0] = 6.0 * (y_[1] - y_[0]) / h_first;
    sub[n - 1] = h_last;
    diag[n - 1] = 2.0 * h_last;
    rhs[n - 1] = -6.0 * (y_[n - 1] - y_[n - 2]) / h_last;
  }
  // natural: the defaults diag = 1, rhs = 0 in rows 0 and n-1 already say m = 0 there.

  for (std::size_t i = 1; i < n; ++i) {
    const double f = sub[i] / diag[i - 1];
    diag[i] -= f * sup[i - 1];
    rhs[i] -= f * rhs[i - 1];
  }
  m_.assign(n, 0.0);
  m_[n - 1] = rhs[n - 1] / diag[n - 1];
  for (std::size_t i = n - 1; i-- > 0;) {
    m_[i] = (rhs[i] - sup[i] * m_[i + 1]) / diag[i];
  }
}

CubicSpline::Sample CubicSpline::evaluate(double x) const {
  // Piece i covers [x_i, x_{i+1}); the end pieces also serve extrapolation.
  const auto it = std::upper_bound(x_.begin(), x_.end(), x);
  const std::size_t last_piece = x_.size() - 2;
  const std::size_t i =
      it == x_.begin() ? 0 : std::min(static_cast<std::size_t>(it - x_.begin()) - 1, last_piece);
  const double h = x_[i + 1] - x_[i];
  const double d = (m_[i + 1] - m_[i]) / (6.0 * h);
  const double dy = (y_[i + 1] - y_[i]) / h;
  // Power form about the nearer knot: the value at a knot is then y exactly, and the
  // polynomial is evaluated at |t| <= h/2, the better-conditioned half.
  double t = x - x_[i];
  double y0 = y_[i];
  double b = dy - h * (2.0 * m_[i] + m_[i + 1]) / 6.0;
  double c = 0.5 * m_[i];
  if (t > 0.5 * h) {
    t = x - x_[i + 1];
    y0 = y_[i + 1];
    b = dy + h * (m_[i] + 2.0 * m_[i + 1]) / 6.0;
    c = 0.5 * m_[i + 1];
  }
  return {y0 + t * (b + t * (c + t * d)), b + t * (2.0 * c + 3.0 * t * d), 2.0 * c + 6.0 * d * t};
}

}  // namespace latticedyn
