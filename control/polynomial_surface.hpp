// Least-squares polynomial surfaces z(x, y) of two variables (thesis 6.2: the quasi-static map
// between rope lengths and the load's end point is fitted by such surfaces, orders up to 5).
#pragma once

#include <span>
#include <vector>

namespace latticedyn {

/// z = sum over i <= order_x, j <= order_y of c_ij u^i v^j, with u, v the inputs mapped
/// linearly onto [-1, 1] over the fitted data's range (the normal equations of raw powers of
/// rope lengths near 50 m would be hopelessly conditioned). Fitted by a column-pivoting QR
/// least-squares solve (Eigen).
class PolynomialSurface {
 public:
  static constexpr int kMaxOrder = 5;

  /// Fits the samples (x[k], y[k], z[k]). Throws std::invalid_argument for orders outside
  /// 0..kMaxOrder, lists of different lengths, non-finite samples, fewer samples than
  /// coefficients, or data that cannot determine them (a variable with a single value while its
  /// order is above 0).
  static PolynomialSurface fit(std::span<const double> x, std::span<const double> y, std::span<const double> z,
                               int order_x, int order_y);

  double operator()(double x, double y) const;
  /// dz/dx and dz/dy at (x, y).
  std::pair<double, double> gradient(double x, double y) const;

  int order_x() const { return order_x_; }
  int order_y() const { return order_y_; }
  /// Coefficients c_ij of the scaled variables, index i * (order_y + 1) + j.
  const std::vector<double>& coefficients() const { return c_; }
  /// Residuals over the fitted samples: root mean square and largest magnitude.
  double rms_residual() const { return rms_; }
  double max_residual() const { return max_; }

 private:
  double scale_x(double x) const { return (2.0 * x - (x_lo_ + x_hi_)) / (x_hi_ - x_lo_); }
  double scale_y(double y) const { return (2.0 * y - (y_lo_ + y_hi_)) / (y_hi_ - y_lo_); }

  int order_x_ = 0, order_y_ = 0;
  double x_lo_ = -1, x_hi_ = 1, y_lo_ = -1, y_hi_ = 1;
  std::vector<double> c_;
  double rms_ = 0.0, max_ = 0.0;
};

}  // namespace latticedyn
