// Least-squares polynomial surfaces of two variables.
#include "control/polynomial_surface.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace latticedyn {

namespace {

// 1, t, t^2, ..., t^order and their derivatives d/dt.
void powers(double t, int order, double* p, double* dp) {
  p[0] = 1.0;
  dp[0] = 0.0;
  for (int i = 1; i <= order; ++i) {
    p[i] = p[i - 1] * t;
    dp[i] = i * p[i - 1];
  }
}

}  // namespace

PolynomialSurface PolynomialSurface::fit(std::span<const double> x, std::span<const double> y,
                                         std::span<const double> z, int order_x, int order_y) {
  if (order_x < 0 || order_x > kMaxOrder || order_y < 0 || order_y > kMaxOrder)
    throw std::invalid_argument("polynomial surface: orders must lie in 0.." + std::to_string(kMaxOrder) + ", got " +
                                std::to_string(order_x) + " and " + std::to_string(order_y));
  if (x.size() != y.size() || x.size() != z.size())
    throw std::invalid_argument("polynomial surface: x, y and z need the same number of samples");
  const int n = static_cast<int>(x.size());
  const int terms = (order_x + 1) * (order_y + 1);
  if (n < terms)
    throw std::invalid_argument("polynomial surface: " + std::to_string(n) + " samples cannot determine " +
                                std::to_string(terms) + " coefficients");
  for (int k = 0; k < n; ++k)
    if (!std::isfinite(x[k]) || !std::isfinite(y[k]) || !std::isfinite(z[k]))
      throw std::invalid_argument("polynomial surface: sample " + std::to_string(k) + " is not finite");

  PolynomialSurface s;
  s.order_x_ = order_x;
  s.order_y_ = order_y;
  const auto [xl, xh] = std::minmax_element(x.begin(), x.end());
  const auto [yl, yh] = std::minmax_element(y.begin(), y.end());
  s.x_lo_ = *xl;
  s.x_hi_ = *xh;
  s.y_lo_ = *yl;
  s.y_hi_ = *yh;
  // A variable that does not vary: only order 0 in it is determined; keep the scaling finite.
  if (s.x_hi_ == s.x_lo_) {
    if (order_x > 0) throw std::invalid_argument("polynomial surface: x takes a single value; its order must be 0");
    s.x_lo_ -= 1.0, s.x_hi_ += 1.0;
  }
  if (s.y_hi_ == s.y_lo_) {
    if (order_y > 0) throw std::invalid_argument("polynomial surface: y takes a single value; its order must be 0");
    s.y_lo_ -= 1.0, s.y_hi_ += 1.0;
  }

  Eigen::MatrixXd A(n, terms);
  Eigen::VectorXd b(n);
  double pu[kMaxOrder + 1], pv[kMaxOrder + 1], d[kMaxOrder + 1];
  for (int k = 0; k < n; ++k) {
    powers(s.scale_x(x[k]), order_x, pu, d);
    powers(s.scale_y(y[k]), order_y, pv, d);
    for (int i = 0; i <= order_x; ++i)
      for (int j = 0; j <= order_y; ++j) A(k, i * (order_y + 1) + j) = pu[i] * pv[j];
    b(k) = z[k];
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (qr.rank() < terms)
    throw std::invalid_argument("polynomial surface: the samples do not determine all " + std::to_string(terms) +
                                " coefficients (rank " + std::to_string(qr.rank()) + "): too few distinct x or y values");
  const Eigen::VectorXd c = qr.solve(b);
  s.c_.assign(c.data(), c.data() + terms);
  const Eigen::VectorXd r = A * c - b;
  s.rms_ = std::sqrt(r.squaredNorm() / n);
  s.max_ = r.cwiseAbs().maxCoeff();
  return s;
}

double PolynomialSurface::operator()(double x, double y) const {
  double pu[kMaxOrder + 1], pv[kMaxOrder + 1], d[kMaxOrder + 1];
  powers(scale_x(x), order_x_, pu, d);
  powers(scale_y(y), order_y_, pv, d);
  double z = 0.0;
  for (int i = 0; i <= order_x_; ++i)
    for (int j = 0; j <= order_y_; ++j) z += c_[i * (order_y_ + 1) + j] * pu[i] * pv[j];
  return z;
}

std::pair<double, double> PolynomialSurface::gradient(double x, double y) const {
  double pu[kMaxOrder + 1], pv[kMaxOrder + 1], du[kMaxOrder + 1], dv[kMaxOrder + 1];
  powers(scale_x(x), order_x_, pu, du);
  powers(scale_y(y), order_y_, pv, dv);
  double gx = 0.0, gy = 0.0;
  for (int i = 0; i <= order_x_; ++i)
    for (int j = 0; j <= order_y_; ++j) {
      const double c = c_[i * (order_y_ + 1) + j];
      gx += c * du[i] * pv[j];
      gy += c * pu[i] * dv[j];
    }
  // Chain rule through the scaling u = (2x - lo - hi) / (hi - lo).
  return {gx * 2.0 / (x_hi_ - x_lo_), gy * 2.0 / (y_hi_ - y_lo_)};
}

}  // namespace latticedyn
