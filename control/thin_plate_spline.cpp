// Thin plate spline surfaces of two variables.
#include "control/thin_plate_spline.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace latticedyn {

namespace {

double kernel(double r2) { return r2 > 0.0 ? 0.5 * r2 * std::log(r2) : 0.0; }  // r^2 log r = r^2 log(r^2) / 2
// d phi / d(r^2) = (log(r^2) + 1) / 2; phi's gradient is 2 (d phi / d r^2) times the offset.
double kernel_slope(double r2) { return r2 > 0.0 ? 0.5 * (std::log(r2) + 1.0) : 0.0; }

}  // namespace

ThinPlateSpline ThinPlateSpline::fit(std::span<const double> x, std::span<const double> y, std::span<const double> z,
                                     double smoothing) {
  if (x.size() != y.size() || x.size() != z.size())
    throw std::invalid_argument("thin plate spline: x, y and z need the same number of samples");
  const int n = static_cast<int>(x.size());
  if (n < 3) throw std::invalid_argument("thin plate spline: at least 3 samples are needed");
  if (!(smoothing >= 0.0)) throw std::invalid_argument("thin plate spline: the smoothing must be >= 0");
  for (int k = 0; k < n; ++k)
    if (!std::isfinite(x[k]) || !std::isfinite(y[k]) || !std::isfinite(z[k]))
      throw std::invalid_argument("thin plate spline: sample " + std::to_string(k) + " is not finite");
  ThinPlateSpline s;
  s.smoothing_ = smoothing;
  const auto [xl, xh] = std::minmax_element(x.begin(), x.end());
  const auto [yl, yh] = std::minmax_element(y.begin(), y.end());
  s.x_lo_ = *xl, s.x_hi_ = *xh, s.y_lo_ = *yl, s.y_hi_ = *yh;
  if (s.x_hi_ == s.x_lo_ || s.y_hi_ == s.y_lo_)
    throw std::invalid_argument("thin plate spline: the samples lie on one line (a variable takes a single value)");
  s.u_.resize(n);
  s.v_.resize(n);
  for (int k = 0; k < n; ++k) {
    s.u_[k] = s.scale_x(x[k]);
    s.v_[k] = s.scale_y(y[k]);
  }
  // [K + lambda I, P; P^T, 0] [w; a] = [z; 0], P = [1 u v].
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n + 3, n + 3);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n + 3);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < i; ++j) {
      const double du = s.u_[i] - s.u_[j], dv = s.v_[i] - s.v_[j];
      const double r2 = du * du + dv * dv;
      if (r2 < 1e-24)
        throw std::invalid_argument("thin plate spline: samples " + std::to_string(j) + " and " + std::to_string(i) +
                                    " coincide");
      A(i, j) = A(j, i) = kernel(r2);
    }
    A(i, i) = smoothing;
    A(i, n) = A(n, i) = 1.0;
    A(i, n + 1) = A(n + 1, i) = s.u_[i];
    A(i, n + 2) = A(n + 2, i) = s.v_[i];
    b(i) = z[i];
  }
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
  if (lu.rank() < n + 3) throw std::invalid_argument("thin plate spline: the samples lie on one line");
  const Eigen::VectorXd c = lu.solve(b);
  s.w_.assign(c.data(), c.data() + n);
  for (int k = 0; k < 3; ++k) s.a_[k] = c(n + k);
  double sum = 0.0;
  for (int k = 0; k < n; ++k) {
    const double r = s(x[k], y[k]) - z[k];
    sum += r * r;
    s.max_ = std::max(s.max_, std::abs(r));
  }
  s.rms_ = std::sqrt(sum / n);
  return s;
}

double ThinPlateSpline::operator()(double x, double y) const {
  const double u = scale_x(x), v = scale_y(y);
  double z = a_[0] + a_[1] * u + a_[2] * v;
  for (std::size_t k = 0; k < w_.size(); ++k) {
    const double du = u - u_[k], dv = v - v_[k];
    z += w_[k] * kernel(du * du + dv * dv);
  }
  return z;
}

std::pair<double, double> ThinPlateSpline::gradient(double x, double y) const {
  const double u = scale_x(x), v = scale_y(y);
  double gu = a_[1], gv = a_[2];
  for (std::size_t k = 0; k < w_.size(); ++k) {
    const double du = u - u_[k], dv = v - v_[k];
    const double g = 2.0 * w_[k] * kernel_slope(du * du + dv * dv);
    gu += g * du;
    gv += g * dv;
  }
  return {gu * 2.0 / (x_hi_ - x_lo_), gv * 2.0 / (y_hi_ - y_lo_)};
}

}  // namespace latticedyn
